// The curve editor: the selected node's animated components drawn over frames with the engine's own interpolation; keys dragged in frame and value, Bezier tangent handles dragged (tied unless Alt), each key's interpolation chosen, keys added by double-click and deleted with Delete; the wheel zooms (Shift: values), middle-drag pans, F frames, a label click hides its curve, the ruler sets the frame. Every change is one set_param of the whole parameter; a drag coalesces into one undo step.

import { evalChannel, slopeIn, slopeOut, type Interp, type Key } from './channel';
import { isChannel, nodeAt } from './network';
import type { AppStore } from './store';

export interface CurveActions {
  /** Sets a parameter's whole value; `merge` folds it into the previous undo step (a drag). */
  setParam(path: string, param: string, value: unknown, merge: boolean): Promise<boolean>;
  setFrame(frame: number): void;
}

/** One animated component of the node. */
export interface Curve {
  param: string;
  component: number;
  /** `size.x`, `radius`. */
  label: string;
  keys: Key[];
}

const AXES = ['x', 'y', 'z', 'w'];
const COLOURS = ['#ff7b72', '#7ee787', '#79c0ff', '#d2a8ff', '#ffa657', '#f2cc60'];
const SVG = 'http://www.w3.org/2000/svg';
const MARGIN = { left: 44, right: 10, top: 10, bottom: 20 };
/** How far (pixels) a tangent handle sits from its key. */
const HANDLE_PX = 40;

/** The animated components of a node's parameters, in parameter order. */
export function curvesOf(params: Record<string, unknown> | undefined): Curve[] {
  const out: Curve[] = [];
  for (const [param, value] of Object.entries(params ?? {})) {
    const comps = Array.isArray(value) ? value : [value];
    comps.forEach((c, component) => {
      if (!isChannel(c)) return;
      const label = comps.length > 1 ? `${param}.${AXES[component] ?? component}` : param;
      out.push({ param, component, label, keys: c.keys.map((k) => ({ ...k })) });
    });
  }
  return out;
}

/** The parameter's value with one component's keys replaced (sorted), as the document writes it. */
export function withKeys(value: unknown, component: number, keys: Key[]): unknown {
  const sorted = [...keys].sort((a, b) => a.frame - b.frame);
  const channel = { keys: sorted.map(clean) };
  if (!Array.isArray(value)) return channel;
  return value.map((c, i) => (i === component ? channel : c));
}

/** A hover text on an SVG element. */
function el_title(e: Element, text: string) {
  const t = document.createElementNS(SVG, 'title');
  t.textContent = text;
  e.appendChild(t);
}

/** A key without fields at their defaults (the document's form). */
function clean(k: Key): Key {
  const out: Key = { frame: k.frame, value: k.value };
  if (k.interp && k.interp !== 'linear') out.interp = k.interp;
  if (k.slope_in !== undefined) out.slope_in = k.slope_in;
  if (k.slope_out !== undefined) out.slope_out = k.slope_out;
  return out;
}

/** Round numbers for the document (six significant digits). */
function round(v: number): number {
  return Number(v.toPrecision(6));
}

interface Selection {
  curve: number;
  key: number;
}

type Drag =
  | { kind: 'key'; sel: Selection; moved: boolean }
  | { kind: 'handle'; sel: Selection; side: 'in' | 'out'; moved: boolean };

export class CurveEditor {
  private curves: Curve[] = [];
  private path: string | null = null;
  private selection: Selection | null = null;
  private drag: Drag | null = null;
  /** The view: frames and values at the plot's edges (kept while dragging so the plot does not jump). */
  private view = { f0: 1, f1: 100, v0: 0, v1: 1 };
  private svg: SVGSVGElement;
  private bar: HTMLElement;
  private shown = '';
  /** A change in flight and the newest one waiting for it (drags send at most one at a time). */
  private sending = false;
  private queued: (() => Promise<unknown>) | null = null;
  /** Set once the user zoomed or panned: the view then stays until F or another node. */
  private userView = false;
  /** Curves hidden by a click on their label, by label. */
  private hidden = new Set<string>();
  private pan: { x: number; y: number; view: { f0: number; f1: number; v0: number; v1: number } } | null = null;

