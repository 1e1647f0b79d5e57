// The studio's channel evaluator against the engine's values (channel.fixture.json, written by crates/graph/tests/channel_fixture.rs) and against Hermite's end conditions.

import { describe, expect, it } from 'vitest';
import { evalChannel, slopeOut, type Key } from '../src/channel';
import fixture from './channel.fixture.json';

describe('evalChannel', () => {
  it('gives the engine value at every sampled frame', () => {
    let checked = 0;
    for (const c of fixture as { keys: Key[]; samples: [number, number][] }[]) {
      for (const [frame, value] of c.samples) {
        expect(evalChannel(c.keys, frame)).toBeCloseTo(value, 12);
        checked++;
      }
    }
    expect(checked).toBeGreaterThan(500);
  });

  it('meets its keys and their slopes', () => {
    const keys: Key[] = [
      { frame: 0, value: 1, interp: 'bezier', slope_out: 2 },
      { frame: 10, value: 3, slope_in: -1 },
    ];
    expect(evalChannel(keys, 0)).toBe(1);
    expect(evalChannel(keys, 10)).toBe(3);
    const h = 1e-4;
    expect((evalChannel(keys, h) - evalChannel(keys, 0)) / h).toBeCloseTo(2, 3);
    expect((evalChannel(keys, 10) - evalChannel(keys, 10 - h)) / h).toBeCloseTo(-1, 3);
    expect(slopeOut(keys, 0)).toBe(2);
  });
});
