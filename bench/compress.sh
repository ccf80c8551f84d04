#!/usr/bin/env bash
# Compressed output side by side, in one run, on the fixture generator's 1.3 M-triangle sphere
# (`gen-fixtures bench-out --big`: creature-1m3.glb): `pelt bake --compress` (groups, fins,
# comb, tangents; EXT_meshopt_compression) against `gltfpack -kv -cc` (which carries no fins
# or groups), with the plain bake and `gltfpack -kv` for reference. Interleaved rounds
# (bench/measure.py: p10/p50/p90 wall time, peak RSS), then each output's size.
# Usage: bench/compress.sh [ROUNDS]   (default 10)
# Needs: cargo, node/npm (installs bench/node_modules), python3.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-10}
out=bench-out
mkdir -p "$out"
dst=$out
if [ -d /dev/shm ] && [ -w /dev/shm ]; then
  dst=/dev/shm/pelt-bench
  mkdir -p "$dst"
fi
[ -d bench/node_modules ] || npm ci --prefix bench --no-audit --no-fund >/dev/null
cargo build --release -q -p pelt -p pelt-fixtures
[ -f "$out/creature-1m3.glb" ] || ./target/release/gen-fixtures "$out" --big
src=$out/creature-1m3.glb
pelt=./target/release/pelt
bin=bench/node_modules/.bin
spec=$out/compress.tsv
tab=$'\t'
cat > "$spec" <<SPEC
pelt bake${tab}$pelt bake -q $src -o $dst/pelt.glb
pelt bake --compress${tab}$pelt bake -q $src -o $dst/pelt-cc.glb --compress
gltfpack -kv${tab}$bin/gltfpack -kv -i $src -o $dst/gp.glb
gltfpack -kv -cc${tab}$bin/gltfpack -kv -cc -i $src -o $dst/gp-cc.glb
SPEC
echo "$(du -m "$src" | cut -f1) MB in; outputs in $dst; $(nproc) cores;" \
  "gltfpack $(node -p "require('./bench/node_modules/gltfpack/package.json').version")"
echo
python3 bench/measure.py "$rounds" "$spec" \
  --vs "gltfpack -kv -cc" "pelt bake --compress" \
  --vs "gltfpack -kv" "pelt bake"
echo
for f in pelt pelt-cc gp gp-cc; do
  printf '%-10s %12d bytes\n' "$f.glb" "$(stat -c %s "$dst/$f.glb")"
done
