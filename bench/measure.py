#!/usr/bin/env python3
"""Times commands side by side: every round runs each command once, in turn, so a slow spell
of the machine falls on all of them alike. Prints a Markdown table (p10, p50, p90 of the wall
time, p90/p50, peak RSS) and, for each --vs pair, the speed and memory ratios.

Usage: measure.py ROUNDS SPEC_FILE [--vs SLOW_LABEL FAST_LABEL]...
SPEC_FILE: one command per line, `LABEL<TAB>COMMAND...` (COMMAND split on spaces), or
`LABEL<TAB>MAX_ROUNDS<TAB>COMMAND...` for a slow tool timed in the first MAX_ROUNDS rounds only.
Wall time: perf_counter around posix_spawn and wait4; peak RSS: the largest ru_maxrss of the
runs (wait4). One untimed warm-up run per command first (page cache, outputs present, as in a
rebuild), except for the slow tools given MAX_ROUNDS.
"""
import os
import sys
import time


def run_once(cmd):
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


def percentile(values, q):
    """Nearest rank: the smallest value with at least a fraction q of the runs at or below."""
    s = sorted(values)
    k = max(0, min(len(s) - 1, -(-int(q * 100) * len(s) // 100) - 1))
    return s[k]


def main():
    rounds, spec = int(sys.argv[1]), sys.argv[2]
    vs, rest = [], sys.argv[3:]
    while rest:
        if rest[0] != "--vs" or len(rest) < 3:
            sys.exit(__doc__)
        vs.append((rest[1], rest[2]))
        rest = rest[3:]
    cmds = []
    with open(spec) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                fields = line.rstrip("\n").split("\t")
                label, cmd = fields[0], fields[-1]
                limit = int(fields[1]) if len(fields) == 3 else rounds
                cmds.append((label, limit, cmd.split()))
    for _, limit, cmd in cmds:
        if limit == rounds:  # slow tools (fewer rounds) skip the warm-up
            run_once(cmd)
    walls = {label: [] for label, _, _ in cmds}
    peak = {label: 0 for label, _, _ in cmds}
    for r in range(rounds):
        for label, limit, cmd in cmds:
            if r >= limit:
                continue
            w, rss = run_once(cmd)
            walls[label].append(w)
            peak[label] = max(peak[label], rss)
    print("| command | runs | p10 | p50 | p90 | p90/p50 | peak RSS |")
    print("|---|---|---|---|---|---|---|")
    p50 = {}
    for label, _, _ in cmds:
        w = walls[label]
        a, b, c = (percentile(w, q) for q in (0.1, 0.5, 0.9))
        p50[label] = b
        print(f"| {label} | {len(w)} | {a:.3f} s | {b:.3f} s | {c:.3f} s | {c / b:.2f} | "
              f"{peak[label] // 1024} MiB |")
    print()
    for slow, fast in vs:
        print(f"- {fast}: **{p50[slow] / p50[fast]:.1f}×** faster than {slow} (p50), "
              f"peak memory {peak[fast] / peak[slow]:.2f}× its")


if __name__ == "__main__":
    main()
