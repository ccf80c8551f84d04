#!/usr/bin/env bash
# Bakes every fixture (default options, --tangents regenerate --quantize u16, and with the
# fur config fixtures/fur.json) and runs the
# Khronos glTF-Validator over the outputs; exits non-zero if any output has an error.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -d tools/validator/node_modules/gltf-validator ] || npm ci --prefix tools/validator --no-audit --no-fund
cargo build -q --bin pelt
out=target/validate
rm -rf "$out" && mkdir -p "$out/default" "$out/regen-u16" "$out/fur"
inputs=(fixtures/*.glb fixtures/edge/*.gltf fixtures/edge/*.obj fixtures/obj/*.obj)
./target/debug/pelt bake -q "${inputs[@]}" -o "$out/default"
./target/debug/pelt bake -q "${inputs[@]}" -o "$out/regen-u16" --tangents regenerate --quantize u16
./target/debug/pelt bake -q "${inputs[@]}" -o "$out/fur" --config fixtures/fur.json
demo=()
# The creature and the Fox `pelt demo` baked, when CI ran it first.
for f in creature fox; do
  [ -f "target/validate-demo/$f.glb" ] && demo+=("target/validate-demo/$f.glb")
done
node tools/validator/validate.mjs "$out"/default/*.glb "$out"/regen-u16/*.glb "$out"/fur/*.glb "${demo[@]}"
