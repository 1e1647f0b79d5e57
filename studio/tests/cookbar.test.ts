// Unit tests of the cook feedback's phase: cooking names the node started last, cancelled and failed cooks mark the viewport stale.
import { expect, test } from 'vitest';
import { cookPhase, type CookSnapshot } from '../src/cookbar';
import type { CookedMsg, StateMsg } from '../src/protocol';

const state = (generation: number) => ({ generation }) as StateMsg;
const cooked = (generation: number, ok = true, kind = 'kernel') =>
  ({ generation, ok, errors: ok ? [] : [{ path: '/n', param: null, message: 'x', kind }] }) as unknown as CookedMsg;
const snap = (s: Partial<CookSnapshot>): CookSnapshot => ({ state: null, cooked: null, progress: new Map(), cancelled: 0, ...s });

test('a cook in flight names the unfinished node started last, with its fraction', () => {
  const progress = new Map([
    ['/a', 1],
    ['/b', 0.25],
    ['/c', 1],
  ]);
  expect(cookPhase(snap({ state: state(3), cooked: cooked(2), progress }))).toEqual({ kind: 'cooking', node: '/b', fraction: 0.25 });
  expect(cookPhase(snap({ state: state(3), cooked: cooked(2) }))).toEqual({ kind: 'cooking', node: null, fraction: 0 });
});

test('a result for the newest generation is idle, or failed, or cancelled', () => {
  expect(cookPhase(snap({ state: state(3), cooked: cooked(3) }))).toEqual({ kind: 'idle' });
  expect(cookPhase(snap({ state: state(3), cooked: cooked(3, false) }))).toEqual({ kind: 'failed' });
  expect(cookPhase(snap({ state: state(3), cooked: cooked(3, false, 'cancelled') }))).toEqual({ kind: 'cancelled' });
});

test('a stopped cook is cancelled until a newer one starts', () => {
  expect(cookPhase(snap({ state: state(3), cooked: cooked(2), cancelled: 3 }))).toEqual({ kind: 'cancelled' });
  expect(cookPhase(snap({ state: state(4), cooked: cooked(2), cancelled: 3 })).kind).toBe('cooking');
});
