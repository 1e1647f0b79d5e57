// Reading the network document: the network at a path, node paths, wires, and an automatic layout for nodes the file gives no position.

import { evalChannel } from './channel';
import { layered } from './layout';
import type { Key } from './channel';

import type { DocNetwork, DocNode } from './protocol';

export const NODE_W = 132;
export const NODE_H = 30;
const GAP_X = 40;
const GAP_Y = 40;

/** `/` joined with a name: `/a` + `b` = `/a/b`. */
export function join(parent: string, name: string): string {
  return parent === '/' ? `/${name}` : `${parent}/${name}`;
}

/** The network at `path` (`/` or a subnet's path), or null. */
export function networkAt(root: DocNetwork, path: string): DocNetwork | null {
  let net: DocNetwork | undefined = root;
  for (const name of path.split('/').filter(Boolean)) {
    net = net?.nodes[name]?.network;
    if (!net) return null;
  }
  return net ?? null;
}

/** The node at an absolute path, or null. */
export function nodeAt(root: DocNetwork, path: string): DocNode | null {
  const i = path.lastIndexOf('/');
  const net = networkAt(root, i <= 0 ? '/' : path.slice(0, i));
  return net?.nodes[path.slice(i + 1)] ?? null;
}

export function parentOf(path: string): string {
  const i = path.lastIndexOf('/');
  return i <= 0 ? '/' : path.slice(0, i);
}

export interface Wire {
  from: string;
  to: string;
  input: number;
}

/** Wires between the nodes of one network (subnet inputs `@N` are drawn from the network's input markers). */
export function wires(net: DocNetwork): Wire[] {
  const out: Wire[] = [];
  for (const [to, node] of Object.entries(net.nodes)) {
    (node.inputs ?? []).forEach((from, input) => {
      if (from) out.push({ from, to, input });
    });
  }
  return out;
}

/**
 * Positions for every node: the file's where given, else a layered layout
 * (see layout.ts). Nodes in `keep` that the file gives no position keep the
 * one they had, so adding a node never moves the others.
 */
export function layout(net: DocNetwork, keep?: Map<string, [number, number]>): Map<string, [number, number]> {
  const names = Object.keys(net.nodes);
  const edges: [string, string][] = wires(net)
    .filter((w) => w.from in net.nodes)
    .map((w) => [w.from, w.to]);
  const pos = layered({ nodes: names, edges }, { width: NODE_W, height: NODE_H, gapX: GAP_X, gapY: GAP_Y });
  const fresh: string[] = [];
  for (const n of names) {
    const p = net.nodes[n].ui?.pos;
    if (Array.isArray(p) && p.length === 2 && p.every(Number.isFinite)) pos.set(n, [p[0], p[1]]);
    else if (keep?.has(n)) pos.set(n, keep.get(n)!);
    else fresh.push(n);
  }
  // A node laid out now (the others kept where they were) moves right until it covers none of them.
  if (keep?.size) {
    const placed = names.filter((n) => !fresh.includes(n)).map((n) => pos.get(n)!);
    const covers = ([x, y]: [number, number]) => placed.some(([a, b]) => Math.abs(a - x) < NODE_W + GAP_X / 2 && Math.abs(b - y) < NODE_H + GAP_Y / 2);
    for (const n of fresh) {
      const p = pos.get(n)!;
      while (covers(p)) p[0] += NODE_W + GAP_X;
      placed.push(p);
    }
  }
  return pos;
}

/** A channel's value at `frame` (linear between keys, held outside them). */
export function channelAt(keys: Key[], frame: number): number {
  return evalChannel(keys, frame);
}

export interface Keyed {
  keys: Key[];
}

/** A component written as an expression: `{"expr": "sin($F)"}`. */
export interface Expr {
  expr: string;
}

export function isExpr(v: unknown): v is Expr {
  return typeof v === 'object' && v !== null && typeof (v as Expr).expr === 'string';
}

export function isChannel(v: unknown): v is Keyed {
  return typeof v === 'object' && v !== null && Array.isArray((v as Keyed).keys);
}

/** The last key frame of any channel in the document (the timeline's default end). */
export function lastKeyFrame(net: DocNetwork): number {
  let last = 0;
  const visit = (v: unknown) => {
    if (isChannel(v)) for (const k of v.keys) last = Math.max(last, k.frame);
    else if (Array.isArray(v)) v.forEach(visit);
  };
  for (const node of Object.values(net.nodes)) {
    Object.values(node.params ?? {}).forEach(visit);
    if (node.network) last = Math.max(last, lastKeyFrame(node.network));
  }
  return last;
}