  constructor(
    private host: HTMLElement,
    private store: AppStore,
    private actions: CurveActions,
  ) {
    host.classList.add('curves');
    host.tabIndex = 0;
    this.bar = document.createElement('div');
    this.bar.className = 'curve-bar';
    this.svg = document.createElementNS(SVG, 'svg');
    host.append(this.bar, this.svg);
    this.svg.addEventListener('pointerdown', (e) => this.pointerDown(e));
    this.svg.addEventListener('pointermove', (e) => this.pointerMove(e));
    this.svg.addEventListener('pointerup', (e) => this.pointerUp(e));
    this.svg.addEventListener('dblclick', (e) => this.addKey(e));
    host.addEventListener('keydown', (e) => {
      if ((e.key === 'Delete' || e.key === 'Backspace') && this.selection) {
        e.preventDefault();
        e.stopPropagation();
        this.deleteKey();
      }
      if (e.key === 'f' || e.key === 'F' || e.key === 'h' || e.key === 'H' || e.key === 'a') {
        // Frame the curves (the panel's own F/H, not the network editor's).
        e.preventDefault();
        e.stopPropagation();
        this.userView = false;
        this.fit();
        this.draw();
      }
    });
    this.svg.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
  }

  /** Redraws from the store unless a drag is under way (the drag draws its own state). */
  render() {
    if (this.drag || this.host.hidden) return;
    const s = this.store;
    const path = s.current;
    const node = path && s.state ? nodeAt(s.state.document, path) : null;
    const key = `${path}|${s.state?.version}|${s.state?.view.frame}|${s.range.join()}|${this.host.clientWidth}x${this.host.clientHeight}`;
    if (key === this.shown) return;
    this.shown = key;
    if (path !== this.path) {
      this.selection = null;
      this.userView = false;
      this.hidden.clear();
    }
    this.path = path;
    this.curves = curvesOf(node?.params);
    if (this.selection && !this.curves[this.selection.curve]?.keys[this.selection.key]) this.selection = null;
    if (!this.userView) this.fit();
    this.draw();
  }

  /** Frames: the timeline's range and every key; values: every curve's extent, padded. */
  private fit() {
    const [a, b] = this.store.range;
    let f0 = a;
    let f1 = b;
    const shown = this.curves.filter((c) => !this.hidden.has(c.label));
    for (const c of shown) {
      for (const k of c.keys) {
        f0 = Math.min(f0, k.frame);
        f1 = Math.max(f1, k.frame);
      }
    }
    if (f1 <= f0) f1 = f0 + 1;
    // A margin so the first and last keys sit inside the plot.
    const fm = (f1 - f0) * 0.03;
    [f0, f1] = [f0 - fm, f1 + fm];
    let v0 = Infinity;
    let v1 = -Infinity;
    for (const c of shown) {
      for (let i = 0; i <= 200; i++) {
        const v = evalChannel(c.keys, f0 + ((f1 - f0) * i) / 200);
        v0 = Math.min(v0, v);
        v1 = Math.max(v1, v);
      }
    }
    if (!Number.isFinite(v0)) [v0, v1] = [0, 1];
    if (v1 - v0 < 1e-9) [v0, v1] = [v0 - 1, v1 + 1];
    const pad = (v1 - v0) * 0.1;
    this.view = { f0, f1, v0: v0 - pad, v1: v1 + pad };
  }

  private size() {
    return { w: Math.max(200, this.host.clientWidth), h: Math.max(120, this.host.clientHeight - this.bar.offsetHeight) };
  }

  x(frame: number): number {
    const { w } = this.size();
    const { f0, f1 } = this.view;
    return MARGIN.left + ((frame - f0) / (f1 - f0)) * (w - MARGIN.left - MARGIN.right);
  }

