// Ramps as the engine evaluates them (crates/geo/src/ramp.rs, Houdini's ramp parameters): keys sorted by position, each key's basis drawing the segment after it (constant, linear, catmull-rom, monotonecubic, bspline), end values held outside the keys; a fixture from the Rust side checks both agree.

export type Basis = 'constant' | 'linear' | 'catmull-rom' | 'monotonecubic' | 'bspline';

export const BASES: Basis[] = ['constant', 'linear', 'catmull-rom', 'monotonecubic', 'bspline'];

/** A key as the document writes it: `value` is a number (float ramp) or `[r, g, b]` (colour ramp). */
export interface RampKey {
  pos: number;
  value: number | number[];
  interp?: string;
}

/** A key reduced to numbers: position, value components, basis. */
interface Key {
  pos: number;
  v: number[];
  basis: Basis;
}

function basisOf(name: string | undefined): Basis {
  return BASES.includes(name as Basis) ? (name as Basis) : 'linear';
}

/** The keys sorted by position (stably), as the engine sorts them. */
export function sortedKeys<K extends { pos: number }>(keys: K[]): K[] {
  return keys
    .map((k, i) => ({ k, i }))
    .sort((a, b) => a.k.pos - b.k.pos || a.i - b.i)
    .map((e) => e.k);
}

/** A ramp ready to evaluate: sorted keys and the slopes its cubic bases use (computed once). */
export class Ramp {
  readonly keys: Key[];
  readonly size: number;
  private catmull: number[][];
  private monotone: number[][];

  constructor(keys: RampKey[], size?: number) {
    const n = size ?? (keys.length && Array.isArray(keys[0].value) ? 3 : 1);
    this.size = n;
    this.keys = sortedKeys(keys).map((k) => {
      const raw = Array.isArray(k.value) ? k.value : [k.value];
      return { pos: Number(k.pos), v: Array.from({ length: n }, (_, c) => Number(raw[c] ?? 0)), basis: basisOf(k.interp) };
    });
    this.catmull = this.keys.map((_, k) => this.catmullSlope(k));
    this.monotone = this.keys.map((_, k) => this.monotoneSlope(k));
  }

  private secant(a: number, b: number): number[] | null {
    const h = this.keys[b].pos - this.keys[a].pos;
    return h > 0 ? this.keys[a].v.map((va, c) => (this.keys[b].v[c] - va) / h) : null;
  }

  private catmullSlope(k: number): number[] {
    const l = Math.max(0, k - 1);
    const r = Math.min(this.keys.length - 1, k + 1);
    return this.secant(l, r) ?? new Array<number>(this.size).fill(0);
  }

  private monotoneSlope(k: number): number[] {
    const zero = new Array<number>(this.size).fill(0);
    if (k === 0 || k + 1 >= this.keys.length) return zero;
    const d0 = this.secant(k - 1, k);
    const d1 = this.secant(k, k + 1);
    if (!d0 || !d1) return zero;
    const h0 = this.keys[k].pos - this.keys[k - 1].pos;
    const h1 = this.keys[k + 1].pos - this.keys[k].pos;
    const w0 = 2 * h1 + h0;
    const w1 = h1 + 2 * h0;
    return d0.map((a, c) => (a * d1[c] <= 0 ? 0 : (w0 + w1) / (w0 / a + w1 / d1[c])));
  }

