// Cook feedback over the viewport: which node is cooking and how far, a cancel button, and the drawn result marked stale while a newer cook runs, or when the last one was cancelled or failed.

import type { CookedMsg, StateMsg } from './protocol';

/** What the page should say of its cook. */
export type CookPhase =
  | { kind: 'idle' }
  | { kind: 'cooking'; node: string | null; fraction: number }
  | { kind: 'cancelled' }
  | { kind: 'failed' };

export interface CookSnapshot {
  state: StateMsg | null;
  cooked: CookedMsg | null;
  /** Progress per node of the cook in flight, in the order nodes started. */
  progress: ReadonlyMap<string, number>;
  /** The newest generation whose cook the server stopped. */
  cancelled: number;
}

/** The phase from what the server said last. */
export function cookPhase(s: CookSnapshot): CookPhase {
  const wanted = s.state?.generation ?? 0;
  const got = s.cooked?.generation ?? 0;
  if (got >= wanted) {
    if (!s.cooked || s.cooked.ok) return { kind: 'idle' };
    return s.cooked.errors.every((e) => e.kind === 'cancelled') ? { kind: 'cancelled' } : { kind: 'failed' };
  }
  if (s.cancelled >= wanted) return { kind: 'cancelled' };
  // The node started last that has not finished is the one to name.
  let node: string | null = null;
  let fraction = 0;
  for (const [path, f] of s.progress) {
    if (f < 1) {
      node = path;
      fraction = f;
    }
  }
  return { kind: 'cooking', node, fraction };
}

/** A cook shorter than this shows no bar (no flicker on every slider step). */
const SHOW_AFTER_MS = 120;

export class CookBar {
  private readonly root: HTMLElement;
  private readonly what: HTMLElement;
  private readonly bar: HTMLProgressElement;
  private readonly cancel: HTMLButtonElement;
  private cookingSince: number | null = null;
  private timer = 0;

  constructor(
    private readonly wrap: HTMLElement,
    onCancel: () => void,
  ) {
    this.root = document.createElement('div');
    this.root.id = 'cook-state';
    this.root.hidden = true;
    this.what = document.createElement('span');
    this.what.className = 'what';
    this.bar = document.createElement('progress');
    this.bar.max = 1;
    this.cancel = document.createElement('button');
    this.cancel.id = 'cancel-cook';
    this.cancel.textContent = 'Cancel';
    this.cancel.title = 'Stop the cook (Esc)';
    this.cancel.addEventListener('click', onCancel);
    this.root.append(this.what, this.bar, this.cancel);
    wrap.appendChild(this.root);
  }

  update(s: CookSnapshot) {
    const phase = cookPhase(s);
    const now = performance.now();
    if (phase.kind === 'cooking') this.cookingSince ??= now;
    else this.cookingSince = null;
    const shown = phase.kind === 'cooking' ? now - this.cookingSince! >= SHOW_AFTER_MS : phase.kind !== 'idle';
    this.wrap.classList.toggle('stale', phase.kind !== 'idle' && shown);
    this.wrap.dataset.cook = phase.kind;
    this.root.hidden = !shown;
    this.root.className = phase.kind;
    this.bar.hidden = phase.kind !== 'cooking';
    this.cancel.hidden = phase.kind !== 'cooking';
    if (phase.kind === 'cooking') {
      this.what.textContent = phase.node ? `cooking ${phase.node}` : 'cooking…';
      // An indeterminate bar until the node reports a fraction.
      if (phase.fraction > 0) this.bar.value = phase.fraction;
      else this.bar.removeAttribute('value');
      if (!shown) {
        clearTimeout(this.timer);
        this.timer = window.setTimeout(() => this.update(s), SHOW_AFTER_MS);
      }
    } else if (phase.kind === 'cancelled') {
      this.what.textContent = 'cancelled: the viewport shows an older result';
    } else if (phase.kind === 'failed') {
      this.what.textContent = 'the cook failed: the viewport shows the last result';
    }
  }
}
