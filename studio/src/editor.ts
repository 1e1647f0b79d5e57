// The network editor: nodes with typed ports and wires in SVG, pan and zoom, box select, drag to move and to wire, flags, badges (cook time, cache hit, progress, error, warning), rename, dive into subnets.

import { boxFrame, drawAnnotations, freshId, newNote, pickColor, type Annotation } from './annotations';
import { join, layout, networkAt, nodeAt, NODE_H, NODE_W, parentOf, wires } from './network';
import { freshCookErrors, hasNetwork, uniqueProblems } from './protocol';
import type { DocNetwork, DocNode } from './protocol';
import type { AppStore } from './store';

/** The smallest zoom the automatic framing goes to: node names stay readable (about 9 px). */
const MIN_FIT_ZOOM = 0.85;

const SVG = 'http://www.w3.org/2000/svg';
/** An inner input's marker (`@0`, `@meta`) inside a subnet or block. */
const MARKER_W = 64;
const MARKER_H = 22;

export interface EditorActions {
  edit(edit: Record<string, unknown>): Promise<boolean>;
  view(path: string | null): void;
  select(paths: string[], current?: string | null): void;
  openTabMenu(x: number, y: number, at: [number, number]): void;
  /** Middle-click on a node: its info panel. */
  info(path: string): void;
}

function el<K extends keyof SVGElementTagNameMap>(tag: K, attrs: Record<string, string | number>, parent?: Element) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  parent?.appendChild(e);
  return e;
}

type Drag =
  | { kind: 'pan'; x: number; y: number; tx: number; ty: number; node?: string }
  | { kind: 'move'; x: number; y: number; start: Map<string, [number, number]>; moved: boolean }
  | { kind: 'box'; x0: number; y0: number; x1: number; y1: number; add: boolean }
  | { kind: 'wire'; from: string; x: number; y: number }
  | { kind: 'note'; id: string; x: number; y: number; start: [number, number]; resize: boolean; moved: boolean };

export class NetworkEditor {
  readonly svg: SVGSVGElement;
  private root: SVGGElement;
  private tx = 0;
  private ty = 0;
  private zoom = 1;
  private drag: Drag | null = null;
  private positions = new Map<string, [number, number]>();
  /** Inside a subnet or block: the enclosing node's inputs (`@0`, `@1`.., `@meta`) as markers above the nodes, wired from like outputs. */
  private markers = new Map<string, [number, number]>();
  /** Automatic positions given to nodes the file places nowhere, by network path. */
  private autoPositions = new Map<string, Map<string, [number, number]>>();
  /** Positions moved locally, until the document confirms them. */
  private pending = new Map<string, [number, number]>();
  private framedAt: string | null = null;
  private mouse: [number, number] = [0, 0];
  private mouseAt: [number, number] | null = null;
  private lastNoteDown: { id: string; at: number } | null = null;
  /** The selected note or box (nodes are the store's selection). */
  private picked: Annotation | null = null;
  /** A note's or resized note's geometry while dragged, until the document has it. */
  private notePending = new Map<string, { pos: [number, number]; size: [number, number] }>();

  constructor(
    private host: HTMLElement,
    private store: AppStore,
    private actions: EditorActions,
  ) {
    this.svg = el('svg', { class: 'net-svg', tabindex: 0 }) as SVGSVGElement;
    host.appendChild(this.svg);
    this.root = el('g', {}, this.svg);
    this.svg.addEventListener('wheel', (e) => this.onWheel(e), { passive: false });
    this.svg.addEventListener('pointerdown', (e) => this.onDown(e));
    window.addEventListener('pointermove', (e) => this.onMove(e));
    window.addEventListener('pointerup', (e) => this.onUp(e));
    this.svg.addEventListener('pointermove', (e) => {
      this.mouse = this.toWorld(e.clientX, e.clientY);
      this.mouseAt = [e.clientX, e.clientY];
    });
    this.svg.addEventListener('pointerleave', () => (this.mouseAt = null));
    this.svg.addEventListener('dblclick', (e) => this.onDoubleClick(e));
  }

  /** The world position under the mouse (where the Tab menu puts a node). */
  mouseWorld(): [number, number] {
    return this.mouse;
  }

  /** The mouse in page coordinates while it is over the editor (where the Tab menu opens). */
  mouseClient(): [number, number] | null {
    return this.mouseAt;
  }

  private net(): DocNetwork | null {
    const s = this.store.state;
    return s ? networkAt(s.document, this.store.at) : null;
  }

