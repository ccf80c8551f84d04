#!/usr/bin/env python3
"""One line per `pelt inspect --json` (stdin): what each triangle primitive keeps of the
PELT_fur contract, for tools/pipeline-survival.sh."""
import json
import sys

prims = json.load(sys.stdin)["primitive"]


def one(q):
    c, t = q["contract"], q.get("topology") or {}
    fins = "fins " + c["fins"]
    if c["fins"] == "present":
        fins += " (%d)" % t["fin_edges"]
    if t.get("fins_stale"):
        fins = "fins stale"
    return ", ".join([
        "comb" if c["comb"] else "no comb",
        "groups" if c["normal_groups"] else "no groups",
        fins,
        "manifest" if c["fur_manifest"] else "no manifest",
        "TANGENT" if "TANGENT" in q["attributes"] else "no TANGENT",
    ])


print("; ".join(sorted(set(one(q) for q in prims if q["mode"] == 4))))
