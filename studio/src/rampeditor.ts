// The ramp widget of the parameter panel: a float ramp's curve (or a colour ramp's gradient) drawn with the engine's interpolation (ramp.ts); a click adds a key there, a drag moves one (position and value), the selected key's fields and interpolation are edited below, Delete removes it. Every change sets the whole parameter; a drag (with the click that added its key) is one undo step.

import { channelAt, isChannel } from './network';
import { Ramp, type RampKey } from './ramp';

const SVG = 'http://www.w3.org/2000/svg';
const HEIGHT = 120;
const STRIP = 28;
const PAD = { left: 8, right: 8, top: 8, bottom: 8 };

/** A key row as the document writes it: each field a number (or `[r, g, b]`), a channel or an expression. */
export type Row = Record<string, unknown>;

export interface RampWidgetOptions {
  rows: Row[];
  colour: boolean;
  frame: number;
  /** Names the widget (node path and parameter): selection and focus survive the panel's redraws by it. */
  place: string;
  /** The selected key (a document row index) when the panel last drew this place. */
  selected: number | null;
  select(k: number | null): void;
  /** Sets the whole parameter; `merge` folds the change into the previous undo step (a drag). */
  set(rows: Row[], merge: boolean): Promise<unknown> | unknown;
  /** Draws the field widgets of the selected key (position, value, interpolation) into `host`; `merge` as for `set` (a slider's drag). */
  fields(host: HTMLElement, row: Row, k: number, set: (row: Row, merge?: boolean) => unknown): void;
  /** The drag ended: the panel may redraw. */
  dragEnded(): void;
}

/** A ramp's key rows as the document holds them; the old text form `u value, u value` (sweep's, before ramps) read as linear keys, so an edit writes it anew as rows. */
export function rampRows(value: unknown): Row[] {
  if (Array.isArray(value)) return value.filter((r): r is Row => typeof r === 'object' && r !== null && !Array.isArray(r));
  if (typeof value !== 'string') return [];
  return value
    .split(',')
    .map((pair) => pair.trim().split(/\s+/).map(Number))
    .filter((n) => n.length === 2 && n.every(Number.isFinite))
    .map(([pos, v]) => ({ pos, value: v, interp: 'linear' }));
}

/** A field's number at `frame`: constants, channels at the frame; NaN for an expression (evaluated by the engine only). */
export function fieldAt(v: unknown, frame: number): number {
  if (typeof v === 'number') return v;
  if (isChannel(v)) return channelAt(v.keys, frame);
  if (typeof v === 'boolean') return Number(v);
  return NaN;
}

/** The rows as keys at `frame` (a missing field takes its default: position 0, value 0, linear). */
export function keysAt(rows: Row[], colour: boolean, frame: number): RampKey[] {
  return rows.map((r) => {
    const pos = fieldAt(r.pos ?? 0, frame);
    const raw = r.value ?? (colour ? [0, 0, 0] : 0);
    const value = colour ? (Array.isArray(raw) ? raw : [raw, raw, raw]).map((c) => fieldAt(c, frame)) : fieldAt(raw, frame);
    return { pos: Number.isFinite(pos) ? pos : 0, value: Array.isArray(value) ? value.map((c) => (Number.isFinite(c) ? c : 0)) : Number.isFinite(value) ? value : 0, interp: typeof r.interp === 'string' ? r.interp : 'linear' };
  });
}

/** The value range a float ramp's plot shows: 0..1 widened to its keys and curve, padded. */
export function plotRange(ramp: Ramp): [number, number] {
  let lo = 0;
  let hi = 1;
  for (const k of ramp.keys) {
    lo = Math.min(lo, k.v[0]);
    hi = Math.max(hi, k.v[0]);
  }
  for (let i = 0; i <= 100; i++) {
    const v = ramp.eval(i / 100)[0];
    lo = Math.min(lo, v);
    hi = Math.max(hi, v);
  }
  const pad = (hi - lo) * 0.06;
  return [lo - pad, hi + pad];
}

