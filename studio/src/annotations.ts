// What the network editor draws besides nodes, all kept in the network file: network boxes (a labelled, coloured frame around nodes; dragging its label moves them), sticky notes (text on a coloured card; drag to move, the corner to resize, double-click to write), and the palette for node, box and note colours.

import { NODE_H, NODE_W } from './network';
import type { DocNetwork, NetworkBox, StickyNote } from './protocol';

const SVG = 'http://www.w3.org/2000/svg';

/** Houdini's network palette, abridged: the colours the C key offers. */
export const PALETTE = ['#c74440', '#e3803a', '#e6c84f', '#6fae4a', '#3f9e8f', '#4a86c8', '#7d5bc7', '#c75b9e', '#8a8f98'];

/** Default colours: boxes grey-blue, notes pale yellow. */
export const BOX_COLOR = '#52627a';
export const NOTE_COLOR = '#d9c66b';

/** Padding around a box's nodes, and the height of its label bar. */
const PAD = 18;
const BAR = 20;

/** What is selected among notes and boxes (nodes are the store's selection). */
export type Annotation = { kind: 'note' | 'box'; id: string };

function el<K extends keyof SVGElementTagNameMap>(tag: K, attrs: Record<string, string | number>, parent: Element) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  parent.appendChild(e);
  return e;
}

/** A box's frame [x0, y0, x1, y1] around its nodes' positions (null when none of them is placed). */
export function boxFrame(b: NetworkBox, positions: Map<string, [number, number]>): [number, number, number, number] | null {
  const at = b.nodes.map((n) => positions.get(n)).filter((p): p is [number, number] => !!p);
  if (!at.length) return null;
  const xs = at.map((p) => p[0]);
  const ys = at.map((p) => p[1]);
  return [Math.min(...xs) - PAD, Math.min(...ys) - PAD - BAR, Math.max(...xs) + NODE_W + PAD, Math.max(...ys) + NODE_H + PAD];
}

/** An id for a new note or box that the network does not use. */
export function freshId(taken: Record<string, unknown> | undefined, prefix: string): string {
  for (let i = 1; ; i++) if (!taken?.[`${prefix}${i}`]) return `${prefix}${i}`;
}

/** Draws the boxes into `back` and the notes into `front` (both layers behind the nodes). */
export function drawAnnotations(back: Element, front: Element, net: DocNetwork, positions: Map<string, [number, number]>, selected: Annotation | null) {
  for (const [id, b] of Object.entries(net.boxes ?? {})) {
    const f = boxFrame(b, positions);
    if (!f) continue;
    const color = b.color ?? BOX_COLOR;
    const on = selected?.kind === 'box' && selected.id === id;
    const g = el('g', { class: 'net-box' + (on ? ' selected' : ''), 'data-box': id }, back);
    el('rect', { class: 'net-box-body', x: f[0], y: f[1], width: f[2] - f[0], height: f[3] - f[1], rx: 6, fill: color, stroke: color }, g);
    el('rect', { class: 'net-box-bar', x: f[0], y: f[1], width: f[2] - f[0], height: BAR, rx: 6, fill: color, 'data-box-bar': id }, g);
    const t = el('text', { class: 'net-box-label', x: f[0] + 8, y: f[1] + 14 }, g);
    t.textContent = b.label;
  }
  for (const [id, n] of Object.entries(net.notes ?? {})) {
    const on = selected?.kind === 'note' && selected.id === id;
    const g = el('g', { class: 'note' + (on ? ' selected' : ''), 'data-note': id, transform: `translate(${n.pos[0]},${n.pos[1]})` }, front);
    el('rect', { class: 'note-body', width: n.size[0], height: n.size[1], rx: 3, fill: n.color ?? NOTE_COLOR }, g);
    const fo = el('foreignObject', { x: 6, y: 4, width: Math.max(1, n.size[0] - 12), height: Math.max(1, n.size[1] - 8) }, g);
    const div = document.createElement('div');
    div.className = 'note-text';
    div.textContent = n.text;
    fo.appendChild(div);
    el('rect', { class: 'note-resize', x: n.size[0] - 10, y: n.size[1] - 10, width: 10, height: 10, 'data-note-resize': id }, g);
  }
}

/** A new note as the document writes it. */
export function newNote(at: [number, number]): StickyNote {
  return { text: 'Note', pos: [Math.round(at[0]), Math.round(at[1])], size: [200, 80] };
}

/** The colour palette as a small popup at page position (x, y); resolves with the chosen colour, null for none, undefined when dismissed. */
export function pickColor(x: number, y: number): Promise<string | null | undefined> {
  return new Promise((resolve) => {
    const pop = document.createElement('div');
    pop.className = 'palette';
    pop.style.left = `${x}px`;
    pop.style.top = `${y}px`;
    const done = (v: string | null | undefined) => {
      pop.remove();
      window.removeEventListener('pointerdown', outside, true);
      resolve(v);
    };
    const outside = (e: Event) => {
      if (!pop.contains(e.target as Node)) done(undefined);
    };
    for (const c of [...PALETTE, null]) {
      const b = document.createElement('button');
      b.className = 'swatch';
      b.title = c ?? 'No colour';
      b.dataset.color = c ?? '';
      if (c) b.style.background = c;
      else b.textContent = '∅';
      b.addEventListener('click', () => done(c));
      pop.appendChild(b);
    }
    pop.addEventListener('keydown', (e) => e.key === 'Escape' && done(undefined));
    document.body.appendChild(pop);
    window.addEventListener('pointerdown', outside, true);
  });
}
