#!/bin/sh
# pelt_bake's action: runs `pelt bake` with a depfile, then lists the declared inputs the bake
# did not read (Bazel's unused_inputs_list), so that changing one of them re-runs nothing.
#   bake.sh PELT OUTPUT DEPFILE UNUSED DECLARED [pelt bake arguments...]
# DECLARED holds the action's declared inputs, one execution-root path per line.
set -eu
pelt=$1 out=$2 dep=$3 unused=$4 declared=$5
shift 5
"$pelt" bake -q "$@" -o "$out" --depfile "$dep"
# The depfile is "OUTPUT: \" then one input per line; Bazel paths hold no spaces.
read_list="$unused.read"
tail -n +2 "$dep" | sed -e 's/^ *//' -e 's/ *\\$//' > "$read_list"
grep -vxF -f "$read_list" "$declared" > "$unused" || true
rm -f "$read_list"
