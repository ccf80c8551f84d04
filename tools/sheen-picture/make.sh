#!/usr/bin/env bash
# The picture in docs/extension/PELT_fur/README.md: the Fox `pelt demo` bakes, drawn by pelt
# and by three.js (a viewer without pelt's runtime) with and without its KHR_materials_sheen.
#   bash tools/sheen-picture/make.sh [FOX.glb]     (default out/demo/fox.glb)
# Needs a release build of pelt, `npm ci --prefix tools/sheen-picture`, Debian's chromium and
# Python's Pillow.
set -euo pipefail
cd "$(dirname "$0")/../.."
fox=${1:-out/demo/fox.glb}
tmp=target/sheen-picture
mkdir -p "$tmp"
target/release/pelt render "$fox" -o "$tmp/pelt.png" --size 1280x960 -q
node tools/sheen-picture/render.mjs "$fox" "$tmp/sheen.png" 640x480
node tools/sheen-picture/render.mjs "$fox" "$tmp/no-sheen.png" 640x480 --no-sheen
python3 - "$tmp" docs/extension/PELT_fur/sheen.png <<'PY'
import sys
from PIL import Image, ImageDraw
tmp, out_path = sys.argv[1], sys.argv[2]
# The Fox's part of each frame (pelt's default framing at 1280x960; three.js's at 640x480).
panels = [
    Image.open(f"{tmp}/pelt.png").convert("RGB").crop((380, 300, 780, 750)).resize((400, 450)),
    Image.open(f"{tmp}/sheen.png").convert("RGB").crop((100, 20, 540, 470)).resize((400, 450)),
    Image.open(f"{tmp}/no-sheen.png").convert("RGB").crop((100, 20, 540, 470)).resize((400, 450)),
]
labels = ["pelt render (shells, fins)", "three.js: KHR_materials_sheen",
          "three.js: the same without sheen"]
out = Image.new("RGB", (1200, 480), (30, 30, 34))
d = ImageDraw.Draw(out)
for i, (im, label) in enumerate(zip(panels, labels)):
    out.paste(im, (i * 400, 30))
    d.text((i * 400 + 10, 8), label, fill=(230, 230, 230))
out.save(out_path, optimize=True)
PY
echo "wrote docs/extension/PELT_fur/sheen.png"