  private toWorld(cx: number, cy: number): [number, number] {
    const r = this.svg.getBoundingClientRect();
    return [(cx - r.left - this.tx) / this.zoom, (cy - r.top - this.ty) / this.zoom];
  }

  private apply() {
    this.root.setAttribute('transform', `translate(${this.tx},${this.ty}) scale(${this.zoom})`);
  }

  /**
   * Fits every node (or the selected ones) in view, as Houdini's H; `readable`
   * (the automatic framing when a network opens) stops at a zoom where names
   * can be read, centred on the node that matters.
   */
  frame(selectedOnly = false, readable = false) {
    const names = [...this.positions.keys()].filter((n) => !selectedOnly || this.store.selected.has(join(this.store.at, n)));
    const r = this.svg.getBoundingClientRect();
    if (!names.length || r.width === 0) return;
    const xs = names.map((n) => this.positions.get(n)![0]);
    const ys = names.map((n) => this.positions.get(n)![1]);
    let [x0, x1] = [Math.min(...xs) - 40, Math.max(...xs) + NODE_W + 140];
    let [y0, y1] = [Math.min(...ys) - 40, Math.max(...ys) + NODE_H + 40];
    // Frame all takes the inner inputs' markers in too.
    for (const [x, y] of selectedOnly ? [] : this.markers.values()) {
      [x0, y0] = [Math.min(x0, x - 40), Math.min(y0, y - 20)];
    }
    // Frame all takes the notes in too (their corners must stay reachable).
    for (const n of selectedOnly ? [] : Object.values(this.net()?.notes ?? {})) {
      [x0, x1] = [Math.min(x0, n.pos[0] - 20), Math.max(x1, n.pos[0] + n.size[0] + 20)];
      [y0, y1] = [Math.min(y0, n.pos[1] - 20), Math.max(y1, n.pos[1] + n.size[1] + 20)];
    }
    const fit = Math.min(1.5, Math.min(r.width / (x1 - x0), r.height / (y1 - y0)));
    this.zoom = readable ? Math.max(MIN_FIT_ZOOM, fit) : fit;
    this.tx = (r.width - (x1 - x0) * this.zoom) / 2 - x0 * this.zoom;
    this.ty = (r.height - (y1 - y0) * this.zoom) / 2 - y0 * this.zoom;
    if (readable && fit < MIN_FIT_ZOOM) {
      // Too many to read at once: readable, centred on the node that matters.
      const s = this.store;
      const viewed = s.state?.view.solo ?? s.state?.output ?? null;
      const focus = [s.current, viewed].find((p) => p && parentOf(p) === s.at && this.positions.has(p.slice(p.lastIndexOf('/') + 1)));
      const [fx, fy] = focus ? this.positions.get(focus.slice(focus.lastIndexOf('/') + 1))! : [(x0 + x1) / 2 - NODE_W / 2, y0 + 40];
      this.tx = r.width / 2 - (fx + NODE_W / 2) * this.zoom;
      this.ty = r.height / 2 - (fy + NODE_H / 2) * this.zoom;
    }
    this.apply();
  }

  private onWheel(e: WheelEvent) {
    e.preventDefault();
    const r = this.svg.getBoundingClientRect();
    const [mx, my] = [e.clientX - r.left, e.clientY - r.top];
    const k = Math.exp(-e.deltaY * 0.0015);
    const z = Math.min(4, Math.max(0.1, this.zoom * k));
    this.tx = mx - ((mx - this.tx) * z) / this.zoom;
    this.ty = my - ((my - this.ty) * z) / this.zoom;
    this.zoom = z;
    this.apply();
  }

  private target(e: Event): { node?: string; port?: string; input?: number; flag?: string } {
    const t = (e.target as Element).closest('[data-node]');
    if (!t) return {};
    const d = (e.target as Element).closest('[data-port],[data-input],[data-flag]') as HTMLElement | null;
    return {
      node: t.getAttribute('data-node') ?? undefined,
      port: d?.getAttribute('data-port') ?? undefined,
      input: d?.hasAttribute('data-input') ? Number(d.getAttribute('data-input')) : undefined,
      flag: d?.getAttribute('data-flag') ?? undefined,
    };
  }

