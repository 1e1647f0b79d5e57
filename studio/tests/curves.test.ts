// The curve editor's reading and writing of the document (animated components found, keys written back sorted in the document's form) and the parameter panel's reading of typed text (numbers stay numbers, anything else is an expression).

import { describe, expect, it } from 'vitest';
import { curvesOf, withKeys } from '../src/curves';
import { describeValue, expands, parseComponent } from '../src/params';

describe('curvesOf', () => {
  it('finds each animated component with a readable label', () => {
    const c = curvesOf({
      size: [{ keys: [{ frame: 1, value: 0 }] }, 1, { keys: [{ frame: 2, value: 3 }] }],
      radius: { keys: [{ frame: 5, value: 1 }] },
      rows: 4,
      center: [{ expr: '$F' }, 0, 0],
    });
    expect(c.map((x) => [x.label, x.param, x.component])).toEqual([
      ['size.x', 'size', 0],
      ['size.z', 'size', 2],
      ['radius', 'radius', 0],
    ]);
  });
});

describe('withKeys', () => {
  it('replaces one component and writes keys sorted without default fields', () => {
    const v = withKeys([1, { keys: [] }, 3], 1, [
      { frame: 9, value: 2, interp: 'linear' },
      { frame: 1, value: 0, interp: 'bezier', slope_out: 0.5 },
    ]);
    expect(v).toEqual([1, { keys: [{ frame: 1, value: 0, interp: 'bezier', slope_out: 0.5 }, { frame: 9, value: 2 }] }, 3]);
    expect(withKeys({ keys: [] }, 0, [{ frame: 1, value: 2 }])).toEqual({ keys: [{ frame: 1, value: 2 }] });
  });
});

describe('typed parameter text', () => {
  it('reads numbers as numbers and anything else as an expression', () => {
    expect(parseComponent(' 2.5 ')).toBe(2.5);
    expect(parseComponent('sin($F)')).toEqual({ expr: 'sin($F)' });
    expect(parseComponent('1e3')).toBe(1000);
  });
  it('knows which strings expand and shows values briefly', () => {
    expect(expands('$HIP/a.obj')).toBe(true);
    expect(expands('`ch("x")`')).toBe(true);
    expect(expands('plain.obj')).toBe(false);
    expect(describeValue([1, 2.123456789])).toBe('1, 2.12346');
    expect(describeValue({ error: 'bad' })).toBe('error: bad');
  });
});