  y(value: number): number {
    const { h } = this.size();
    const { v0, v1 } = this.view;
    return h - MARGIN.bottom - ((value - v0) / (v1 - v0)) * (h - MARGIN.top - MARGIN.bottom);
  }

  private frameAt(px: number): number {
    const { w } = this.size();
    const { f0, f1 } = this.view;
    return f0 + ((px - MARGIN.left) / (w - MARGIN.left - MARGIN.right)) * (f1 - f0);
  }

  private valueAt(py: number): number {
    const { h } = this.size();
    const { v0, v1 } = this.view;
    return v0 + ((h - MARGIN.bottom - py) / (h - MARGIN.top - MARGIN.bottom)) * (v1 - v0);
  }

  private el<K extends keyof SVGElementTagNameMap>(tag: K, attrs: Record<string, string | number>, parent: Element = this.svg) {
    const e = document.createElementNS(SVG, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
    parent.appendChild(e);
    return e;
  }

  private draw() {
    const { w, h } = this.size();
    this.svg.setAttribute('width', String(w));
    this.svg.setAttribute('height', String(h));
    this.svg.replaceChildren();
    this.drawBar();
    if (!this.curves.length) {
      const t = this.el('text', { x: 12, y: 24, class: 'curve-empty' });
      t.textContent = this.path ? 'No animated parameters: set a key with ◇ in the parameter panel.' : 'Select a node to see its curves.';
      return;
    }
    this.drawGrid();
    const frame = this.store.state?.view.frame ?? 1;
    this.el('line', { x1: this.x(frame), x2: this.x(frame), y1: MARGIN.top, y2: h - MARGIN.bottom, class: 'curve-now' });
    this.curves.forEach((c, ci) => {
      if (this.hidden.has(c.label)) return;
      const colour = COLOURS[ci % COLOURS.length];
      const pts: string[] = [];
      for (let px = MARGIN.left; px <= w - MARGIN.right; px += 2) pts.push(`${px},${this.y(evalChannel(c.keys, this.frameAt(px))).toFixed(1)}`);
      this.el('polyline', { points: pts.join(' '), class: 'curve-line', stroke: colour, 'data-curve': c.label });
      c.keys.forEach((k, ki) => {
        const selected = this.selection?.curve === ci && this.selection.key === ki;
        if (selected) this.drawHandles(ci, ki, colour);
        this.el('rect', {
          x: this.x(k.frame) - 4,
          y: this.y(k.value) - 4,
          width: 8,
          height: 8,
          fill: selected ? '#fff' : colour,
          class: 'curve-key' + (selected ? ' selected' : ''),
          'data-curve': ci,
          'data-key': ki,
        });
      });
    });
    this.curves.forEach((c, ci) => {
      const off = this.hidden.has(c.label);
      const t = this.el('text', { x: w - MARGIN.right - 4, y: MARGIN.top + 12 + ci * 14, 'text-anchor': 'end', fill: COLOURS[ci % COLOURS.length], class: 'curve-label' + (off ? ' off' : ''), 'data-label': c.label });
      t.textContent = c.label;
      el_title(t, off ? 'Hidden: click to show' : 'Click to hide');
    });
  }

  private drawGrid() {
    const { w, h } = this.size();
    const { f0, f1, v0, v1 } = this.view;
    const step = (span: number) => {
      const raw = span / 8;
      const p = 10 ** Math.floor(Math.log10(raw));
      return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw) ?? raw;
    };
    const fs = Math.max(1, step(f1 - f0));
    for (let f = Math.ceil(f0 / fs) * fs; f <= f1; f += fs) {
      this.el('line', { x1: this.x(f), x2: this.x(f), y1: MARGIN.top, y2: h - MARGIN.bottom, class: 'curve-grid' });
      const t = this.el('text', { x: this.x(f), y: h - 6, 'text-anchor': 'middle', class: 'curve-tick' });
      t.textContent = String(round(f));
    }
    const vs = step(v1 - v0);
    for (let v = Math.ceil(v0 / vs) * vs; v <= v1; v += vs) {
      this.el('line', { x1: MARGIN.left, x2: w - MARGIN.right, y1: this.y(v), y2: this.y(v), class: 'curve-grid' });
      const t = this.el('text', { x: MARGIN.left - 4, y: this.y(v) + 3, 'text-anchor': 'end', class: 'curve-tick' });
      t.textContent = String(round(v));
    }
  }

