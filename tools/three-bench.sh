#!/usr/bin/env bash
# Frame times of the three.js runtime (headless Chromium, WebGL2 on SwiftShader here) beside
# pelt's forward mode (lavapipe), on the demo's scenes, and the shells-by-screen-size rule's
# time and error against a fixed 16 shells at three camera distances (error: FLIP against 128
# forward shells, the converged shell model, drawn by pelt). Needs `pelt demo` run in
# OUT_DEMO, a release build with the FLIP example, chromium and `npm ci --prefix
# integrations/three`:
#   cargo build --release && cargo build --release --example flip_pngs -p pelt-measure
#   bash tools/three-bench.sh out/demo 640x360 20
set -euo pipefail
demo=${1:-out/demo}
size=${2:-640x360}
frames=${3:-20}
root=$(cd "$(dirname "$0")/.." && pwd)
pelt="$root/target/release/pelt"
flip="$root/target/release/examples/flip_pngs"
render="node $root/integrations/three/render.mjs"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$demo"
python3 - <<'PY'
import json
f = json.load(open('fox.json'))
for o in f['objects']:
    o.get('material', {}).pop('spring', None)
json.dump(f, open('.bench-fox.json', 'w'))
s = json.load(open('scene.json'))
t, p = s['camera']['target'], s['camera']['position']
for k in (0.5, 1.0, 2.0):
    c = json.loads(json.dumps(s))
    c['camera']['position'] = [t[i] + (p[i] - t[i]) * k for i in range(3)]
    c['camera']['near'] = s['camera']['near'] * k
    json.dump(c, open(f'.bench-d{k}.json', 'w'))
PY
pelt_ms() { "$pelt" render "$@" --mode forward --backend vulkan --size "$size" --bench "$frames" --json -q | python3 -c 'import json,sys; t=sorted(f["ms"] for f in json.load(sys.stdin)["frames"][1:]); print(f"{t[len(t)//2]:.1f}")'; }
three_ms() { $render "$@" --size "$size" --bench "$frames" | python3 -c 'import json,sys; print("%.1f" % json.load(sys.stdin)["medianMs"])'; }
echo "| scene ($size, 16 shells) | pelt forward, lavapipe (ms) | three.js, Chromium on SwiftShader (ms) |"
echo "|---|---|---|"
echo "| creature (scene.json) | $(pelt_ms scene.json --shells 16) | $(three_ms scene.json --shells 16) |"
echo "| Fox, Walk 0.35 s (fox.json, no springs) | $(pelt_ms .bench-fox.json --shells 16 --animation Walk --time 0.35) | $(three_ms .bench-fox.json --shells 16 --animation Walk --time 0.35) |"
echo
echo "| camera distance | shells by size | rule: three ms | 16: three ms | rule: pelt ms | 16: pelt ms | rule FLIP | 16 FLIP |"
echo "|---|---|---|---|---|---|---|---|"
for k in 0.5 1.0 2.0; do
  s=.bench-d$k.json
  n=$($render $s -o "$work/r.png" --size "$size" --report | python3 -c 'import json,sys; print(json.load(sys.stdin)["fur"][0]["shells"])')
  "$pelt" render $s --mode forward --size "$size" --shells 128 -o "$work/ref.png" -q
  "$pelt" render $s --mode forward --size "$size" -o "$work/rule.png" -q
  "$pelt" render $s --mode forward --size "$size" --shells 16 -o "$work/16.png" -q
  echo "| ×$k | $n | $(three_ms $s) | $(three_ms $s --shells 16) | $(pelt_ms $s) | $(pelt_ms $s --shells 16) | $("$flip" "$work/rule.png" "$work/ref.png") | $("$flip" "$work/16.png" "$work/ref.png") |"
done
rm -f .bench-fox.json .bench-d*.json
