#!/usr/bin/env bash
# Bazel's own cost per bake action, side by side in one run: N bakes of the example's cube
# (each its own copy, its own target) run directly (xargs, one per core), then by Bazel with
# pelt's rules in the Linux sandbox and without a sandbox, and as remote cache hits from a
# loopback BuildGrid after a clean. Each Bazel build starts from `bazel clean` with the server
# warm; ROUNDS rounds, median wall time. Usage: bench/bazel.sh [N] [ROUNDS] (default 100 5)
# Needs: bazel (Debian bazel-bootstrap); BuildGrid's bgd on PATH or in $PELT_BGD for the
# cache row (python3 -m venv V && V/bin/pip install buildgrid==0.4.4).
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-100}
rounds=${2:-5}
cargo build --release -q -p pelt
pelt=$PWD/target/release/pelt
work=$(mktemp -d /tmp/pelt-bazel-bench.XXXXXX)
root=$work/root
trap 'bazel --output_user_root="$root" shutdown >/dev/null 2>&1 || true; [ -n "${bgd_pid:-}" ] && kill "$bgd_pid" 2>/dev/null; chmod -R u+w "$work"; rm -rf "$work"' EXIT
cp -r bazel "$work/bazel"
ws=$work/ws
mkdir -p "$ws/assets"
cat > "$ws/WORKSPACE" <<WS
local_repository(name = "pelt_rules", path = "../bazel")
load("@pelt_rules//:repositories.bzl", "pelt_binary")
pelt_binary(name = "pelt_tool", path = "$pelt")
WS
echo 'load("@pelt_rules//:defs.bzl", "pelt_bake")' > "$ws/BUILD.bazel"
for i in $(seq "$n"); do
  sed "s/cube.bin/c$i.bin/" examples/bazel/assets/cube.gltf > "$ws/assets/c$i.gltf"
  cp examples/bazel/assets/cube.bin "$ws/assets/c$i.bin"
  printf 'pelt_bake(name = "c%s", src = "assets/c%s.gltf", srcs = ["assets/c%s.bin"])\n' \
    "$i" "$i" "$i" >> "$ws/BUILD.bazel"
done
cd "$ws"
bz() { bazel --output_user_root="$root" --max_idle_secs=600 "$@" 2>/dev/null; }
ms() { python3 -c "import sys,time; print(round((time.time()-float(sys.argv[1]))*1000))" "$1"; }
bz build //... >/dev/null  # warm the server and fetch pelt_tool
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
bgd=${PELT_BGD:-$(command -v bgd || true)}
if [ -n "$bgd" ]; then
  sed "s/127.0.0.1:50051/127.0.0.1:$port/" "$OLDPWD/examples/bazel/buildgrid-cache.yml" > "$work/cache.yml"
  "$bgd" server start "$work/cache.yml" >"$work/bgd.log" 2>&1 &
  bgd_pid=$!
  until python3 -c "import socket,sys; socket.create_connection(('127.0.0.1',$port),1)" 2>/dev/null; do sleep 0.2; done
  bz build //... --remote_cache=grpc://127.0.0.1:$port >/dev/null
fi
declare -A t
for r in $(seq "$rounds"); do
  rm -rf "$work/direct"; mkdir -p "$work/direct"
  s=$(python3 -c 'import time; print(time.time())')
  seq "$n" | xargs -P "$(nproc)" -I{} "$pelt" bake -q "assets/c{}.gltf" -o "$work/direct/c{}.glb"
  t[direct]+="$(ms "$s") "
  for mode in linux-sandbox local; do
    bz clean
    s=$(python3 -c 'import time; print(time.time())')
    bz build //... --spawn_strategy=$mode >/dev/null
    t[$mode]+="$(ms "$s") "
  done
  if [ -n "$bgd" ]; then
    bz clean
    s=$(python3 -c 'import time; print(time.time())')
    bz build //... --spawn_strategy=linux-sandbox --remote_cache=grpc://127.0.0.1:$port >/dev/null
    t[cache]+="$(ms "$s") "
  fi
done
med() { tr ' ' '\n' | grep . | sort -n | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
d=$(echo "${t[direct]}" | med)
echo "$n bakes of a 24-vertex cube, $(nproc) cores, median of $rounds rounds:"
printf '%-34s %8s %14s\n' "" "wall ms" "ms per bake"
printf '%-34s %8s %14s\n' "pelt bake, xargs -P $(nproc)" "$d" "$(python3 -c "print(round($d/$n,1))")"
for k in linux-sandbox local cache; do
  [ -n "${t[$k]:-}" ] || continue
  m=$(echo "${t[$k]}" | med)
  label="bazel build, $k"
  [ "$k" = cache ] && label="bazel build, all remote cache hits"
  printf '%-34s %8s %14s\n' "$label" "$m" "$(python3 -c "print(round($m/$n,1))")"
done