  private onDown(e: PointerEvent) {
    this.svg.focus();
    const t = this.target(e);
    const [wx, wy] = this.toWorld(e.clientX, e.clientY);
    if (e.button === 1 || (e.button === 0 && e.altKey)) {
      // A middle-click that does not move is Houdini's node info.
      this.drag = { kind: 'pan', x: e.clientX, y: e.clientY, tx: this.tx, ty: this.ty, node: e.button === 1 ? t.node : undefined };
      return;
    }
    if (e.button !== 0) return;
    const marker = (e.target as Element).closest('[data-marker]')?.getAttribute('data-marker');
    if (marker) {
      this.drag = { kind: 'wire', from: marker, x: wx, y: wy };
      return;
    }
    if (!t.node && this.annotationDown(e, wx, wy)) return;
    this.picked = null;
    if (!t.node) {
      this.drag = { kind: 'box', x0: wx, y0: wy, x1: wx, y1: wy, add: e.shiftKey };
      return;
    }
    const path = join(this.store.at, t.node);
    if (t.flag === 'display') {
      void this.actions.edit({ kind: 'set_flag', path, flag: 'display', on: true });
      return;
    }
    if (t.flag === 'template') {
      const node = this.net()?.nodes[t.node];
      void this.actions.edit({ kind: 'set_flag', path, flag: 'template', on: !node?.template });
      return;
    }
    if (t.flag === 'bypass') {
      const node = this.net()?.nodes[t.node];
      void this.actions.edit({ kind: 'set_flag', path, flag: 'bypass', on: !node?.bypass });
      return;
    }
    if (t.port === 'out') {
      this.drag = { kind: 'wire', from: t.node, x: wx, y: wy };
      return;
    }
    if (t.input !== undefined) {
      // Dragging off a connected input picks its wire up.
      const from = this.net()?.nodes[t.node]?.inputs?.[t.input];
      if (from) {
        void this.actions.edit({ kind: 'disconnect', to: path, input: t.input });
        this.drag = { kind: 'wire', from, x: wx, y: wy };
      }
      return;
    }
    const sel = new Set(this.store.selected);
    if (e.shiftKey) {
      if (sel.has(path)) sel.delete(path);
      else sel.add(path);
    } else if (!sel.has(path)) {
      sel.clear();
      sel.add(path);
    }
    this.actions.select([...sel], path);
    const start = new Map<string, [number, number]>();
    for (const p of sel) {
      const name = p.slice(p.lastIndexOf('/') + 1);
      const at = this.positions.get(name);
      if (at) start.set(name, [...at] as [number, number]);
    }
    this.drag = { kind: 'move', x: wx, y: wy, start, moved: false };
  }

  private onMove(e: PointerEvent) {
    const d = this.drag;
    if (!d) return;
    const [wx, wy] = this.toWorld(e.clientX, e.clientY);
    if (d.kind === 'pan') {
      this.tx = d.tx + e.clientX - d.x;
      this.ty = d.ty + e.clientY - d.y;
      this.apply();
    } else if (d.kind === 'move') {
      const [dx, dy] = [wx - d.x, wy - d.y];
      if (Math.abs(dx) + Math.abs(dy) > 2) d.moved = true;
      for (const [n, [x, y]] of d.start) this.pending.set(n, [x + dx, y + dy]);
      this.render();
    } else if (d.kind === 'box') {
      d.x1 = wx;
      d.y1 = wy;
      this.render();
    } else if (d.kind === 'wire') {
      d.x = wx;
      d.y = wy;
      this.render();
    } else if (d.kind === 'note') {
      const note = this.net()?.notes?.[d.id];
      if (!note) return;
      const [dx, dy] = [wx - d.x, wy - d.y];
      if (Math.abs(dx) + Math.abs(dy) > 2) d.moved = true;
      const moved = d.resize
        ? { pos: note.pos, size: [Math.max(60, d.start[0] + dx), Math.max(30, d.start[1] + dy)] as [number, number] }
        : { pos: [d.start[0] + dx, d.start[1] + dy] as [number, number], size: note.size };
      this.notePending.set(d.id, moved);
      this.render();
    }
  }

