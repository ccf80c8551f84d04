#!/usr/bin/env bash
# Runs the Khronos glTF-Validator on every .glb that a test run wrote: run the tests with
# PELT_WRITTEN_LOG=<file> (pelt-io's writer appends each output's path there), then
#   bash tools/validate-written.sh <file>
# Fails when any output has an error, or when the log is missing or empty (nothing checked).
set -euo pipefail
cd "$(dirname "$0")/.."
log=${1:?usage: validate-written.sh LOGFILE}
[ -d tools/validator/node_modules/gltf-validator ] || npm ci --prefix tools/validator --no-audit --no-fund
if [ ! -s "$log" ]; then
  echo "validate-written: $log lists no outputs: were the tests run with PELT_WRITTEN_LOG?" >&2
  exit 1
fi
sorted=$(mktemp)
trap 'rm -f "$sorted"' EXIT
sort -u "$log" > "$sorted"
echo "validate-written: $(wc -l < "$sorted") outputs logged"
node tools/validator/validate.mjs --errors-only --list "$sorted"
