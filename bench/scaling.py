#!/usr/bin/env python3
"""Per-triangle cost of the default bake from 10 k to 1.3 M triangles: the fixture creature
(tangents present, Blender's layout) at five sizes, each baked RUNS times in turn. Prints the
median wall time, the median in-process time (the report's read + decode + bake + encode +
write, without process start and exit) and both per triangle, relative to 1.3 M.

Usage: bench/scaling.py [RUNS]   (default 15; run from the repository root after
`cargo build --release -p pelt -p pelt-fixtures`)
"""
import json
import os
import statistics
import subprocess
import sys
import time

SIZES = [(50, 100), (112, 224), (158, 316), (316, 632), (570, 1140)]
OUT = "bench-out/scaling"


def name(rings, segs):
    return "creature-1m3" if (rings, segs) == (570, 1140) else f"creature-{2 * rings * segs}"


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    os.makedirs(OUT, exist_ok=True)
    args = ["./target/release/gen-fixtures", OUT]
    for r, s in SIZES:
        if not os.path.exists(f"{OUT}/{name(r, s)}.glb"):
            args += ["--creature", f"{r}x{s}"]
    if len(args) > 2:
        subprocess.run(args, check=True)
    results = {n: ([], []) for n in (name(r, s) for r, s in SIZES)}
    tris = {}
    for _ in range(runs):
        for n in results:
            t = time.perf_counter()
            p = subprocess.run(["./target/release/pelt", "bake", "-q", f"{OUT}/{n}.glb",
                                "-o", f"{OUT}/{n}.out.glb", "--report", "-"],
                               check=True, capture_output=True)
            wall = time.perf_counter() - t
            rep = json.loads(p.stdout)["inputs"][0]
            tm = rep["timings"]
            inproc = (rep["read_ms"] + tm["decode_ms"] + tm["bake_ms"] + tm["encode_ms"]
                      + rep["write_ms"]) / 1000
            tris[n] = rep["triangles"]
            results[n][0].append(wall)
            results[n][1].append(inproc)
    big = name(*SIZES[-1])
    ref = statistics.median(results[big][1]) / tris[big]
    print(f"| triangles | wall (p50 of {runs}) | in-process (p50) | in-process per triangle "
          "| relative to 1.3 M | wall per triangle |")
    print("|---|---|---|---|---|---|")
    for n, (walls, inp) in results.items():
        w, i = statistics.median(walls), statistics.median(inp)
        per = i / tris[n]
        print(f"| {tris[n]:,} | {w * 1000:.1f} ms | {i * 1000:.1f} ms | {per * 1e9:.0f} ns "
              f"| {per / ref:.2f} | {w / tris[n] * 1e9:.0f} ns |".replace(",", " "))


if __name__ == "__main__":
    main()
