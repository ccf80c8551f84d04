// The scene pelt gives one asset (crates/pelt-scene/src/framing.rs, asset_scene): the camera
// framing its bounding sphere from the front, a little above and to the side, a key, a fill
// and a rim light sized to it, a little ambient, and the procedural sky for fur. `box` is
// the asset's bounds ({ min, max } arrays), `furLength` its longest fur in its units.

export function assetScene(asset, box, furLength, width, height, fur = true) {
  const center = [0, 1, 2].map((k) => (box.min[k] + box.max[k]) / 2);
  const diag = Math.hypot(...[0, 1, 2].map((k) => box.max[k] - box.min[k]));
  const radius = Math.max(diag / 2 + furLength, 1e-3);
  const fovYDeg = 40;
  const half = Math.tan((fovYDeg * Math.PI) / 360);
  const fit = Math.min(half, half * (width / height));
  const distance = (radius / Math.sin(Math.atan(fit))) * 1.1;
  const d = [0.35, 0.3, 1.0];
  const dl = Math.hypot(...d);
  const eye = center.map((c, k) => c + (d[k] / dl) * distance);
  const light = (offset, color, intensity) => ({
    position: center.map((c, k) => c + offset[k] * radius),
    radius: radius * 8,
    intensity: intensity * radius * radius,
    color,
  });
  return {
    output: { width, height },
    camera: {
      position: eye, target: center, up: [0, 1, 0], fovYDeg,
      near: Math.max(distance - radius * 1.5, distance * 0.01), far: distance + radius * 4,
    },
    ambient: [0.04, 0.04, 0.04],
    objects: [{ asset, material: { kind: fur ? 'fur' : 'opaque' }, color: fur ? [1, 1, 1] : [0.8, 0.8, 0.8] }],
    sky: { kind: fur ? 'procedural' : 'none' },
    lights: [
      light([1.5, 2.0, 2.5], [1.0, 0.95, 0.85], 6.0),
      light([-2.5, 0.5, 1.5], [0.55, 0.65, 1.0], 2.5),
      light([0.0, 1.5, -3.0], [1.0, 1.0, 1.0], 4.0),
    ],
  };
}