/** Six significant digits, as the panel writes numbers. */
function round(v: number): number {
  return Number(v.toPrecision(6));
}

function hex(rgb: number[]): string {
  return '#' + rgb.map((c) => Math.round(Math.min(1, Math.max(0, c)) * 255).toString(16).padStart(2, '0')).join('');
}

function fromHex(h: string): number[] {
  return [1, 3, 5].map((i) => round(parseInt(h.slice(i, i + 2), 16) / 255));
}

export class RampWidget {
  readonly dom: HTMLDivElement;
  private svg: SVGSVGElement;
  private below: HTMLDivElement;
  private rows: Row[];
  private selected: number | null;
  private drag: { k: number; moved: boolean; id: number } | null = null;
  private range: [number, number] = [0, 1];
  /** A change in flight and the newest one waiting for it (a drag sends at most one at a time). */
  private sending = false;
  private queued: (() => unknown) | null = null;
  private queuedMerge = true;

  constructor(private o: RampWidgetOptions) {
    this.rows = o.rows.map((r) => ({ ...r }));
    this.selected = o.selected !== null && o.selected < this.rows.length ? o.selected : null;
    this.dom = document.createElement('div');
    this.dom.className = 'ramp' + (o.colour ? ' colour' : '');
    this.dom.tabIndex = 0;
    this.dom.dataset.place = o.place;
    this.svg = document.createElementNS(SVG, 'svg');
    this.svg.classList.add('ramp-plot');
    this.svg.setAttribute('height', String(o.colour ? STRIP + 22 : HEIGHT));
    this.below = document.createElement('div');
    this.below.className = 'ramp-key';
    this.dom.append(this.svg, this.below);
    this.svg.addEventListener('pointerdown', (e) => this.pointerDown(e));
    this.svg.addEventListener('pointermove', (e) => this.pointerMove(e));
    this.svg.addEventListener('pointerup', (e) => this.pointerUp(e));
    this.svg.addEventListener('pointercancel', (e) => this.pointerUp(e));
    this.dom.addEventListener('keydown', (e) => {
      if ((e.key === 'Delete' || e.key === 'Backspace') && this.selected !== null && !(e.target as HTMLElement).closest('input, select, textarea')) {
        // The panel's own Delete, not the network editor's.
        e.preventDefault();
        e.stopPropagation();
        this.remove(this.selected);
      }
    });
    if (typeof ResizeObserver !== 'undefined') new ResizeObserver(() => this.draw()).observe(this.svg);
    this.draw();
    this.drawFields();
  }

  private width(): number {
    return Math.max(120, this.svg.clientWidth || 280);
  }

  private ramp(): Ramp {
    return new Ramp(keysAt(this.rows, this.o.colour, this.o.frame), this.o.colour ? 3 : 1);
  }

  private x(pos: number): number {
    return PAD.left + pos * (this.width() - PAD.left - PAD.right);
  }

  private posAt(px: number): number {
    return Math.min(1, Math.max(0, (px - PAD.left) / (this.width() - PAD.left - PAD.right)));
  }

  private y(v: number): number {
    const [lo, hi] = this.range;
    return HEIGHT - PAD.bottom - ((v - lo) / (hi - lo)) * (HEIGHT - PAD.top - PAD.bottom);
  }

  private valueAt(py: number): number {
    const [lo, hi] = this.range;
    return lo + ((HEIGHT - PAD.bottom - py) / (HEIGHT - PAD.top - PAD.bottom)) * (hi - lo);
  }

