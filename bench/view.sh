#!/usr/bin/env bash
# pelt view's frame budget: a scripted orbit of the demo creature at 1280x720 under Xvfb, at
# budgets of 66, 100 and 200 ms and without one, on each back end. Prints, per run, the
# median time of the moving frames (after the first two: the first frame carries pipelines,
# the second the budget's cost measurement), the quality the budget chose, and the still
# full-quality frame at the end.
# Usage: bash bench/view.sh [FRAMES]   (needs xvfb-run; uses target/release/pelt)
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-30}
pelt=target/release/pelt
[ -x "$pelt" ] || cargo build --release
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$pelt" demo -o "$dir" --size 320x180 --frames 1 -q
for backend in vulkan gl; do
  for budget in 66 100 200 100000; do
    log="$dir/$backend-$budget.log"
    xvfb-run -a -s "-screen 0 1280x720x24" "$pelt" view "$dir/creature.glb" --size 1280x720 \
      --backend "$backend" --frames "$frames" --orbit 3 --budget-ms "$budget" 2>"$log" >/dev/null
    python3 - "$log" "$backend" "$budget" <<'PY'
import re, statistics, sys
log, backend, budget = sys.argv[1:]
rows = [l for l in open(log) if l.startswith("frame ")]
ms = [float(re.match(r"frame \d+: ([\d.]+) ms", l).group(1)) for l in rows]
moving = ms[2:-1]
q = re.search(r"\(moving: ([^)]*)\)", rows[-2])
label = "none (full quality)" if budget == "100000" else f"{budget} ms"
print(f"| {backend} | {label} | {statistics.median(moving):.0f} ms | {q.group(1).split('; budget')[0] if q else 'full quality'} | {ms[-1]:.0f} ms |")
PY
  done
done
