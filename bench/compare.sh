#!/usr/bin/env bash
# pelt's bake side by side with gltfpack -kv and glTF-Transform, in one run, on the fixture
# generator's two ~1.3 M-triangle creatures (`gen-fixtures bench-out --big`):
#   creature-1m3.glb        tangents present, one bufferView per attribute (Blender's layout)
#   creature-1m3-notan.glb  no tangents, interleaved in one bufferView (gltfpack's layout)
# Tangent generation is compared like for like: MikkTSpace (--tangent-generator mikktspace)
# against gltf-transform tangents, which makes MikkTSpace; the default bake (the gradient frame
# where no normal map needs MikkTSpace) against gltfpack -kv, which makes none.
# Every round runs each command once, in turn (bench/measure.py), so a slow spell of this
# shared machine falls on all tools alike; p10/p50/p90 of the wall time and peak RSS (wait4).
# gltf-transform's tangent runs take about a minute each: they are timed in the first 2 rounds.
# Outputs go to a tmpfs (/dev/shm/pelt-bench) when there is one, for every tool alike: on this
# 2-core VM, writes to ext4 add sporadic stalls of 0.1-0.2 s (in one 20-round run pelt's p90/p50
# was 1.54 writing to disk against 1.09 to tmpfs in the same rounds). `--disk` writes them to
# bench-out/ instead.
# Usage: bench/compare.sh [ROUNDS] [--disk]   (default 20 rounds)
# Needs: cargo, node/npm (installs bench/node_modules), python3.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=20 disk=0
for a in "$@"; do
  case $a in
    --disk) disk=1 ;;
    *) rounds=$a ;;
  esac
done
out=bench-out
mkdir -p "$out"
dst=$out
if [ "$disk" = 0 ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then
  dst=/dev/shm/pelt-bench
  mkdir -p "$dst"
fi
[ -d bench/node_modules ] || npm ci --prefix bench --no-audit --no-fund >/dev/null
cargo build --release -q -p pelt -p pelt-fixtures
if [ ! -f "$out/creature-1m3.glb" ] || [ ! -f "$out/creature-1m3-notan.glb" ]; then
  ./target/release/gen-fixtures "$out" --big
fi
tan=$out/creature-1m3.glb
notan=$out/creature-1m3-notan.glb
pelt=./target/release/pelt
bin=bench/node_modules/.bin
spec=$out/compare.tsv
tab=$'\t'
cat > "$spec" <<SPEC
cp (tangents)${tab}cp $tan $dst/cp.glb
pelt bake (tangents kept; groups and fins)${tab}$pelt bake -q $tan -o $dst/pelt.glb
gltfpack -kv (tangents)${tab}$bin/gltfpack -kv -i $tan -o $dst/gltfpack.glb
pelt bake --topology off (tangents kept)${tab}$pelt bake -q $tan -o $dst/pelt-off.glb --topology off
pelt bake (no tangents: gradient frame, the default)${tab}$pelt bake -q $notan -o $dst/pelt-gen.glb
gltfpack -kv (no tangents)${tab}$bin/gltfpack -kv -i $notan -o $dst/gltfpack-notan.glb
pelt bake --tangent-generator mikktspace (no tangents)${tab}$pelt bake -q $notan -o $dst/pelt-mikk.glb --tangent-generator mikktspace
pelt bake --tangents regenerate --tangent-generator mikktspace${tab}$pelt bake -q $tan -o $dst/pelt-regen.glb --tangents regenerate --tangent-generator mikktspace
gltf-transform tangents --overwrite${tab}2${tab}$bin/gltf-transform tangents $tan $dst/gt-regen.glb --overwrite
gltf-transform tangents (no tangents)${tab}2${tab}$bin/gltf-transform tangents $notan $dst/gt-gen.glb
SPEC
echo "$(du -m "$tan" | cut -f1) MB with tangents, $(du -m "$notan" | cut -f1) MB without; outputs in $dst;" \
  "$(nproc) cores; gltfpack $(node -p "require('./bench/node_modules/gltfpack/package.json').version")," \
  "glTF-Transform $(node -p "require('./bench/node_modules/@gltf-transform/cli/package.json').version")"
echo
python3 bench/measure.py "$rounds" "$spec" \
  --vs "gltfpack -kv (tangents)" "pelt bake (tangents kept; groups and fins)" \
  --vs "gltfpack -kv (no tangents)" "pelt bake (no tangents: gradient frame, the default)" \
  --vs "gltf-transform tangents --overwrite" "pelt bake --tangents regenerate --tangent-generator mikktspace" \
  --vs "gltf-transform tangents (no tangents)" "pelt bake --tangent-generator mikktspace (no tangents)" \
  --vs "gltfpack -kv (no tangents)" "pelt bake --tangent-generator mikktspace (no tangents)"