  private onUp(e: PointerEvent) {
    const d = this.drag;
    this.drag = null;
    if (!d) return;
    if (d.kind === 'pan' && d.node && Math.hypot(e.clientX - d.x, e.clientY - d.y) < 4) {
      this.actions.info(join(this.store.at, d.node));
      return;
    }
    if (d.kind === 'note') {
      const note = this.net()?.notes?.[d.id];
      const moved = this.notePending.get(d.id);
      if (d.moved && note && moved) {
        const round = (p: [number, number]): [number, number] => [Math.round(p[0]), Math.round(p[1])];
        void this.actions.edit({ kind: 'set_note', parent: this.store.at, id: d.id, note: { ...note, pos: round(moved.pos), size: round(moved.size) } }).finally(() => {
          this.notePending.delete(d.id);
          this.render();
        });
      } else this.notePending.delete(d.id);
      return;
    }
    if (d.kind === 'move' && d.moved) {
      const positions: Record<string, [number, number]> = {};
      for (const n of d.start.keys()) positions[join(this.store.at, n)] = this.pending.get(n)!;
      void this.actions.edit({ kind: 'move', positions });
    } else if (d.kind === 'box') {
      const [x0, x1] = [Math.min(d.x0, d.x1), Math.max(d.x0, d.x1)];
      const [y0, y1] = [Math.min(d.y0, d.y1), Math.max(d.y0, d.y1)];
      const hit = [...this.positions]
        .filter(([, [x, y]]) => x + NODE_W > x0 && x < x1 && y + NODE_H > y0 && y < y1)
        .map(([n]) => join(this.store.at, n));
      const sel = d.add ? new Set([...this.store.selected, ...hit]) : new Set(hit);
      this.actions.select([...sel], hit[0] ?? (sel.size ? this.store.current : null));
      this.render();
    } else if (d.kind === 'wire') {
      const t = this.target(e);
      if (t.node && t.node !== d.from) {
        const node = this.net()?.nodes[t.node];
        const input = t.input ?? firstFreeInput(node, this.store.catalogue.get(node?.type ?? '')?.inputs.length ?? 1);
        void this.actions.edit({ kind: 'connect', from: join(this.store.at, d.from), to: join(this.store.at, t.node), input });
      }
      this.render();
    }
  }

  private onDoubleClick(e: MouseEvent) {
    const t = this.target(e);
    if (!t.node) return;
    const node = this.net()?.nodes[t.node];
    if ((e.target as Element).closest('.node-name')) {
      this.rename(t.node);
    } else if (hasNetwork(node, this.store.catalogue)) {
      this.dive(join(this.store.at, t.node));
    }
  }

  /** Shows the network inside a subnet. */
  dive(path: string) {
    if (!hasNetwork(nodeAt(this.store.state!.document, path), this.store.catalogue)) return;
    this.store.at = path;
    this.actions.select([], null);
  }

  /** Back to the network containing this one. */
  up() {
    if (this.store.at === '/') return;
    const at = this.store.at;
    this.store.at = at.slice(0, at.lastIndexOf('/')) || '/';
    this.actions.select([at], at);
  }

  /** An inline text field over the node's name. */
  rename(name: string) {
    const p = this.positions.get(name);
    if (!p) return;
    const r = this.svg.getBoundingClientRect();
    const hr = this.host.getBoundingClientRect();
    const input = document.createElement('input');
    input.className = 'rename';
    input.value = name;
    input.style.left = `${r.left - hr.left + this.tx + p[0] * this.zoom}px`;
    input.style.top = `${r.top - hr.top + this.ty + p[1] * this.zoom}px`;
    this.host.appendChild(input);
    input.focus();
    input.select();
    let done = false;
    const finish = async (commit: boolean) => {
      if (done) return;
      done = true;
      const to = input.value.trim();
      input.remove();
      if (commit && to && to !== name) {
        const path = join(this.store.at, name);
        if (await this.actions.edit({ kind: 'rename', path, name: to })) {
          this.actions.select([join(this.store.at, to)], join(this.store.at, to));
        }
      }
      this.svg.focus();
    };
    input.addEventListener('keydown', (e) => {
      e.stopPropagation();
      if (e.key === 'Enter') void finish(true);
      if (e.key === 'Escape') void finish(false);
    });
    input.addEventListener('blur', () => void finish(true));
  }

