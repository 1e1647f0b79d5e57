// Unit tests of the keymap: Houdini's keys resolve to their actions where they hold, and nowhere else.
import { expect, test } from 'vitest';
import { BINDINGS, bindingFor, type KeyPress } from '../src/keymap';

const press = (key: string, p: Partial<KeyPress> = {}): string | null =>
  bindingFor({ key, mod: false, shift: false, typing: false, inViewport: false, overViewport: false, spaceHeld: false, ...p })?.action ?? null;

test('saving works everywhere, even in a text field; the other commands wait until typing ends', () => {
  expect(press('s', { mod: true, typing: true })).toBe('save');
  expect(press('S', { mod: true, shift: true })).toBe('save');
  expect(press('z', { mod: true, typing: true })).toBeNull();
  expect(press('Tab', { typing: true })).toBeNull();
  expect(press('q', { typing: true })).toBeNull();
});

test('Ctrl+Z undoes, Ctrl+Shift+Z and Ctrl+Y redo, Ctrl+C and Ctrl+V copy and paste', () => {
  expect(press('z', { mod: true })).toBe('undo');
  expect(press('Z', { mod: true, shift: true })).toBe('redo');
  expect(press('y', { mod: true })).toBe('redo');
  expect(press('c', { mod: true })).toBe('copy');
  expect(press('v', { mod: true })).toBe('paste');
  // Any other chord is the browser's.
  expect(press('f', { mod: true })).toBeNull();
  expect(press('q', { mod: true })).toBeNull();
});

test('Space+1..4 over the viewport pick its view; 1..4 alone do nothing', () => {
  const over = { spaceHeld: true, overViewport: true, inViewport: true };
  expect(['1', '2', '3', '4'].map((k) => press(k, over))).toEqual(['view-persp', 'view-top', 'view-front', 'view-right']);
  expect(press('1', { spaceHeld: true })).toBeNull();
  expect(press('1', { overViewport: true, inViewport: true })).toBeNull();
});

test('keys that edit the network hold in the editor; F, A and H frame whichever pane has the pointer', () => {
  expect(press('P')).toBe('sticky-note');
  expect(press('p')).toBeNull();
  expect(press('P', { inViewport: true })).toBeNull();
  expect(press('O')).toBe('network-box');
  expect(press('i')).toBe('info');
  expect(press('t', { inViewport: true })).toBeNull();
  expect(press('c')).toBe('colour');
  expect(press('f')).toBe('frame-selection-in-editor');
  expect(press('F', { inViewport: true })).toBe('frame-selection-in-viewport');
  expect(press('h')).toBe('frame-all-in-editor');
  expect(press('a', { inViewport: true })).toBe('frame-all-in-viewport');
  expect(press(' ')).toBe('timeline');
  expect(press(' ', { inViewport: true })).toBeNull();
});

test('flags, diving, cancel and rename hold in either pane', () => {
  for (const inViewport of [false, true]) {
    expect(['r', 'Q', 'w', 'Enter', 'U', 'Escape', 'F2', 'Tab', 'Delete', 'Backspace'].map((k) => press(k, { inViewport }))).toEqual([
      'display',
      'bypass',
      'solo',
      'dive',
      'up',
      'cancel',
      'rename',
      'tab-menu',
      'delete',
      'delete',
    ]);
  }
});

test('every binding says what it does, and no two bindings claim the same key in the same place', () => {
  const seen = new Set<string>();
  for (const b of BINDINGS) {
    expect(b.what.length).toBeGreaterThan(3);
    for (const k of b.keys) {
      const id = `${b.mod ? 'mod+' : ''}${b.shift === undefined ? '' : b.shift ? 'shift+' : 'noshift+'}${k}@${b.where}`;
      expect(seen.has(id), id).toBe(false);
      seen.add(id);
    }
  }
});
