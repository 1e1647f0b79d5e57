// The studio's client state: what the server said last (state, cook, progress) and what this page chose (network shown, selection, frame range), with change notification.

import type { CookedMsg, NodeType, StateMsg } from './protocol';

export interface Store {
  catalogue: Map<string, NodeType>;
  state: StateMsg | null;
  cooked: CookedMsg | null;
  /** Cook progress per node path during the current generation. */
  progress: Map<string, number>;
  /** The newest generation whose cook the server stopped. */
  cancelled: number;
  /** Events of the last cook that ran each node (badges persist across cooks). */
  badges: Map<string, { ms: number; hit: boolean; warnings: string[] }>;
  /** The network shown in the editor (`/` or a subnet path). */
  at: string;
  selected: Set<string>;
  /** The node whose parameters the panel shows. */
  current: string | null;
  range: [number, number];
  rangeSet: boolean;
  /** Playback rate: the network's `fps`, else 24. */
  fps: number;
  /** This tab's number on the server (its undo history is its own). */
  client: number;
}

type Fn = () => void;

export function createStore(): Store & { subscribe(fn: Fn): void; notify(): void } {
  const listeners: Fn[] = [];
  let queued = false;
  return {
    catalogue: new Map(),
    state: null,
    cooked: null,
    progress: new Map(),
    cancelled: 0,
    badges: new Map(),
    at: '/',
    selected: new Set(),
    current: null,
    range: [1, 100],
    rangeSet: false,
    fps: 24,
    client: 0,
    subscribe(fn: Fn) {
      listeners.push(fn);
    },
    /** Redraws once per animation frame however many changes came in. */
    notify() {
      if (queued) return;
      queued = true;
      requestAnimationFrame(() => {
        queued = false;
        for (const fn of listeners) fn();
      });
    },
  };
}

export type AppStore = ReturnType<typeof createStore>;
