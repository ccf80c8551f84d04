#!/usr/bin/env python3
"""Runs a command N times (after one warm-up run) and prints its wall-time percentiles and peak
memory as one Markdown table row: label | p10 | p50 | p90 | p90/p50 | peak RSS.

Usage: measure.py N LABEL -- COMMAND...   (wall time per run from perf_counter around
fork/exec/wait; peak RSS is the largest ru_maxrss of the runs, from wait4).
"""
import os
import sys
import time


def run_once(cmd):
    # posix_spawn (vfork-like): little start-up cost of its own, unlike fork() of Python.
    err_path = "/tmp/pelt-measure-stderr.txt"
    actions = [
        (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
        (os.POSIX_SPAWN_OPEN, 2, err_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644),
    ]
    t = time.perf_counter()
    pid = os.posix_spawnp(cmd[0], cmd, os.environ, file_actions=actions)
    _, status, usage = os.wait4(pid, 0)
    wall = time.perf_counter() - t
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        with open(err_path, errors="replace") as f:
            sys.exit(f"{' '.join(cmd)} failed ({code}):\n{f.read()}")
    return wall, usage.ru_maxrss  # KiB on Linux


def percentile(sorted_values, q):
    # Nearest rank: the smallest value with at least q of the runs at or below it.
    k = max(0, min(len(sorted_values) - 1, int(-(-q * len(sorted_values) // 1)) - 1))
    return sorted_values[k]


def main():
    n, label = int(sys.argv[1]), sys.argv[2]
    cmd = sys.argv[sys.argv.index("--") + 1:]
    run_once(cmd)  # warm-up: page cache, output file present as in a rebuild
    walls, peak = [], 0
    for _ in range(n):
        w, rss = run_once(cmd)
        walls.append(w)
        peak = max(peak, rss)
    walls.sort()
    p10, p50, p90 = (percentile(walls, q) for q in (0.1, 0.5, 0.9))
    print(f"| {label} | {p10:.3f} s | {p50:.3f} s | {p90:.3f} s | {p90 / p50:.2f} | {peak // 1024} MiB |",
          flush=True)


if __name__ == "__main__":
    main()
