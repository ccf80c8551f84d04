#!/usr/bin/env python3
"""The curves behind pelt's shells-by-screen-size rule (crates/pelt-fur/src/shells.rs):
error against shell count at several camera distances. For each distance (the scene's camera
moved toward its target by a factor), `pelt render --mode forward` draws 2 to 64 shells and
128 shells (the converged shell model); each count's FLIP against 128 is printed, with the
fur's projected length in pixels (from `pelt render --explain`'s planned count is not used:
the length is computed here as pelt_scene::footprint::fur_pixels does, from the asset's box
given on the command line) and the knee: the smallest count that a doubling improves by under
FLIP 0.003.

    python3 tools/shell-rule-curves.py out/demo/scene.json --size 320x180 \\
        --pelt target/release/pelt --flip target/release/examples/flip_pngs

(`cargo build --release --example flip_pngs -p pelt-measure` builds the FLIP tool.)
"""
import argparse, json, math, os, subprocess, sys, tempfile

COUNTS = [2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64]
FACTORS = [2.0, 1.4, 1.0, 0.7, 0.5, 0.35]


def glb_box(path):
    import struct
    data = open(path, 'rb').read()
    n = struct.unpack('<I', data[12:16])[0]
    j = json.loads(data[20:20 + n])
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    length = max((m.get('extensions', {}).get('PELT_fur', {}).get('length', 0) for m in j.get('materials', [])), default=0)
    for mesh in j['meshes']:
        for p in mesh['primitives']:
            a = j['accessors'][p['attributes']['POSITION']]
            lo = [min(x, y) for x, y in zip(lo, a['min'])]
            hi = [max(x, y) for x, y in zip(hi, a['max'])]
    return lo, hi, length


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('scene')
    ap.add_argument('--size', default='320x180')
    ap.add_argument('--pelt', default='target/release/pelt')
    ap.add_argument('--flip', default='target/release/examples/flip_pngs')
    a = ap.parse_args()
    scene = json.load(open(a.scene))
    base = os.path.dirname(os.path.abspath(a.scene))
    fur = next(o for o in scene['objects'] if o.get('material', {}).get('kind') == 'fur')
    lo, hi, length = glb_box(os.path.join(base, fur['asset']))
    w, h = map(int, a.size.split('x'))
    cam = scene['camera']
    t, p0 = cam['target'], cam['position']
    print(f"| distance | fur on screen (px) | " + " | ".join(str(n) for n in COUNTS) + " | knee |")
    print("|---" * (len(COUNTS) + 3) + "|")
    with tempfile.TemporaryDirectory() as tmp:
        for f in FACTORS:
            s = json.loads(json.dumps(scene))
            s['camera']['position'] = [t[i] + (p0[i] - t[i]) * f for i in range(3)]
            s['camera']['near'] = cam['near'] * f
            path = os.path.join(base, f'.shell-rule-{f}.json')
            json.dump(s, open(path, 'w'))
            try:
                fwd = [t[i] - s['camera']['position'][i] for i in range(3)]
                fl = math.sqrt(sum(x * x for x in fwd))
                corners = [[x, y, z] for x in (lo[0] - length, hi[0] + length) for y in (lo[1] - length, hi[1] + length) for z in (lo[2] - length, hi[2] + length)]
                near = min(sum((c[i] - s['camera']['position'][i]) * fwd[i] / fl for i in range(3)) for c in corners)
                near = max(near, s['camera']['near'])
                px = length * h / (2 * math.tan(math.radians(cam.get('fovYDeg', 45)) / 2)) / near
                imgs = {}
                for n in COUNTS + [128]:
                    out = os.path.join(tmp, f'{f}-{n}.png')
                    subprocess.run([a.pelt, 'render', path, '--mode', 'forward', '--size', a.size, '--shells', str(n), '-o', out, '-q'], check=True)
                    imgs[n] = out
                err = {n: float(subprocess.run([a.flip, imgs[n], imgs[128]], check=True, capture_output=True, text=True).stdout) for n in COUNTS}
                knee = next((n for n in COUNTS if 2 * n in err and err[n] - err[2 * n] < 0.003), COUNTS[-1])
                print(f"| {f} | {px:.1f} | " + " | ".join(f"{err[n]:.4f}" for n in COUNTS) + f" | {knee} |")
            finally:
                os.remove(path)


if __name__ == '__main__':
    sys.exit(main())