  /** Whether key `ki`'s incoming and outgoing tangents shape the curve (the segment on that side is Bezier). */
  private tangents(keys: Key[], ki: number): { in: boolean; out: boolean } {
    return { in: ki > 0 && keys[ki - 1].interp === 'bezier', out: ki < keys.length - 1 && keys[ki].interp === 'bezier' };
  }

  /** A handle's end: HANDLE_PX from the key along the slope, as drawn on screen. */
  private handleEnd(k: Key, slope: number, side: 'in' | 'out'): [number, number] {
    const dx = this.x(k.frame + 1) - this.x(k.frame);
    const dy = this.y(k.value + slope) - this.y(k.value);
    const len = Math.hypot(dx, dy) || 1;
    const s = side === 'out' ? 1 : -1;
    return [this.x(k.frame) + (s * HANDLE_PX * dx) / len, this.y(k.value) + (s * HANDLE_PX * dy) / len];
  }

  private drawHandles(ci: number, ki: number, colour: string) {
    const keys = this.curves[ci].keys;
    const k = keys[ki];
    const t = this.tangents(keys, ki);
    for (const side of ['in', 'out'] as const) {
      if (!t[side]) continue;
      const slope = side === 'in' ? slopeIn(keys, ki) : slopeOut(keys, ki);
      const [hx, hy] = this.handleEnd(k, slope, side);
      this.el('line', { x1: this.x(k.frame), y1: this.y(k.value), x2: hx, y2: hy, stroke: colour, class: 'curve-tangent' });
      this.el('circle', { cx: hx, cy: hy, r: 4, class: 'curve-handle', 'data-side': side, 'data-curve': ci, 'data-key': ki });
    }
  }

  private drawBar() {
    this.bar.replaceChildren();
    const sel = this.selection;
    const c = sel ? this.curves[sel.curve] : null;
    const k = sel && c ? c.keys[sel.key] : null;
    if (!c || !k || !sel) {
      const hint = document.createElement('span');
      hint.className = 'dim';
      hint.textContent = this.curves.length ? 'Click a key to edit it; double-click a curve to add one.' : '';
      this.bar.appendChild(hint);
      return;
    }
    const label = document.createElement('b');
    label.textContent = `${c.label} key ${sel.key + 1}/${c.keys.length}`;
    const field = (name: string, v: number, apply: (x: number) => void) => {
      const l = document.createElement('label');
      l.textContent = `${name} `;
      const i = document.createElement('input');
      i.type = 'number';
      i.className = `curve-${name}`;
      i.value = String(round(v));
      i.step = 'any';
      i.addEventListener('change', () => Number.isFinite(Number(i.value)) && apply(Number(i.value)));
      l.appendChild(i);
      return l;
    };
    const interp = document.createElement('select');
    interp.className = 'curve-interp';
    interp.title = 'How the curve goes from this key to the next';
    for (const m of ['constant', 'linear', 'bezier', 'ease'] as Interp[]) {
      const o = document.createElement('option');
      o.value = o.textContent = m;
      interp.appendChild(o);
    }
    interp.value = k.interp ?? 'linear';
    interp.addEventListener('change', () => this.changeKey(sel, (key) => ({ ...key, interp: interp.value as Interp }), false));
    const flat = document.createElement('button');
    flat.textContent = 'auto';
    flat.title = 'Automatic tangents (clears the slopes set by hand)';
    flat.addEventListener('click', () => this.changeKey(sel, (key) => ({ ...key, slope_in: undefined, slope_out: undefined }), false));
    const del = document.createElement('button');
    del.textContent = 'delete';
    del.title = 'Delete this key (Delete)';
    del.addEventListener('click', () => this.deleteKey());
    this.bar.append(
      label,
      field('frame', k.frame, (f) => this.changeKey(sel, (key) => ({ ...key, frame: this.freeFrame(c.keys, sel.key, f) }), false)),
      field('value', k.value, (v) => this.changeKey(sel, (key) => ({ ...key, value: v }), false)),
      interp,
      flat,
      del,
    );
  }

