// The studio's keyboard, Houdini's keys: one table of what each key does and where, resolved by a pure function main.ts calls and the tests read.

import type { ViewName } from './viewport';

/** What a key asks for; main.ts does it. */
export type Action =
  | 'save'
  | 'undo'
  | 'redo'
  | 'copy'
  | 'paste'
  | `view-${ViewName}`
  | 'tab-menu'
  | 'delete'
  | 'sticky-note'
  | 'network-box'
  | 'info'
  | 'template'
  | 'colour'
  | 'dive'
  | 'up'
  | 'frame-selection-in-viewport'
  | 'frame-selection-in-editor'
  | 'frame-all-in-viewport'
  | 'frame-all-in-editor'
  | 'display'
  | 'bypass'
  | 'solo'
  | 'cancel'
  | 'rename'
  | 'timeline';

/**
 * Where a binding holds: `anywhere` (a text field included), `outside-fields`
 * (not while typing), `editor` or `viewport` (outside fields, the pointer or
 * focus in that pane, or not), `space-viewport` (Space held over the viewport).
 */
export type Where = 'anywhere' | 'outside-fields' | 'editor' | 'viewport' | 'space-viewport';

export interface Binding {
  /** `KeyboardEvent.key` values; with `mod`, compared without case. */
  keys: string[];
  /** Ctrl (Cmd on a Mac) held. */
  mod?: boolean;
  /** With `mod`: Shift held (undefined: either). */
  shift?: boolean;
  where: Where;
  action: Action;
  /** The browser's own use of the key is stopped. */
  prevent?: boolean;
  /** For the help: what it does. */
  what: string;
}

/** The bindings, the first that matches wins. */
export const BINDINGS: readonly Binding[] = [
  { keys: ['s'], mod: true, where: 'anywhere', action: 'save', prevent: true, what: 'save the network' },
  { keys: ['z'], mod: true, shift: true, where: 'outside-fields', action: 'redo', prevent: true, what: 'redo' },
  { keys: ['z'], mod: true, shift: false, where: 'outside-fields', action: 'undo', prevent: true, what: 'undo' },
  { keys: ['y'], mod: true, where: 'outside-fields', action: 'redo', prevent: true, what: 'redo' },
  { keys: ['c'], mod: true, where: 'outside-fields', action: 'copy', what: 'copy the selected nodes' },
  { keys: ['v'], mod: true, where: 'outside-fields', action: 'paste', what: 'paste nodes' },
  { keys: ['1'], where: 'space-viewport', action: 'view-persp', prevent: true, what: 'perspective view' },
  { keys: ['2'], where: 'space-viewport', action: 'view-top', prevent: true, what: 'top view' },
  { keys: ['3'], where: 'space-viewport', action: 'view-front', prevent: true, what: 'front view' },
  { keys: ['4'], where: 'space-viewport', action: 'view-right', prevent: true, what: 'right view' },
  { keys: ['Tab'], where: 'outside-fields', action: 'tab-menu', prevent: true, what: 'add a node (at the pointer, wired after the selected one)' },
  { keys: ['Delete', 'Backspace'], where: 'outside-fields', action: 'delete', what: 'delete the picked wire or the selected nodes' },
  { keys: ['P'], where: 'editor', action: 'sticky-note', what: 'a sticky note (Shift+P)' },
  { keys: ['O'], where: 'editor', action: 'network-box', what: 'a network box around the selection (Shift+O)' },
  { keys: ['i', 'I'], where: 'editor', action: 'info', what: "the current node's info" },
  { keys: ['t', 'T'], where: 'editor', action: 'template', what: 'the template flag' },
  { keys: ['c', 'C'], where: 'editor', action: 'colour', what: 'colour the selected nodes' },
  { keys: ['Enter'], where: 'outside-fields', action: 'dive', what: 'into the current subnet' },
  { keys: ['u', 'U'], where: 'outside-fields', action: 'up', what: 'up a network level' },
  { keys: ['f', 'F'], where: 'viewport', action: 'frame-selection-in-viewport', what: 'frame the selection' },
  { keys: ['f', 'F'], where: 'editor', action: 'frame-selection-in-editor', what: 'frame the selected nodes' },
  { keys: ['a', 'h'], where: 'viewport', action: 'frame-all-in-viewport', what: 'frame everything' },
  { keys: ['a', 'h'], where: 'editor', action: 'frame-all-in-editor', what: 'frame every node' },
  { keys: ['r', 'R'], where: 'outside-fields', action: 'display', what: 'the display flag' },
  { keys: ['q', 'Q'], where: 'outside-fields', action: 'bypass', what: 'the bypass flag' },
  { keys: ['w', 'W'], where: 'outside-fields', action: 'solo', what: 'solo view of the current node' },
  { keys: ['Escape'], where: 'outside-fields', action: 'cancel', what: 'cancel the cook' },
  { keys: ['F2'], where: 'outside-fields', action: 'rename', what: 'rename the current node' },
  { keys: [' '], where: 'editor', action: 'timeline', prevent: true, what: 'show or hide the timeline' },
];

/** What the handler knows of a key press. */
export interface KeyPress {
  key: string;
  /** Ctrl or Cmd. */
  mod: boolean;
  shift: boolean;
  /** Focus in a text field, select or text area. */
  typing: boolean;
  /** Focus in the viewport, or the pointer over it. */
  inViewport: boolean;
  /** The pointer over the viewport. */
  overViewport: boolean;
  /** Space held down. */
  spaceHeld: boolean;
}

function holds(where: Where, p: KeyPress): boolean {
  switch (where) {
    case 'anywhere':
      return true;
    case 'outside-fields':
      return !p.typing;
    case 'editor':
      return !p.typing && !p.inViewport;
    case 'viewport':
      return !p.typing && p.inViewport;
    case 'space-viewport':
      return !p.typing && p.spaceHeld && p.overViewport;
  }
}

/** The binding a key press triggers, if any. */
export function bindingFor(p: KeyPress): Binding | null {
  for (const b of BINDINGS) {
    if ((b.mod ?? false) !== p.mod) continue;
    if (b.mod && b.shift !== undefined && b.shift !== p.shift) continue;
    const key = b.mod ? p.key.toLowerCase() : p.key;
    if (b.keys.includes(key) && holds(b.where, p)) return b;
  }
  return null;
}
