// Keyframed channels as the engine evaluates them (crates/graph/src/channel.rs): constant, linear, Bezier (cubic Hermite with per-frame slopes, automatic where unset) and ease segments; a fixture from the Rust side checks both agree.

export type Interp = 'constant' | 'linear' | 'bezier' | 'ease';

export interface Key {
  frame: number;
  value: number;
  /** How the segment from this key to the next is drawn (linear when absent). */
  interp?: Interp;
  /** Slopes in value per frame; unset Bezier slopes are automatic. */
  slope_in?: number;
  slope_out?: number;
}

function hermite(p0: number, p1: number, m0: number, m1: number, t: number): number {
  const t2 = t * t;
  const t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * m1;
}

/** The automatic slope at key `i`: the neighbours' finite difference. */
export function autoSlope(keys: Key[], i: number): number {
  const a = Math.max(0, i - 1);
  const b = Math.min(keys.length - 1, i + 1);
  return a === b ? 0 : (keys[b].value - keys[a].value) / (keys[b].frame - keys[a].frame);
}

/** The slope leaving key `i` (explicit or automatic). */
export function slopeOut(keys: Key[], i: number): number {
  return keys[i].slope_out ?? autoSlope(keys, i);
}

/** The slope arriving at key `i` (explicit or automatic). */
export function slopeIn(keys: Key[], i: number): number {
  return keys[i].slope_in ?? autoSlope(keys, i);
}

/** The value at `frame` of keys sorted by frame; before the first and after the last key the nearest key's value holds. */
export function evalChannel(keys: Key[], frame: number): number {
  if (!keys.length) return 0;
  if (frame <= keys[0].frame) return keys[0].value;
  const last = keys.length - 1;
  if (frame >= keys[last].frame) return keys[last].value;
  let i = 0;
  while (i + 1 < keys.length && keys[i + 1].frame <= frame) i++;
  const a = keys[i];
  const b = keys[i + 1];
  const span = b.frame - a.frame;
  const t = (frame - a.frame) / span;
  switch (a.interp ?? 'linear') {
    case 'constant':
      return a.value;
    case 'ease':
      return hermite(a.value, b.value, 0, 0, t);
    case 'bezier':
      return hermite(a.value, b.value, slopeOut(keys, i) * span, slopeIn(keys, i + 1) * span, t);
    default:
      return a.value + (b.value - a.value) * t;
  }
}