  /** The nearest frame to `f` that no other key of the curve holds, between its neighbours (keys keep their order). */
  private freeFrame(keys: Key[], ki: number, f: number): number {
    const lo = ki > 0 ? keys[ki - 1].frame + 1e-3 : -Infinity;
    const hi = ki < keys.length - 1 ? keys[ki + 1].frame - 1e-3 : Infinity;
    return Math.min(hi, Math.max(lo, f));
  }

  /** Applies `change` to the selected key and sends the parameter (at most one send in flight). */
  private changeKey(sel: Selection, change: (k: Key) => Key, merge: boolean) {
    const c = this.curves[sel.curve];
    c.keys[sel.key] = change(c.keys[sel.key]);
    this.send(c, merge);
    this.draw();
  }

  private send(c: Curve, merge: boolean) {
    const path = this.path;
    const node = path && this.store.state ? nodeAt(this.store.state.document, path) : null;
    if (!path || !node) return;
    const value = withKeys(node.params?.[c.param], c.component, c.keys);
    const go = () => this.actions.setParam(path, c.param, value, merge);
    if (this.sending) {
      this.queued = go;
      return;
    }
    this.sending = true;
    const run = (f: () => Promise<unknown>) => {
      void f().finally(() => {
        const next = this.queued;
        this.queued = null;
        if (next) run(next);
        else this.sending = false;
      });
    };
    run(go);
  }

  private target(e: Event): { ci: number; ki: number; side?: 'in' | 'out' } | null {
    const t = e.target as Element;
    if (!t.matches('.curve-key, .curve-handle')) return null;
    return { ci: Number(t.getAttribute('data-curve')), ki: Number(t.getAttribute('data-key')), side: (t.getAttribute('data-side') as 'in' | 'out') ?? undefined };
  }

  private pointerDown(e: PointerEvent) {
    this.host.focus();
    const label = (e.target as Element).getAttribute('data-label');
    if (label) {
      if (this.hidden.has(label)) this.hidden.delete(label);
      else this.hidden.add(label);
      if (this.selection && this.curves[this.selection.curve]?.label === label) this.selection = null;
      this.draw();
      return;
    }
    if (e.button === 1 || (e.button === 0 && e.altKey && !this.target(e))) {
      this.pan = { x: e.clientX, y: e.clientY, view: { ...this.view } };
      this.svg.setPointerCapture(e.pointerId);
      return;
    }
    const r = this.svg.getBoundingClientRect();
    if (e.clientY - r.top > this.size().h - MARGIN.bottom) {
      // The frame ruler under the plot sets the frame, as a timeline does.
      this.actions.setFrame(Math.round(this.frameAt(e.clientX - r.left)));
      return;
    }
    const hit = this.target(e);
    if (!hit) {
      if (this.selection) {
        this.selection = null;
        this.draw();
      }
      return;
    }
    const sel = { curve: hit.ci, key: hit.ki };
    this.selection = sel;
    this.svg.setPointerCapture(e.pointerId);
    this.drag = hit.side ? { kind: 'handle', sel, side: hit.side, moved: false } : { kind: 'key', sel, moved: false };
    this.draw();
  }