  render() {
    const net = this.net();
    this.root.replaceChildren();
    if (!net) return;
    // Automatic positions stay put once shown (per network), so adding a node moves nothing.
    const kept = this.autoPositions.get(this.store.at);
    this.positions = layout(net, kept);
    const auto = new Map<string, [number, number]>();
    for (const [n, p] of this.positions) if (!net.nodes[n]?.ui?.pos) auto.set(n, p);
    this.autoPositions.set(this.store.at, auto);
    for (const [n, p] of this.pending) {
      const doc = net.nodes[n]?.ui?.pos;
      if (this.drag?.kind === 'move' || !doc || doc[0] !== p[0] || doc[1] !== p[1]) {
        if (net.nodes[n]) this.positions.set(n, p);
      }
      if (!this.drag && doc && Math.abs(doc[0] - p[0]) < 0.11 && Math.abs(doc[1] - p[1]) < 0.11) this.pending.delete(n);
    }
    this.markers = this.innerInputs(net);
    if (this.framedAt !== this.store.at && this.positions.size) {
      this.framedAt = this.store.at;
      this.frame(false, true);
    }
    const boxLayer = el('g', { class: 'boxes' }, this.root);
    // Notes sit behind the wires and nodes, as in Houdini: they never hide a node.
    const noteLayer = el('g', { class: 'notes' }, this.root);
    const wireLayer = el('g', { class: 'wires' }, this.root);
    for (const w of wires(net)) {
      const a = this.outPort(w.from);
      const b = this.positions.get(w.to);
      if (!a || !b) continue;
      const count = Math.max(net.nodes[w.to].inputs?.length ?? 1, this.inputsOf(net.nodes[w.to]));
      drawWire(wireLayer, a, [b[0] + portX(w.input, count), b[1]], `wire from-${w.from} to-${w.to}`);
    }
    for (const [name, at] of this.markers) this.drawMarker(name, at);
    const failed = this.readsFailed(net);
    for (const [name, node] of Object.entries(net.nodes)) this.drawNode(name, node, this.positions.get(name)!, failed.get(name));
    const notes = { ...net.notes };
    for (const [id, p] of this.notePending) if (notes[id]) notes[id] = { ...notes[id], ...p };
    if (this.picked && !(this.picked.kind === 'note' ? notes[this.picked.id] : net.boxes?.[this.picked.id])) this.picked = null;
    drawAnnotations(boxLayer, noteLayer, { ...net, notes }, this.positions, this.picked);
    const d = this.drag;
    if (d?.kind === 'wire') {
      const a = this.outPort(d.from);
      if (a) drawWire(this.root, a, [d.x, d.y], 'wire live');
    }
    if (d?.kind === 'box') {
      el('rect', { class: 'box-select', x: Math.min(d.x0, d.x1), y: Math.min(d.y0, d.y1), width: Math.abs(d.x1 - d.x0), height: Math.abs(d.y1 - d.y0) }, this.root);
    }
  }

  /** Where wires from `from` start: a node's output, or an inner input's marker. */
  private outPort(from: string): [number, number] | null {
    const a = this.positions.get(from);
    if (a) return [a[0] + NODE_W / 2, a[1] + NODE_H];
    const m = this.markers.get(from);
    return m ? [m[0] + MARKER_W / 2, m[1] + MARKER_H] : null;
  }

  /**
   * Inside a subnet or block, its inputs as markers in a row above the
   * nodes (Houdini's subnet input connectors): `@0` to the last input the
   * node has or the network reads, and `@meta` in a block.
   */
  private innerInputs(net: DocNetwork): Map<string, [number, number]> {
    const out = new Map<string, [number, number]>();
    const at = this.store.at;
    if (at === '/' || !this.store.state) return out;
    const holder = nodeAt(this.store.state.document, at);
    if (!holder) return out;
    let count = Math.max(1, holder.inputs?.length ?? 0);
    let meta = this.store.catalogue.get(holder.type)?.meta ?? false;
    for (const node of Object.values(net.nodes)) {
      for (const from of node.inputs ?? []) {
        const n = from?.match(/^@(\d+)$/);
        if (n) count = Math.max(count, Number(n[1]) + 1);
        if (from === '@meta') meta = true;
      }
    }
    const names = [...Array.from({ length: count }, (_, i) => `@${i}`), ...(meta ? ['@meta'] : [])];
    const placed = [...this.positions.values()];
    const left = placed.length ? Math.min(...placed.map((p) => p[0])) : 0;
    const top = placed.length ? Math.min(...placed.map((p) => p[1])) : 0;
    names.forEach((n, i) => out.set(n, [left + i * (MARKER_W + 16), top - MARKER_H - 60]));
    return out;
  }

  private drawMarker(name: string, [x, y]: [number, number]) {
    const g = el('g', { class: 'inner-input', transform: `translate(${x},${y})`, 'data-marker': name }, this.root);
    el('rect', { class: 'body', width: MARKER_W, height: MARKER_H, rx: 11 }, g);
    const label = el('text', { class: 'node-name', x: MARKER_W / 2, y: 15, 'text-anchor': 'middle' }, g);
    label.textContent = name;
    el('circle', { class: 'port out', cx: MARKER_W / 2, cy: MARKER_H, r: 5, 'data-marker': name }, g);
    el('title', {}, g).textContent =
      name === '@meta' ? "the block's pass: detail attributes iteration, numiterations, value (drag to an input to wire it)" : `the enclosing node's input ${Number(name.slice(1)) + 1} (in a block, @0 is the piece or feedback; drag to an input to wire it)`;
  }

