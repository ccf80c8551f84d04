#!/usr/bin/env python3
"""A quad (2 × 2 m, facing up) with one large base colour texture, for the texture-bounds
figures in docs/preview.md: red follows x, green follows y, blue a checker of 64-texel
squares. Writes DIR/quad-png.gltf, quad-jpeg.gltf (baseline) and quad-pjpeg.gltf
(progressive), each beside its image.

    python3 bench/big-texture.py DIR [SIDE]      # SIDE defaults to 16384
    /usr/bin/time -f "%e s %M KB" target/release/pelt render DIR/quad-png.gltf \\
        -o DIR/out.png --size 160x90

Needs numpy and Pillow (pip install numpy pillow).
"""
import base64
import json
import os
import struct
import sys

import numpy as np
from PIL import Image

Image.MAX_IMAGE_PIXELS = None


def image(side, alpha):
    x = np.arange(side, dtype=np.uint32)
    ramp = (x * 255 // max(side - 1, 1)).astype(np.uint8)
    img = np.zeros((side, side, 4 if alpha else 3), np.uint8)
    img[:, :, 0] = ramp[None, :]
    img[:, :, 1] = ramp[:, None]
    img[:, :, 2] = ((x[None, :] // 64 + x[:, None] // 64) % 2 * 200).astype(np.uint8)
    if alpha:
        img[:, :, 3] = 255
    return img


def quad(uri):
    pos = struct.pack("<12f", -1, 0, 1, 1, 0, 1, 1, 0, -1, -1, 0, -1)
    nrm = struct.pack("<12f", *([0, 1, 0] * 4))
    uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    buf = pos + nrm + uv + idx
    views = [(0, 48), (48, 48), (96, 32), (128, 12)]
    return {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
        "textures": [{"source": 0}],
        "images": [{"uri": uri}],
        "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1, 0, -1], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
    }


def main():
    out = sys.argv[1]
    side = int(sys.argv[2]) if len(sys.argv) > 2 else 16384
    os.makedirs(out, exist_ok=True)
    Image.fromarray(image(side, True), "RGBA").save(os.path.join(out, "quad-png.png"))
    rgb = Image.fromarray(image(side, False), "RGB")
    rgb.save(os.path.join(out, "quad-jpeg.jpg"), quality=90)
    rgb.save(os.path.join(out, "quad-pjpeg.jpg"), quality=90, progressive=True)
    for name, uri in [("quad-png", "quad-png.png"), ("quad-jpeg", "quad-jpeg.jpg"),
                      ("quad-pjpeg", "quad-pjpeg.jpg")]:
        with open(os.path.join(out, name + ".gltf"), "w") as f:
            json.dump(quad(uri), f)


if __name__ == "__main__":
    main()
