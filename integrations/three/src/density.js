// The strand model as a medium (pelt_fur::density, crates/pelt-fur/src/density.rs): per
// texel, T(z), the top-view area fraction of strands taller than z, at 8 heights, splatted
// from the same seeded strands the fur textures were rendered from (SplitMix64 streams,
// pelt_fur::strands::nth), with box-filtered mip levels (T is an area fraction, so a level's
// mean over a footprint is exact), plus κ = Σ 2r / Σ π r² and the mean strand diameter. The
// shells' opacity reads it (layer_opacity in the generated GLSL). Computed at load from the
// manifest's `strands`, as pelt's preview does; test/density.test.js checks it against pelt.

export const BINS = 8;
const MAX_SAMPLED = 1 << 20;
const MASK = (1n << 64n) - 1n;
const GAMMA = 0x9e3779b97f4a7c15n;

function mix64(z) {
  z = ((z ^ (z >> 30n)) * 0xbf58476d1ce4e5b9n) & MASK;
  z = ((z ^ (z >> 27n)) * 0x94d049bb133111ebn) & MASK;
  return z ^ (z >> 31n);
}

/** SplitMix64 stream `index` of `seed` (pelt_fur::rng::SplitMix64::stream). */
export class SplitMix64 {
  constructor(seed, index) {
    this.state = mix64((BigInt(seed) & MASK) ^ mix64((BigInt(index) + GAMMA) & MASK));
  }
  nextU64() {
    this.state = (this.state + GAMMA) & MASK;
    return mix64(this.state);
  }
  unit() {
    return Number(this.nextU64() >> 11n) * (1 / 2 ** 53);
  }
  below(n) {
    return Number(((this.nextU64() >> 32n) * BigInt(n)) >> 32n);
  }
}

export { mix64 };

const wrapUnit = (v) => {
  const w = v - Math.floor(v);
  return w >= 1 ? 0 : w;
};

/** pelt_fur::StrandParams::default(): what a manifest leaves out. */
export const STRAND_DEFAULTS = {
  seed: 1, strands: 12000, radius: 0.0025, radiusJitter: 0.3, heightMin: 0.4, heightMax: 1.0,
  heightBias: 1.0, tilt: 0, clumps: 0, clumping: 0, clumpRadius: 0.01,
};

/** The strand model's parameters from a manifest's `strands` object, checked. */
export function strandParams(s) {
  const p = {};
  for (const [k, d] of Object.entries(STRAND_DEFAULTS)) p[k] = s[k] ?? d;
  for (const [k, v] of Object.entries(p)) {
    if (typeof v !== 'number' || !Number.isFinite(v)) throw new Error(`strands.${k} is not a number`);
  }
  if (!Number.isInteger(p.strands) || p.strands < 1 || p.strands > 2 ** 32 - 1) throw new Error(`strands.strands is ${p.strands}`);
  if (!Number.isInteger(p.clumps) || p.clumps < 0 || p.clumps > 1 << 20) throw new Error(`strands.clumps is ${p.clumps}`);
  if (!Number.isInteger(p.seed) || p.seed < 0) throw new Error(`strands.seed is ${p.seed}`);
  return p;
}

/** Strand `i` (pelt_fur::strands::nth): root x, y, radius r, height h. */
function nth(p, centres, i) {
  const span = p.heightMax - p.heightMin;
  const s = new SplitMix64(p.seed, i);
  const member = s.unit();
  let clump = 0;
  if (centres.length === 0) s.nextU64();
  else clump = s.below(p.clumps);
  const u = s.unit();
  const v = s.unit();
  const ur = s.unit();
  const uh = s.unit();
  let x = u;
  let y = v;
  if (member < p.clumping && centres.length > 0) {
    const rr = Math.sqrt(-2 * Math.log(1 - u)) * p.clumpRadius;
    const a = 2 * Math.PI * v;
    const [cx, cy] = centres[clump];
    x = wrapUnit(cx + rr * Math.cos(a));
    y = wrapUnit(cy + rr * Math.sin(a));
  }
  const r = p.radius * (1 + p.radiusJitter * (2 * ur - 1));
  const h = p.heightMin + span * uh ** p.heightBias;
  return { x, y, r, h };
}

/** The side of the density texture (pelt_fur::density::side_for). */
export function sideFor(strands, max = 1024) {
  const s = Math.ceil(Math.sqrt(strands));
  let pow = 1;
  while (pow < s) pow *= 2;
  return Math.min(Math.max(pow, 4), Math.max(max, 4));
}

/**
 * The medium statistics of strand parameters `p` (strandParams) at level-0 side `side`:
 * { side, levels: [Float32Array of side² × 8], kappa, diameter }.
 */
export function density(p, side = sideFor(p.strands)) {
  const centres = [];
  for (let c = 0; c < p.clumps; c++) {
    const s = new SplitMix64(p.seed, (MASK - BigInt(c)));
    centres.push([s.unit(), s.unit()]);
  }
  const stride = Math.max(Math.ceil(p.strands / MAX_SAMPLED), 1);
  const n = side;
  const texelArea = 1 / (n * n);
  const level0 = new Float64Array(n * n * BINS);
  let sum2r = 0;
  let sumArea = 0;
  let count = 0;
  for (let i = 0; i < p.strands; i += stride) {
    const s = nth(p, centres, i);
    const a = Math.PI * s.r * s.r * stride;
    sum2r += 2 * s.r * stride;
    sumArea += a;
    count += stride;
    const bins = Math.min(Math.ceil(s.h * BINS), BINS);
    const fx = s.x * n - 0.5;
    const fy = s.y * n - 0.5;
    const x0 = Math.floor(fx);
    const y0 = Math.floor(fy);
    const wx = fx - x0;
    const wy = fy - y0;
    for (const [dy, wyy] of [[0, 1 - wy], [1, wy]]) {
      for (const [dx, wxx] of [[0, 1 - wx], [1, wx]]) {
        const x = (((x0 + dx) % n) + n) % n;
        const y = (((y0 + dy) % n) + n) % n;
        const v = (a * wxx * wyy) / texelArea;
        const at = (y * n + x) * BINS;
        for (let k = 0; k < bins; k++) level0[at + k] += v;
      }
    }
  }
  const levels = [level0];
  for (let w = n >> 1, pw = n; w >= 1; pw = w, w >>= 1) {
    const prev = levels[levels.length - 1];
    const next = new Float64Array(w * w * BINS);
    for (let y = 0; y < w; y++) {
      for (let x = 0; x < w; x++) {
        for (const [dx, dy] of [[0, 0], [1, 0], [0, 1], [1, 1]]) {
          const c = ((2 * y + dy) * pw + 2 * x + dx) * BINS;
          for (let k = 0; k < BINS; k++) next[(y * w + x) * BINS + k] += prev[c + k] / 4;
        }
      }
    }
    levels.push(next);
  }
  return {
    side,
    levels: levels.map((l) => Float32Array.from(l)),
    kappa: sumArea > 0 ? sum2r / sumArea : 0,
    diameter: count > 0 ? sum2r / count : 0,
  };
}
