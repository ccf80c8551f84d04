#!/usr/bin/env python3
"""Experiment (a)'s scene redrawn three ways, to see where its frame goes on a CPU rasterizer.

Writes into OUT: merged.json (all 101 spheres as one mesh, one draw), separate.json (the same
sphere mesh as a glTF asset, 101 draws, as scene_a.json draws the built-in one) and front.json
(the merged mesh without the triangles that face away from the camera). Same camera and lights
as SCENE. Usage: python3 bench/scene-a-variants.py SCENE OUT, then
pelt render OUT/merged.json --backend vulkan --bench 20 --warmup 5 (and the others).
"""
import json
import math
import os
import struct
import sys

RINGS, SEGS = 24, 48  # the built-in sphere's (pelt_scene::asset::sphere)


def sphere():
    verts, normals = [], []
    for r in range(RINGS + 1):
        th = math.pi * r / RINGS
        for s in range(SEGS + 1):
            ph = 2 * math.pi * s / SEGS
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            verts.append(tuple(0.5 * c for c in n))
            normals.append(n)
    row = SEGS + 1
    idx = []
    for r in range(RINGS):
        for s in range(SEGS):
            a, b = r * row + s, (r + 1) * row + s
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return verts, normals, idx


def faces_camera(p, cam):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = p
    u, v = (bx - ax, by - ay, bz - az), (cx - ax, cy - ay, cz - az)
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return n[0] * (cam[0] - ax) + n[1] * (cam[1] - ay) + n[2] * (cam[2] - az) > -1e-9


def glb(path, pos, nrm, idx):
    pb = b"".join(struct.pack("<3f", *p) for p in pos)
    nb = b"".join(struct.pack("<3f", *n) for n in nrm)
    ib = struct.pack("<%dI" % len(idx), *idx)
    data = pb + nb + ib
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    view = lambda off, n, target: {"buffer": 0, "byteOffset": off, "byteLength": n, "target": target}
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5}}],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [view(0, len(pb), 34962), view(len(pb), len(nb), 34962),
                        view(len(pb) + len(nb), len(ib), 34963)],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
    }
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    total = 12 + 8 + len(j) + 8 + len(data)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, total))
        f.write(struct.pack("<II", len(j), 0x4E4F534A) + j)
        f.write(struct.pack("<II", len(data), 0x004E4942) + data)


def main(scene_path, out):
    os.makedirs(out, exist_ok=True)
    scene = json.load(open(scene_path))
    cam = scene["camera"]["position"]
    verts, normals, idx = sphere()
    pos, nrm, merged, front = [], [], [], []
    for o in scene["objects"]:
        t = o["transform"]["translation"]
        base = len(pos)
        pts = [(v[0] + t[0], v[1] + t[1], v[2] + t[2]) for v in verts]
        pos += pts
        nrm += normals
        for k in range(0, len(idx), 3):
            tri = [i + base for i in idx[k:k + 3]]
            merged += tri
            if faces_camera([pts[i] for i in idx[k:k + 3]], cam):
                front += tri
    glb(os.path.join(out, "all.glb"), pos, nrm, merged)
    glb(os.path.join(out, "front.glb"), pos, nrm, front)
    glb(os.path.join(out, "one.glb"), verts, normals, idx)
    for name, objects in [
        ("merged", [{"asset": "all.glb"}]),
        ("front", [{"asset": "front.glb"}]),
        ("separate", [{"asset": "one.glb", "transform": o["transform"]} for o in scene["objects"]]),
    ]:
        with open(os.path.join(out, name + ".json"), "w") as f:
            json.dump(dict(scene, objects=objects), f)
    print(f"{len(merged) // 3} triangles, {len(front) // 3} facing the camera")


if __name__ == "__main__":
    main(*sys.argv[1:3])