  /** A press on a note (move, or resize at its corner) or a box's label (moves its nodes); true when it took the press. */
  private annotationDown(e: PointerEvent, wx: number, wy: number): boolean {
    const t = e.target as Element;
    const net = this.net();
    const note = t.closest('[data-note]')?.getAttribute('data-note');
    if (note && net?.notes?.[note]) {
      // The redraw below replaces the note under the mouse, so a double-click is told by time.
      const now = performance.now();
      if (this.lastNoteDown?.id === note && now - this.lastNoteDown.at < 400 && !t.hasAttribute('data-note-resize')) {
        this.lastNoteDown = null;
        // The press would take the focus back from the text field.
        e.preventDefault();
        setTimeout(() => this.writeNote(note), 0);
        return true;
      }
      this.lastNoteDown = { id: note, at: now };
      this.picked = { kind: 'note', id: note };
      const n = net.notes[note];
      const resize = t.hasAttribute('data-note-resize');
      this.drag = { kind: 'note', id: note, x: wx, y: wy, start: resize ? [...n.size] : [...n.pos], resize, moved: false };
      this.actions.select([], null);
      this.render();
      return true;
    }
    const bar = t.getAttribute('data-box-bar');
    const box = bar ?? t.closest('[data-box]')?.getAttribute('data-box');
    if (bar && net?.boxes?.[bar]) {
      const now = performance.now();
      if (this.lastNoteDown?.id === `box:${bar}` && now - this.lastNoteDown.at < 400) {
        this.lastNoteDown = null;
        e.preventDefault();
        setTimeout(() => this.renameBox(bar), 0);
        return true;
      }
      this.lastNoteDown = { id: `box:${bar}`, at: now };
    }
    if (box && net?.boxes?.[box]) {
      this.picked = { kind: 'box', id: box };
      if (!bar) {
        // The box alone is selected: C colours it, Delete removes it.
        this.actions.select([], null);
        this.render();
        return true;
      }
      // Dragging the label moves the box's nodes, as Houdini's boxes do.
      const members = net.boxes[box].nodes;
      this.actions.select(members.map((n) => join(this.store.at, n)), null);
      const start = new Map<string, [number, number]>();
      for (const n of members) {
        const at = this.positions.get(n);
        if (at) start.set(n, [...at] as [number, number]);
      }
      this.drag = { kind: 'move', x: wx, y: wy, start, moved: false };
      return true;
    }
    return false;
  }

  /** Shift+P: a sticky note at the mouse. */
  addNote() {
    const id = freshId(this.net()?.notes, 'note');
    this.picked = { kind: 'note', id };
    this.actions.select([], null);
    void this.actions.edit({ kind: 'set_note', parent: this.store.at, id, note: newNote(this.mouse) });
  }

  /** Shift+O: a network box around the selected nodes of this network. */
  boxSelection() {
    const net = this.net();
    const names = [...this.store.selected].filter((p) => parentOf(p) === this.store.at).map((p) => p.slice(p.lastIndexOf('/') + 1));
    if (!net || !names.length) return;
    const id = freshId(net.boxes, 'box');
    void this.actions.edit({ kind: 'set_box', parent: this.store.at, id, box: { label: `Box ${id.slice(3)}`, nodes: names } });
  }

  /** C: colours the selected nodes, or else the selected note or box, from the palette. */
  async colour() {
    const at = this.mouseAt ?? [200, 200];
    const c = await pickColor(at[0], at[1]);
    if (c === undefined) return;
    const net = this.net();
    // Selected nodes first (Houdini's C); else the selected note or box.
    const p = this.store.selected.size ? null : this.picked;
    if (p?.kind === 'note' && net?.notes?.[p.id]) {
      void this.actions.edit({ kind: 'set_note', parent: this.store.at, id: p.id, note: { ...net.notes[p.id], color: c ?? undefined } });
    } else if (p?.kind === 'box' && net?.boxes?.[p.id]) {
      void this.actions.edit({ kind: 'set_box', parent: this.store.at, id: p.id, box: { ...net.boxes[p.id], color: c ?? undefined } });
    } else if (this.store.selected.size) {
      void this.actions.edit({ kind: 'set_color', paths: [...this.store.selected], color: c });
    }
  }

  /** Delete on a selected note or box removes it (its nodes stay); false when neither is selected. */
  deletePicked(): boolean {
    const p = this.picked;
    if (!p) return false;
    this.picked = null;
    void this.actions.edit(p.kind === 'note' ? { kind: 'set_note', parent: this.store.at, id: p.id, note: null } : { kind: 'set_box', parent: this.store.at, id: p.id, box: null });
    return true;
  }

