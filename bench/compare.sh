#!/usr/bin/env bash
# Full bake of the ~1.3 M-triangle creature, side by side with gltfpack -kv and glTF-Transform.
# Wall time (median of N runs) and peak memory (max RSS, GNU time). Usage: bench/compare.sh [N]
# Needs: cargo, node/npm (installs bench/node_modules), GNU time (/usr/bin/time).
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
out=bench-out
mkdir -p "$out"
[ -d bench/node_modules ] || npm ci --prefix bench --no-audit --no-fund >/dev/null
cargo build --release -q -p pelt -p pelt-fixtures
[ -f "$out/creature-1m3.glb" ] || ./target/release/gen-fixtures "$out" --big
in="$out/creature-1m3.glb"
# The same mesh without TANGENT, for the generate-tangents comparison.
[ -f "$out/creature-1m3-notan.glb" ] || node bench/strip-tangents.mjs "$in" "$out/creature-1m3-notan.glb"
bin=bench/node_modules/.bin

measure() { # label, command...
  local label=$1; shift
  local times=() peak=0
  for _ in $(seq "$runs"); do
    /usr/bin/time -f '%e %M' -o "$out/time.txt" "$@" >/dev/null 2>"$out/stderr.txt" || { cat "$out/stderr.txt"; exit 1; }
    read -r t m < "$out/time.txt"
    times+=("$t"); [ "$m" -gt "$peak" ] && peak=$m
  done
  local med
  med=$(printf '%s\n' "${times[@]}" | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  printf '| %-52s | %6.2f s | %5d MiB |\n' "$label" "$med" $((peak / 1024))
}

echo "| command (1.3 M triangles, $(du -m "$in" | cut -f1) MB .glb, median of $runs) | wall | peak RSS |"
echo "|---|---|---|"
measure "cp" cp "$in" "$out/cp.glb"
measure "pelt bake (TANGENT kept; groups and fins)" ./target/release/pelt bake -q "$in" -o "$out/pelt.glb"
measure "pelt bake --topology groups (TANGENT kept)" ./target/release/pelt bake -q "$in" -o "$out/pelt-groups.glb" --topology groups
measure "pelt bake --topology off (TANGENT kept)" ./target/release/pelt bake -q "$in" -o "$out/pelt-off.glb" --topology off
measure "gltfpack -kv" "$bin/gltfpack" -kv -i "$in" -o "$out/gltfpack.glb"
measure "gltf-transform copy" "$bin/gltf-transform" copy "$in" "$out/gt-copy.glb"
measure "pelt bake (no TANGENT: MikkTSpace generated)" ./target/release/pelt bake -q "$out/creature-1m3-notan.glb" -o "$out/pelt-gen.glb"
measure "pelt bake --tangents regenerate" ./target/release/pelt bake -q "$in" -o "$out/pelt-regen.glb" --tangents regenerate
measure "gltf-transform tangents" "$bin/gltf-transform" tangents "$out/creature-1m3-notan.glb" "$out/gt-tangents.glb"
