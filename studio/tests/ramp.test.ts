// The studio's ramp evaluator against the engine's values (ramp.fixture.json, written by crates/graph/tests/ramp_fixture.rs) and against analytic answers per basis.

import { describe, expect, it } from 'vitest';
import { evalRamp, Ramp, sortedKeys, type RampKey } from '../src/ramp';
import { keysAt, plotRange, rampRows } from '../src/rampeditor';
import fixture from './ramp.fixture.json';

describe('evalRamp', () => {
  it('gives the engine value at every sampled position', () => {
    let checked = 0;
    for (const c of fixture as { keys: RampKey[]; samples: [number, number[]][] }[]) {
      for (const [x, value] of c.samples) {
        const got = evalRamp(c.keys, x);
        expect(got.length).toBe(value.length);
        got.forEach((v, k) => expect(v).toBeCloseTo(value[k], 12));
        checked++;
      }
    }
    expect(checked).toBeGreaterThan(2000);
  });

  it('meets analytic answers', () => {
    const lin: RampKey[] = [
      { pos: 0, value: 2.5, interp: 'linear' },
      { pos: 1, value: 4.5, interp: 'linear' },
    ];
    expect(evalRamp(lin, 0.5)[0]).toBeCloseTo(3.5, 12);
    expect(evalRamp(lin, -1)[0]).toBe(2.5);
    const smooth: RampKey[] = [
      { pos: 0, value: 0, interp: 'monotonecubic' },
      { pos: 1, value: 1, interp: 'monotonecubic' },
    ];
    expect(evalRamp(smooth, 0.25)[0]).toBeCloseTo(0.25 * 0.25 * 2.5, 12);
    const step: RampKey[] = [
      { pos: 0, value: 1, interp: 'constant' },
      { pos: 0.5, value: 2, interp: 'constant' },
    ];
    expect(evalRamp(step, 0.49)[0]).toBe(1);
    expect(evalRamp(step, 0.5)[0]).toBe(2);
    expect(evalRamp([], 0.5)).toEqual([0]);
  });

  it('sorts keys by position, stably', () => {
    const keys = [{ pos: 0.5, id: 'a' }, { pos: 0.1, id: 'b' }, { pos: 0.5, id: 'c' }];
    expect(sortedKeys(keys).map((k) => k.id)).toEqual(['b', 'a', 'c']);
  });
});

describe('the ramp widget model', () => {
  it('reads rows at a frame: channels evaluated, defaults filled, expressions held at 0', () => {
    const rows = [
      { pos: { keys: [{ frame: 1, value: 0 }, { frame: 11, value: 1 }] }, value: 2 },
      { pos: 1, value: { expr: '$F' }, interp: 'bspline' },
    ];
    expect(keysAt(rows, false, 6)).toEqual([
      { pos: 0.5, value: 2, interp: 'linear' },
      { pos: 1, value: 0, interp: 'bspline' },
    ]);
    expect(keysAt([{ pos: 0.2 }], true, 1)).toEqual([{ pos: 0.2, value: [0, 0, 0], interp: 'linear' }]);
  });

  it("reads sweep's old text form as linear keys", () => {
    expect(rampRows('0 1, 1 0.2')).toEqual([
      { pos: 0, value: 1, interp: 'linear' },
      { pos: 1, value: 0.2, interp: 'linear' },
    ]);
    expect(rampRows([{ pos: 0 }, 3, null])).toEqual([{ pos: 0 }]);
  });

  it('plots 0..1 widened to the curve', () => {
    const [lo, hi] = plotRange(new Ramp([{ pos: 0, value: 0, interp: 'catmull-rom' }, { pos: 0.5, value: 2, interp: 'catmull-rom' }, { pos: 1, value: 0 }]));
    expect(lo).toBeLessThan(0);
    expect(hi).toBeGreaterThan(2);
  });
});