  /** The value at `x`: one number per component. */
  eval(x: number): number[] {
    const keys = this.keys;
    if (!keys.length) return new Array<number>(this.size).fill(0);
    if (!(x > keys[0].pos)) return [...keys[0].v];
    const last = keys.length - 1;
    if (x >= keys[last].pos) return [...keys[last].v];
    let lo = 0;
    let hi = keys.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (keys[mid].pos <= x) lo = mid + 1;
      else hi = mid;
    }
    const i = lo - 1;
    const a = keys[i];
    const b = keys[i + 1];
    const h = b.pos - a.pos;
    const t = (x - a.pos) / h;
    switch (a.basis) {
      case 'constant':
        return [...a.v];
      case 'linear':
        return a.v.map((va, c) => va + (b.v[c] - va) * t);
      case 'catmull-rom':
        return hermite(a, b, this.catmull[i], this.catmull[i + 1], h, t);
      case 'monotonecubic':
        return hermite(a, b, this.monotone[i], this.monotone[i + 1], h, t);
      default:
        return this.bspline(i, x);
    }
  }

  /** The B-spline run through segment `i`: its keys (and the one ending it) are control points, the ends reflected. */
  private bspline(i: number, x: number): number[] {
    const keys = this.keys;
    let a = i;
    while (a > 0 && keys[a - 1].basis === 'bspline') a--;
    let e = i + 1;
    while (e + 1 < keys.length && keys[e].basis === 'bspline') e++;
    const last = e - a;
    const get = (k: number, c: number) => (c === 0 ? keys[k].pos : keys[k].v[c - 1]);
    const point = (j: number, c: number) => {
      if (j < 0) return 2 * get(a, c) - get(a + 1, c);
      if (j > last) return 2 * get(e, c) - get(e - 1, c);
      return get(a + j, c);
    };
    const start = (s: number) => (point(s - 1, 0) + 4 * point(s, 0) + point(s + 1, 0)) / 6;
    let s = 0;
    while (s + 1 < last && start(s + 1) <= x) s++;
    const coefficients = (c: number) => {
      const p = [point(s - 1, c), point(s, c), point(s + 1, c), point(s + 2, c)];
      return [(-p[0] + 3 * p[1] - 3 * p[2] + p[3]) / 6, (3 * p[0] - 6 * p[1] + 3 * p[2]) / 6, (-3 * p[0] + 3 * p[2]) / 6, (p[0] + 4 * p[1] + p[2]) / 6];
    };
    const u = solveMonotoneCubic(coefficients(0), x);
    return Array.from({ length: this.size }, (_, c) => {
      const k = coefficients(c + 1);
      return ((k[0] * u + k[1]) * u + k[2]) * u + k[3];
    });
  }
}

function hermite(a: Key, b: Key, ma: number[], mb: number[], h: number, t: number): number[] {
  const t2 = t * t;
  const t3 = t2 * t;
  const h00 = 2 * t3 - 3 * t2 + 1;
  const h10 = t3 - 2 * t2 + t;
  const h01 = -2 * t3 + 3 * t2;
  const h11 = t3 - t2;
  return a.v.map((va, c) => h00 * va + h10 * h * ma[c] + h01 * b.v[c] + h11 * h * mb[c]);
}

/** Where in 0..1 the non-decreasing cubic with coefficients `k` (highest first) equals `x`: Newton inside a shrinking bracket. */
function solveMonotoneCubic(k: number[], x: number): number {
  const f = (u: number) => ((k[0] * u + k[1]) * u + k[2]) * u + k[3];
  const x0 = k[3];
  const x1 = k[0] + k[1] + k[2] + k[3];
  if (!(x > x0) || x1 <= x0) return 0;
  if (x >= x1) return 1;
  const tolerance = (x1 - x0) * 1e-13;
  let lo = 0;
  let hi = 1;
  let u = (x - x0) / (x1 - x0);
  for (let n = 0; n < 64; n++) {
    const r = f(u) - x;
    if (Math.abs(r) <= tolerance) break;
    if (r < 0) lo = u;
    else hi = u;
    const d = (3 * k[0] * u + 2 * k[1]) * u + k[2];
    const next = u - r / d;
    u = next > lo && next < hi ? next : 0.5 * (lo + hi);
    if (hi - lo <= Number.EPSILON) break;
  }
  return u;
}

/** The value of document keys at `x` (a float ramp's first component). */
export function evalRamp(keys: RampKey[], x: number): number[] {
  return new Ramp(keys).eval(x);
}