  /** An inline editor over a note's text. */
  private writeNote(id: string) {
    const note = this.net()?.notes?.[id];
    if (!note) return;
    this.inlineText('textarea', note.pos, note.size, note.text, (text) =>
      this.actions.edit({ kind: 'set_note', parent: this.store.at, id, note: { ...note, text } }),
    );
  }

  /** An inline editor over a box's label (double-click its bar). */
  private renameBox(id: string) {
    const net = this.net();
    const b = net?.boxes?.[id];
    const f = b ? boxFrame(b, this.positions) : null;
    if (!b || !f) return;
    this.inlineText('input', [f[0], f[1]], [Math.max(120, f[2] - f[0]), 20], b.label, (label) =>
      this.actions.edit({ kind: 'set_box', parent: this.store.at, id, box: { ...b, label } }),
    );
  }

  /** A text field over a world rectangle; Enter (Ctrl/Cmd+Enter in a textarea) or leaving it commits, Esc cancels. */
  private inlineText(tag: 'textarea' | 'input', pos: [number, number], size: [number, number], value: string, commit: (text: string) => unknown) {
    const r = this.svg.getBoundingClientRect();
    const hr = this.host.getBoundingClientRect();
    const field = document.createElement(tag);
    field.className = tag === 'textarea' ? 'note-edit' : 'note-edit box-edit';
    field.value = value;
    field.style.left = `${r.left - hr.left + this.tx + pos[0] * this.zoom}px`;
    field.style.top = `${r.top - hr.top + this.ty + pos[1] * this.zoom}px`;
    field.style.width = `${size[0] * this.zoom}px`;
    field.style.height = `${size[1] * this.zoom}px`;
    this.host.appendChild(field);
    field.focus();
    field.select();
    let done = false;
    const finish = (ok: boolean) => {
      if (done) return;
      done = true;
      field.remove();
      if (ok && field.value !== value) void commit(field.value);
      this.svg.focus();
    };
    field.addEventListener('keydown', (ev) => {
      const e = ev as KeyboardEvent;
      e.stopPropagation();
      if (e.key === 'Escape') finish(false);
      if (e.key === 'Enter' && (tag === 'input' || e.ctrlKey || e.metaKey)) finish(true);
    });
    field.addEventListener('blur', () => finish(true));
  }

  private inputsOf(node: DocNode): number {
    const t = this.store.catalogue.get(node.type);
    const declared = t?.inputs.length ?? 1;
    return t?.variadic ? Math.max(declared, (node.inputs?.length ?? 0) + 1) : declared;
  }

  /**
   * Nodes of this network that read a node whose cook failed (directly or
   * further up), each with the failed node's path: they failed with it, as
   * Houdini marks every node below an error.
   */
  private readsFailed(net: DocNetwork): Map<string, string> {
    const s = this.store;
    const at = s.at === '/' ? '' : s.at;
    const out = new Map<string, string>();
    // A failing node at this level, or the node at this level holding it.
    const here = (path: string) => (path.startsWith(at + '/') ? path.slice(at.length + 1).split('/')[0] : null);
    const queue: [string, string][] = [];
    for (const e of freshCookErrors(s.state, s.cooked)) {
      const n = here(e.path);
      if (n && e.kind !== 'cancelled') queue.push([n, e.path]);
    }
    const readers = new Map<string, string[]>();
    for (const w of wires(net)) readers.set(w.from, [...(readers.get(w.from) ?? []), w.to]);
    while (queue.length) {
      const [n, source] = queue.pop()!;
      for (const r of readers.get(n) ?? []) {
        if (!out.has(r)) {
          out.set(r, source);
          queue.push([r, source]);
        }
      }
    }
    return out;
  }