  private pointerMove(e: PointerEvent) {
    if (this.pan) {
      const { w, h } = this.size();
      const p = this.pan;
      const df = ((e.clientX - p.x) / (w - MARGIN.left - MARGIN.right)) * (p.view.f1 - p.view.f0);
      const dv = ((e.clientY - p.y) / (h - MARGIN.top - MARGIN.bottom)) * (p.view.v1 - p.view.v0);
      this.view = { f0: p.view.f0 - df, f1: p.view.f1 - df, v0: p.view.v0 + dv, v1: p.view.v1 + dv };
      this.userView = true;
      this.draw();
      return;
    }
    const d = this.drag;
    if (!d) return;
    const r = this.svg.getBoundingClientRect();
    const px = e.clientX - r.left;
    const py = e.clientY - r.top;
    const c = this.curves[d.sel.curve];
    const merge = d.moved;
    d.moved = true;
    if (d.kind === 'key') {
      // Whole frames unless Shift is held, as Houdini snaps keys to frames.
      const raw = this.frameAt(px);
      const f = this.freeFrame(c.keys, d.sel.key, e.shiftKey ? round(raw) : Math.round(raw));
      this.changeKey(d.sel, (k) => ({ ...k, frame: f, value: round(this.valueAt(py)) }), merge);
    } else {
      const k = c.keys[d.sel.key];
      const df = this.frameAt(px) - k.frame;
      const dv = this.valueAt(py) - k.value;
      // A handle dragged past its key's frame stays on its side.
      const along = d.side === 'out' ? Math.max(df, 1e-3) : Math.min(df, -1e-3);
      const slope = round(dv / along);
      this.changeKey(
        d.sel,
        (key) => (e.altKey ? { ...key, [d.side === 'out' ? 'slope_out' : 'slope_in']: slope } : { ...key, slope_in: slope, slope_out: slope }),
        merge,
      );
    }
  }

  private pointerUp(e: PointerEvent) {
    if (this.pan) {
      this.pan = null;
      this.svg.releasePointerCapture(e.pointerId);
      return;
    }
    if (!this.drag) return;
    this.svg.releasePointerCapture(e.pointerId);
    this.drag = null;
  }

  /** The wheel zooms the frames about the mouse; with Shift or Ctrl, the values. */
  private wheel(e: WheelEvent) {
    e.preventDefault();
    const r = this.svg.getBoundingClientRect();
    const k = Math.exp(e.deltaY * 0.0015);
    const v = this.view;
    if (e.shiftKey || e.ctrlKey) {
      const at = this.valueAt(e.clientY - r.top);
      this.view = { ...v, v0: at + (v.v0 - at) * k, v1: at + (v.v1 - at) * k };
    } else {
      const at = this.frameAt(e.clientX - r.left);
      this.view = { ...v, f0: at + (v.f0 - at) * k, f1: at + (v.f1 - at) * k };
    }
    this.userView = true;
    this.draw();
  }

  /** Double-click: a key on the nearest curve at that frame, on the curve. */
  private addKey(e: MouseEvent) {
    if (!this.curves.length || this.target(e)) return;
    const r = this.svg.getBoundingClientRect();
    const f = Math.round(this.frameAt(e.clientX - r.left));
    const py = e.clientY - r.top;
    let best = this.curves.findIndex((c) => !this.hidden.has(c.label));
    if (best < 0) return;
    this.curves.forEach((c, i) => {
      if (this.hidden.has(c.label)) return;
      if (Math.abs(this.y(evalChannel(c.keys, f)) - py) < Math.abs(this.y(evalChannel(this.curves[best].keys, f)) - py)) best = i;
    });
    const c = this.curves[best];
    if (c.keys.some((k) => k.frame === f)) return;
    const at = c.keys.findIndex((k) => k.frame > f);
    const prev = at === -1 ? c.keys.length - 1 : at - 1;
    // The new key takes the interpolation around it, so the curve keeps its kind.
    const key: Key = { frame: f, value: round(evalChannel(c.keys, f)), interp: prev >= 0 ? c.keys[prev].interp : undefined };
    c.keys.splice(at === -1 ? c.keys.length : at, 0, key);
    this.selection = { curve: best, key: at === -1 ? c.keys.length - 1 : at };
    this.send(c, false);
    this.draw();
  }

  private deleteKey() {
    const sel = this.selection;
    if (!sel) return;
    const c = this.curves[sel.curve];
    if (c.keys.length <= 1) return;
    c.keys.splice(sel.key, 1);
    this.selection = null;
    this.send(c, false);
    this.draw();
  }
}
