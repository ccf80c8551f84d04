#!/usr/bin/env bash
# What survives of a baked asset through glTF tools: for each tool and command, the forward
# render's FLIP against the original's, the contract `pelt inspect` reports, whether pelt
# warned, and the Khronos validator's error count. Prints one Markdown table row per run
# (docs/pipelines.md records the output).
#
#   tools/pipeline-survival.sh BAKED.glb [OUT_DIR]
#
# Needs `cargo build --release` (pelt) and `cargo build --release -p pelt-measure --example
# flip_pngs`, `npm ci --prefix integrations/gltf-transform` (glTF-Transform and gltfpack) and
# `npm ci --prefix tools/validator`; Blender's row runs where `blender` is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
in=$(realpath "$1")
out=${2:-target/pipeline-survival}
mkdir -p "$out"
out=$(realpath "$out")
bin=integrations/gltf-transform/node_modules/.bin
config=integrations/gltf-transform/pelt.config.mjs
pelt=target/release/pelt
flip=target/release/examples/flip_pngs

# The contract as inspect reports it (tools/pipeline-contract.py): comb, groups, fins (with
# their count), manifest, TANGENT.
contract() {
  "$pelt" inspect "$1" --json | python3 tools/pipeline-contract.py
}

render() {
  "$pelt" render "$1" -o "$2" --mode forward --size 320x180 2>"$2.log"
}

errors() {
  node tools/validator/validate.mjs "$1" | sed -n 's/.*: \([0-9]*\) errors.*/\1/p'
}

render "$in" "$out/original.png"
echo "| tool | command | FLIP | contract after | pelt warns | validator errors |"
echo "|---|---|---|---|---|---|"
echo "| (pelt bake) | | 0 | $(contract "$in") | no | $(errors "$in") |"

row() {
  local tool=$1 command=$2 file=$3
  render "$file" "$out/$(basename "$file" .glb).png"
  local f warns
  f=$("$flip" "$out/original.png" "$out/$(basename "$file" .glb).png" | tail -1)
  warns=$(grep -c "warning" "$out/$(basename "$file" .glb).png.log" || true)
  echo "| $tool | $command | $f | $(contract "$file") | $([ "$warns" -gt 0 ] && echo yes || echo no) | $(errors "$file") |"
}

for c in copy prune dedup weld reorder quantize meshopt optimize; do
  "$bin/gltf-transform" "$c" "$in" "$out/gt-$c.glb" --config "$config" >/dev/null 2>&1
  row "glTF-Transform 4.5.1 + config" "$c" "$out/gt-$c.glb"
done
for c in copy optimize; do
  "$bin/gltf-transform" "$c" "$in" "$out/plain-$c.glb" >/dev/null 2>&1
  row "glTF-Transform 4.5.1, no config" "$c" "$out/plain-$c.glb"
done
"$bin/gltfpack" -i "$in" -o "$out/gltfpack-kv.glb" -kv >/dev/null 2>&1
row "gltfpack 1.3.0" "-kv" "$out/gltfpack-kv.glb"
"$bin/gltfpack" -i "$in" -o "$out/gltfpack.glb" >/dev/null 2>&1
row "gltfpack 1.3.0" "(defaults)" "$out/gltfpack.glb"
if command -v blender >/dev/null 2>&1; then
  script=$out/blender-round-trip.py
  cat >"$script" <<'EOF'
import sys
import numpy as np
if not hasattr(np, "bool"):
    np.bool = np.bool_  # Blender 3.4's exporter with NumPy >= 1.24
import bpy
a = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=a[0])
bpy.ops.export_scene.gltf(filepath=a[1], export_format="GLB")
EOF
  blender -b --factory-startup --python "$script" -- "$in" "$out/blender.glb" >/dev/null 2>&1
  row "Blender $(blender --version 2>/dev/null | sed -n '1s/Blender //p')" "import, export" "$out/blender.glb"
fi