  private drawNode(name: string, node: DocNode, [x, y]: [number, number], failedInput?: string) {
    const s = this.store;
    const path = join(s.at, name);
    const problems = (s.state?.problems ?? []).filter((p) => p.level !== 'note' && (p.path === path || p.path.startsWith(path + '/')));
    const cookErr = freshCookErrors(s.state, s.cooked).filter((p) => p.path === path && p.kind !== 'cancelled');
    const errors = uniqueProblems([...problems, ...cookErr]);
    const viewed = (s.state?.view.solo ?? s.state?.output) === path;
    const warnings = errors.length ? [] : (s.badges.get(path)?.warnings ?? []);
    const classes = ['node', node.bypass ? 'bypass' : '', s.selected.has(path) ? 'selected' : '', errors.length ? 'error' : '', !errors.length && failedInput ? 'input-error' : '', warnings.length ? 'warning' : '', viewed ? 'viewed' : '', hasNetwork(node, this.store.catalogue) ? 'subnet' : ''];
    const g = el('g', { class: classes.join(' '), transform: `translate(${x},${y})`, 'data-node': name, 'data-path': path }, this.root);
    const body = el('rect', { class: 'body', width: NODE_W, height: NODE_H, rx: 5 }, g);
    if (node.ui?.color) body.style.fill = node.ui.color;
    el('rect', { class: 'flag bypass-flag' + (node.bypass ? ' on' : ''), x: 0, y: 0, width: 14, height: NODE_H, rx: 4, 'data-flag': 'bypass' }, g);
    el('rect', { class: 'flag template-flag' + (node.template ? ' on' : ''), x: NODE_W - 24, y: 0, width: 10, height: NODE_H, rx: 2, 'data-flag': 'template' }, g);
    el('rect', { class: 'flag display-flag' + (node.display || viewed ? ' on' : ''), x: NODE_W - 14, y: 0, width: 14, height: NODE_H, rx: 4, 'data-flag': 'display' }, g);
    const label = el('text', { class: 'node-name', x: 20, y: 13 }, g);
    label.textContent = name;
    const ty = el('text', { class: 'node-type', x: 20, y: 25 }, g);
    ty.textContent = node.type;
    const count = this.inputsOf(node);
    for (let i = 0; i < count; i++) {
      const connected = !!node.inputs?.[i];
      const port = el('circle', { class: 'port in' + (connected ? ' connected' : ''), cx: portX(i, count), cy: 0, r: 5, 'data-input': i }, g);
      const t = s.catalogue.get(node.type)?.inputs[Math.min(i, (s.catalogue.get(node.type)?.inputs.length ?? 1) - 1)];
      el('title', {}, port).textContent = `${t?.name ?? 'input ' + (i + 1)} (${t?.type ?? 'geometry'})`;
    }
    const outType = s.catalogue.get(node.type)?.output ?? 'geometry';
    el('circle', { class: `port out type-${outType}`, cx: NODE_W / 2, cy: NODE_H, r: 5, 'data-port': 'out' }, g);
    const badge = s.badges.get(path);
    const progress = s.progress.get(path);
    if (progress !== undefined && progress < 1) {
      el('rect', { class: 'progress', x: 0, y: NODE_H + 3, width: NODE_W * progress, height: 3 }, g);
    }
    const info = el('text', { class: 'badge' + (badge?.hit ? ' hit' : ''), x: NODE_W + 8, y: 13 }, g);
    // Below a failed node, an older cook's time would say this one cooked.
    info.textContent = badge && !failedInput ? (badge.hit ? 'cache' : `${badge.ms < 10 ? badge.ms.toFixed(1) : Math.round(badge.ms)} ms`) : '';
    if (!errors.length && failedInput) {
      const t = el('text', { class: 'error-text', x: NODE_W + 8, y: 26 }, g);
      t.textContent = `an input failed: ${failedInput}`;
      el('title', {}, g).textContent = `${failedInput} failed to cook, so this node could not cook`;
    } else if (errors.length) {
      const t = el('text', { class: 'error-text', x: NODE_W + 8, y: 26 }, g);
      const msg = errors[0].param ? `${errors[0].param}: ${errors[0].message}` : errors[0].message;
      t.textContent = msg.length > 60 ? msg.slice(0, 57) + '…' : msg;
      el('title', {}, g).textContent = errors.map((e) => `${e.param ? e.param + ': ' : ''}${e.message}`).join('\n');
    } else if (warnings.length) {
      const t = el('text', { class: 'warning-text', x: NODE_W + 8, y: 26 }, g);
      t.textContent = warnings[0].length > 60 ? warnings[0].slice(0, 57) + '…' : warnings[0];
      el('title', {}, g).textContent = warnings.join('\n');
    }
  }
}

function portX(i: number, count: number): number {
  return ((i + 1) * NODE_W) / (count + 1);
}

function firstFreeInput(node: DocNode | undefined, declared: number): number {
  const ins = node?.inputs ?? [];
  for (let i = 0; i < Math.max(declared, ins.length); i++) if (!ins[i]) return i;
  return ins.length;
}

function drawWire(parent: Element, [x0, y0]: [number, number], [x1, y1]: [number, number], cls: string) {
  const dy = Math.max(30, Math.abs(y1 - y0) / 2);
  el('path', { class: cls, d: `M${x0},${y0} C${x0},${y0 + dy} ${x1},${y1 - dy} ${x1},${y1}` }, parent);
}