  private el<K extends keyof SVGElementTagNameMap>(tag: K, attrs: Record<string, string | number>, parent: Element = this.svg): SVGElementTagNameMap[K] {
    const e = document.createElementNS(SVG, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
    parent.appendChild(e);
    return e;
  }

  /** The plot: grid, curve and keys (a float ramp), or the gradient and key markers (a colour ramp). */
  draw() {
    const w = this.width();
    this.svg.replaceChildren();
    const ramp = this.ramp();
    const keys = keysAt(this.rows, this.o.colour, this.o.frame);
    const title = (e: Element, text: string) => {
      const t = document.createElementNS(SVG, 'title');
      t.textContent = text;
      e.appendChild(t);
    };
    if (this.o.colour) {
      const grad = this.el('linearGradient', { id: `ramp-${this.o.place.replace(/[^A-Za-z0-9]/g, '_')}`, x1: 0, x2: 1, y1: 0, y2: 0 }, this.el('defs', {}));
      for (let i = 0; i <= 64; i++) this.el('stop', { offset: i / 64, 'stop-color': hex(ramp.eval(i / 64)) }, grad);
      this.el('rect', { x: PAD.left, y: 4, width: w - PAD.left - PAD.right, height: STRIP, fill: `url(#${grad.id})`, class: 'ramp-strip' });
      keys.forEach((k, i) => {
        const x = this.x(k.pos);
        const m = this.el('path', {
          d: `M${x} ${STRIP + 6} l6 10 h-12 z`,
          fill: hex(k.value as number[]),
          class: 'ramp-key-mark' + (i === this.selected ? ' selected' : ''),
          'data-key': i,
        });
        title(m, `key ${i}: ${k.pos} (${k.interp})`);
      });
      return;
    }
    // The value range holds while a key is dragged, so the plot does not move under the pointer.
    if (!this.drag) this.range = plotRange(ramp);
    for (const v of [0, 1]) {
      if (v >= this.range[0] && v <= this.range[1]) this.el('line', { x1: PAD.left, x2: w - PAD.right, y1: this.y(v), y2: this.y(v), class: 'ramp-grid' });
    }
    for (const p of [0, 0.25, 0.5, 0.75, 1]) this.el('line', { x1: this.x(p), x2: this.x(p), y1: PAD.top, y2: HEIGHT - PAD.bottom, class: 'ramp-grid' });
    const pts: string[] = [];
    const n = Math.max(50, Math.round((w - PAD.left - PAD.right) / 2));
    for (let i = 0; i <= n; i++) pts.push(`${this.x(i / n).toFixed(1)},${this.y(ramp.eval(i / n)[0]).toFixed(1)}`);
    this.el('polyline', { points: pts.join(' '), class: 'ramp-curve' });
    keys.forEach((k, i) => {
      const row = this.rows[i];
      const computed = !this.draggable(row.pos) || !this.draggable(row.value);
      const c = this.el('circle', {
        cx: this.x(k.pos),
        cy: this.y(k.value as number),
        r: 5,
        class: 'ramp-key-mark' + (i === this.selected ? ' selected' : '') + (computed ? ' computed' : ''),
        'data-key': i,
      });
      title(c, `key ${i}: ${round(k.pos)}, ${round(k.value as number)} (${k.interp})`);
    });
  }

  /** Whether a field is a constant a drag may move (channels and expressions stay as they are). */
  private draggable(v: unknown): boolean {
    return v === undefined || typeof v === 'number' || (Array.isArray(v) && v.every((c) => typeof c === 'number'));
  }

  /** The selected key's fields (position, value, interpolation) and its delete button, or a hint. */
  private drawFields() {
    this.below.replaceChildren();
    const k = this.selected;
    if (k === null || !this.rows[k]) {
      const hint = document.createElement('span');
      hint.className = 'dim';
      hint.textContent = `${this.rows.length} key${this.rows.length === 1 ? '' : 's'}: click the ${this.o.colour ? 'strip' : 'plot'} to add one, drag one to move it, select one to edit it.`;
      this.below.appendChild(hint);
      return;
    }
    const head = document.createElement('b');
    head.textContent = `key ${k}`;
    this.below.appendChild(head);
    const fields = document.createElement('div');
    fields.className = 'ramp-fields';
    this.o.fields(fields, this.rows[k], k, (row, merge) => {
      this.rows[k] = row;
      this.draw();
      return this.send(merge ?? false);
    });
    this.below.appendChild(fields);
    if (this.o.colour) {
      const pick = document.createElement('input');
      pick.type = 'color';
      pick.className = 'ramp-colour';
      pick.title = 'Pick the key colour';
      const v = keysAt([this.rows[k]], true, this.o.frame)[0].value as number[];
      pick.value = hex(v);
      pick.addEventListener('change', () => {
        this.rows[k] = { ...this.rows[k], value: fromHex(pick.value) };
        void this.send(false);
        this.draw();
      });
      fields.appendChild(pick);
    }
    const del = document.createElement('button');
    del.textContent = 'delete';
    del.className = 'ramp-delete';
    del.title = 'Remove this key (Delete)';
    del.disabled = this.rows.length <= 1;
    del.addEventListener('click', () => this.remove(k));
    this.below.appendChild(del);
  }

  private setSelected(k: number | null) {
    this.selected = k;
    this.o.select(k);
  }

  private send(merge: boolean): unknown {
    const rows = this.rows.map((r) => ({ ...r }));
    if (this.sending) {
      // A newer state replaces a waiting one, and opens an undo step if the one it replaces would have.
      const m = merge && this.queuedMerge;
      this.queuedMerge = m;
      this.queued = () => this.o.set(rows, m);
      return undefined;
    }
    const go = () => this.o.set(rows, merge);
    this.sending = true;
    const run = (f: () => unknown) => {
      void Promise.resolve(f()).finally(() => {
        const next = this.queued;
        this.queued = null;
        this.queuedMerge = true;
        if (next) run(next);
        else this.sending = false;
      });
    };
    run(go);
    return undefined;
  }

  private remove(k: number) {
    if (this.rows.length <= 1) return;
    this.rows.splice(k, 1);
    this.setSelected(null);
    void this.send(false);
    this.draw();
    this.drawFields();
  }

  private local(e: PointerEvent): [number, number] {
    const r = this.svg.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }

  private pointerDown(e: PointerEvent) {
    if (e.button !== 0) return;
    this.dom.focus({ preventScroll: true });
    e.preventDefault();
    const hit = (e.target as Element).closest('[data-key]');
    let k: number;
    let moved = false;
    if (hit) {
      k = Number(hit.getAttribute('data-key'));
    } else {
      // A click on the plot adds a key there (on a colour ramp, the colour there) and drags it.
      const [px, py] = this.local(e);
      const pos = round(this.posAt(px));
      const ramp = this.ramp();
      const sorted = keysAt(this.rows, this.o.colour, this.o.frame);
      const before = sorted.reduce<number | null>((best, key, i) => (key.pos <= pos && (best === null || key.pos >= sorted[best].pos) ? i : best), null);
      const interp = before !== null ? sorted[before].interp : (sorted[0]?.interp ?? 'linear');
      const value = this.o.colour ? ramp.eval(pos).map(round) : round(this.valueAt(py));
      this.rows.push({ pos, value, interp });
      k = this.rows.length - 1;
      void this.send(false);
      moved = true;
    }
    this.setSelected(k);
    this.drag = { k, moved, id: e.pointerId };
    this.dom.dataset.dragging = '1';
    this.svg.setPointerCapture(e.pointerId);
    this.draw();
    this.drawFields();
  }

  private pointerMove(e: PointerEvent) {
    const d = this.drag;
    if (!d || e.pointerId !== d.id) return;
    const [px, py] = this.local(e);
    const row = { ...this.rows[d.k] };
    if (this.draggable(row.pos)) row.pos = round(this.posAt(px));
    if (!this.o.colour && this.draggable(row.value)) row.value = round(this.valueAt(py));
    this.rows[d.k] = row;
    // The first move of a drag opens an undo step; the rest fold into it.
    void this.send(d.moved);
    d.moved = true;
    this.draw();
  }

  private pointerUp(e: PointerEvent) {
    const d = this.drag;
    if (!d || e.pointerId !== d.id) return;
    this.svg.releasePointerCapture(e.pointerId);
    this.drag = null;
    delete this.dom.dataset.dragging;
    this.drawFields();
    this.o.dragEnded();
  }
}
