#!/usr/bin/env bash
# Batch-bake benchmark: 64 painted creatures (16 384 triangles each, 400 KB) in 8 folders.
# Times (median of RUNS) one `pelt bake` over the tree at --jobs 1 and 2, the same tree again
# with --incremental when everything is up to date, one changed file with --incremental, and,
# for comparison, one pelt process per file (how a naive build rule calls it).
# Usage: bench/batch.sh [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-5}"
cargo build --release -q
pelt=target/release/pelt
work=target/bench-batch
rm -rf "$work"
for d in 0 1 2 3 4 5 6 7; do
  mkdir -p "$work/in/set$d"
  for i in 0 1 2 3 4 5 6 7; do cp fixtures/creature.glb "$work/in/set$d/c$i.glb"; done
done

now() { date +%s.%N; }
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_it() { # label, command...
  local label="$1"; shift
  local t=()
  for _ in $(seq "$runs"); do
    local s e
    s=$(now); "$@" > /dev/null 2>&1; e=$(now)
    t+=("$(awk "BEGIN { print $e - $s }")")
  done
  printf '%-44s %8.3f s\n' "$label" "$(printf '%s\n' "${t[@]}" | median)"
}

fresh() { rm -rf "$work/out"; "$pelt" bake "$work/in" -o "$work/out" -q "$@"; }
time_it "64 files, one process, --jobs 1" fresh --jobs 1
time_it "64 files, one process, --jobs 2" fresh --jobs 2
fresh --incremental
time_it "64 files, --incremental, all up to date" "$pelt" bake "$work/in" -o "$work/out" -q --incremental
flip=0
change_one() { # each run finds one input changed (it alternates between two meshes)
  flip=$((1 - flip))
  if [ "$flip" = 1 ]; then cp fixtures/torus.glb "$work/in/set3/c5.glb"; else cp fixtures/creature.glb "$work/in/set3/c5.glb"; fi
  "$pelt" bake "$work/in" -o "$work/out" -q --incremental
}
time_it "64 files, --incremental, 1 changed" change_one
per_file() { rm -rf "$work/out1"; for f in "$work"/in/set*/c*.glb; do "$pelt" bake "$f" -o "$work/out1/$(basename "$(dirname "$f")")-$(basename "$f")" -q --jobs 1; done; }
time_it "64 processes, one per file, --jobs 1" per_file
