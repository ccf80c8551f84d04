#!/usr/bin/env python3
"""Per-triangle cost of the default bake from 10 k to 1.3 M triangles: the fixture creature
(tangents present, Blender's layout) at five sizes.

Two ways, each run RUNS times, round by round (every command once per round, in turn, each
timed run right after a discarded run of the same command):
- one file per process: `pelt bake FILE` once per size. Prints the median wall time and the
  median in-process time (the report's read + decode + bake + encode + write, without process
  start and exit), per triangle and relative to 1.3 M; then the in-process time of the same
  bake with `--jobs 1` and the speedup two threads give over one.
- batch: a folder of copies of the same file, as many as make about 1.3 M triangles in all
  (130 at 10 k, 1 at 1.3 M), baked by one `pelt bake FOLDER -o OUT`. Prints the median wall
  time per triangle relative to the single 1.3 M file: what a pipeline baking a folder of
  small assets pays per triangle, process start included once.

Outputs go to a tmpfs (/dev/shm) when there is one, as in bench/compare.sh.
Usage: bench/scaling.py [RUNS]   (default 15; run from the repository root after
`cargo build --release -p pelt -p pelt-fixtures`)
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

SIZES = [(50, 100), (112, 224), (158, 316), (316, 632), (570, 1140)]
SRC = "bench-out/scaling"
PELT = "./target/release/pelt"


def name(rings, segs):
    return "creature-1m3" if (rings, segs) == (570, 1140) else f"creature-{2 * rings * segs}"


def out_root():
    shm = "/dev/shm"
    base = shm if os.path.isdir(shm) and os.access(shm, os.W_OK) else SRC
    return os.path.join(base, "pelt-scaling")


def make_inputs():
    os.makedirs(SRC, exist_ok=True)
    args = ["./target/release/gen-fixtures", SRC]
    for r, s in SIZES:
        if not os.path.exists(f"{SRC}/{name(r, s)}.glb"):
            args += ["--creature", f"{r}x{s}"]
    if len(args) > 2:
        subprocess.run(args, check=True)


def triangles(path):
    p = subprocess.run([PELT, "inspect", path, "--json"], check=True, capture_output=True)
    return json.loads(p.stdout)["triangles"]


def batch_folder(n, tris, total):
    """A folder of hard links to `n`, about `total` triangles in all; returns (folder, copies)."""
    copies = max(1, round(total / tris))
    folder = f"{SRC}/batch-{n}"
    if os.path.isdir(folder) and len(os.listdir(folder)) != copies:
        shutil.rmtree(folder)
    if not os.path.isdir(folder):
        os.makedirs(folder)
        for k in range(copies):
            os.link(f"{SRC}/{n}.glb", f"{folder}/copy-{k:03}.glb")
    return folder, copies


def timed(cmd):
    t = time.perf_counter()
    p = subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t, p.stdout


def single_run(n, out, extra):
    """One `pelt bake` of size `n`: (wall seconds, in-process seconds from its report)."""
    wall, stdout = timed([PELT, "bake", "-q", f"{SRC}/{n}.glb", "-o", f"{out}/single/{n}.glb",
                          "--report", "-"] + extra)
    rep = json.loads(stdout)["inputs"][0]
    tm = rep["timings"]
    inproc = (rep["read_ms"] + tm["decode_ms"] + tm["bake_ms"] + tm["encode_ms"]
              + rep["write_ms"]) / 1000
    return wall, inproc


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    make_inputs()
    names = [name(r, s) for r, s in SIZES]
    tris = {n: triangles(f"{SRC}/{n}.glb") for n in names}
    big = names[-1]
    folders = {n: batch_folder(n, tris[n], tris[big]) for n in names}
    out = out_root()
    single = {n: ([], [], []) for n in names}
    batch = {n: [] for n in names}
    for _ in range(runs):
        for n in names:
            os.makedirs(f"{out}/single", exist_ok=True)
            # A discarded run first (hyperfine's --warmup): the timed run then follows a run
            # of its own size, not the previous command's release of 300 MB.
            single_run(n, out, [])
            wall, inproc = single_run(n, out, [])
            single[n][0].append(wall)
            single[n][1].append(inproc)
            single[n][2].append(single_run(n, out, ["--jobs", "1"])[1])
        for n in names:
            timed([PELT, "bake", "-q", folders[n][0], "-o", f"{out}/batch-{n}"])
            wall, _ = timed([PELT, "bake", "-q", folders[n][0], "-o", f"{out}/batch-{n}"])
            batch[n].append(wall)
    shutil.rmtree(out, ignore_errors=True)
    ref_in = statistics.median(single[big][1]) / tris[big]
    ref_batch = statistics.median(batch[big]) / tris[big]
    print(f"| triangles | one file: wall (p50 of {runs}) | in-process (p50) | in-process per "
          "triangle | relative to 1.3 M | `--jobs 1` in-process (p50) | 2 threads' speedup "
          "| batch: files | wall (p50) | wall per triangle | relative to 1.3 M |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in names:
        w, i = statistics.median(single[n][0]), statistics.median(single[n][1])
        one = statistics.median(single[n][2])
        per = i / tris[n]
        copies = folders[n][1]
        b = statistics.median(batch[n])
        bper = b / (copies * tris[n])
        print(f"| {tris[n]:,} | {w * 1000:.1f} ms | {i * 1000:.1f} ms | {per * 1e9:.0f} ns "
              f"| {per / ref_in:.2f} | {one * 1000:.1f} ms | {one / i:.2f}× "
              f"| {copies} | {b * 1000:.0f} ms | {bper * 1e9:.0f} ns "
              f"| {bper / ref_batch:.2f} |".replace(",", " "))


if __name__ == "__main__":
    main()
