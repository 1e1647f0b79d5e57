// A layered (Sugiyama) layout for networks without stored positions: longest-path layers, long wires split by dummy nodes, barycentre sweeps keeping the order with the fewest crossings, then x positions pulled towards each node's neighbours without overlaps. Hand-written: elkjs would add about 1.5 MB to the bundle the binary embeds and lays out asynchronously; SOP networks are narrow DAGs this handles well.

export interface LayoutGraph {
  /** Node names in a stable order (the document's). */
  nodes: string[];
  /** Wires as [from, to] (inputs above readers). */
  edges: [string, string][];
}

export interface LayoutOptions {
  width: number;
  height: number;
  gapX: number;
  gapY: number;
}

type Order = string[][];

/** Each node's layer: one below its deepest input (a cycle's back edge is ignored). */
function layers(g: LayoutGraph): Map<string, number> {
  const inputs = new Map<string, string[]>();
  for (const [a, b] of g.edges) inputs.set(b, [...(inputs.get(b) ?? []), a]);
  const depth = new Map<string, number>();
  const visiting = new Set<string>();
  // Iterative depth-first search: no network is deep enough to overflow it.
  for (const start of g.nodes) {
    if (depth.has(start)) continue;
    const stack: [string, number][] = [[start, 0]];
    visiting.add(start);
    while (stack.length) {
      const top = stack[stack.length - 1];
      const ins = inputs.get(top[0]) ?? [];
      if (top[1] < ins.length) {
        const next = ins[top[1]++];
        if (!depth.has(next) && !visiting.has(next)) {
          visiting.add(next);
          stack.push([next, 0]);
        }
        continue;
      }
      const d = ins.reduce((m, i) => (depth.has(i) ? Math.max(m, depth.get(i)! + 1) : m), 0);
      depth.set(top[0], d);
      visiting.delete(top[0]);
      stack.pop();
    }
  }
  return depth;
}

/** Crossings between two adjacent layers, edges given as pairs of positions. */
function crossingsBetween(pairs: [number, number][]): number {
  pairs.sort((p, q) => p[0] - q[0] || p[1] - q[1]);
  let n = 0;
  for (let i = 0; i < pairs.length; i++) for (let j = i + 1; j < pairs.length; j++) if (pairs[j][1] < pairs[i][1] && pairs[j][0] > pairs[i][0]) n++;
  return n;
}

/** Every wire crossing of an ordering (layer by layer). */
export function crossings(order: Order, edges: [string, string][]): number {
  const at = new Map<string, [number, number]>();
  order.forEach((row, l) => row.forEach((n, k) => at.set(n, [l, k])));
  const byLayer = new Map<number, [number, number][]>();
  for (const [a, b] of edges) {
    const pa = at.get(a);
    const pb = at.get(b);
    if (!pa || !pb || pb[0] !== pa[0] + 1) continue;
    byLayer.set(pa[0], [...(byLayer.get(pa[0]) ?? []), [pa[1], pb[1]]]);
  }
  let n = 0;
  for (const pairs of byLayer.values()) n += crossingsBetween(pairs);
  return n;
}

/** The layered graph: wires spanning several layers pass through dummy nodes (`\u0000k`). */
function proper(g: LayoutGraph, depth: Map<string, number>): { order: Order; edges: [string, string][] } {
  const order: Order = [];
  const put = (n: string, l: number) => (order[l] ??= []).push(n);
  for (const n of g.nodes) put(n, depth.get(n) ?? 0);
  const edges: [string, string][] = [];
  let dummies = 0;
  for (const [a, b] of g.edges) {
    const la = depth.get(a) ?? 0;
    const lb = depth.get(b) ?? 0;
    if (lb <= la) continue;
    let prev = a;
    for (let l = la + 1; l < lb; l++) {
      const d = `\u0000${dummies++}`;
      put(d, l);
      edges.push([prev, d]);
      prev = d;
    }
    edges.push([prev, b]);
  }
  for (let l = 0; l < order.length; l++) order[l] ??= [];
  return { order, edges };
}

/** Barycentre sweeps down and up; the ordering with the fewest crossings wins. */
function reduceCrossings(order: Order, edges: [string, string][]): Order {
  const up = new Map<string, string[]>();
  const down = new Map<string, string[]>();
  for (const [a, b] of edges) {
    up.set(b, [...(up.get(b) ?? []), a]);
    down.set(a, [...(down.get(a) ?? []), b]);
  }
  let best = order.map((r) => [...r]);
  let bestCount = crossings(best, edges);
  const cur = order.map((r) => [...r]);
  for (let sweep = 0; sweep < 12 && bestCount > 0; sweep++) {
    const downward = sweep % 2 === 0;
    const ls = [...cur.keys()];
    for (const l of downward ? ls.slice(1) : ls.slice(0, -1).reverse()) {
      const ref = cur[downward ? l - 1 : l + 1];
      const pos = new Map(ref.map((n, k) => [n, k]));
      const nb = downward ? up : down;
      const bary = new Map<string, number>();
      cur[l].forEach((n, k) => {
        const ks = (nb.get(n) ?? []).map((m) => pos.get(m)).filter((x): x is number => x !== undefined);
        bary.set(n, ks.length ? ks.reduce((s, x) => s + x, 0) / ks.length : k);
      });
      cur[l] = [...cur[l]].sort((a, b) => bary.get(a)! - bary.get(b)!);
    }
    const c = crossings(cur, edges);
    if (c < bestCount) {
      bestCount = c;
      best = cur.map((r) => [...r]);
    }
  }
  return best;
}

/** x of each node: in order, a slot apart at least, pulled towards the mean x of its neighbours. */
function place(order: Order, edges: [string, string][], slot: number): Map<string, number> {
  const x = new Map<string, number>();
  for (const row of order) row.forEach((n, k) => x.set(n, (k - (row.length - 1) / 2) * slot));
  const nbUp = new Map<string, string[]>();
  const nbDown = new Map<string, string[]>();
  for (const [a, b] of edges) {
    nbUp.set(b, [...(nbUp.get(b) ?? []), a]);
    nbDown.set(a, [...(nbDown.get(a) ?? []), b]);
  }
  for (let pass = 0; pass < 8; pass++) {
    const downward = pass % 2 === 0;
    const ls = [...order.keys()];
    for (const l of downward ? ls.slice(1) : ls.slice(0, -1).reverse()) {
      const row = order[l];
      const nb = downward ? nbUp : nbDown;
      const want = row.map((n) => {
        const xs = (nb.get(n) ?? []).map((m) => x.get(m)!);
        return xs.length ? xs.reduce((s, v) => s + v, 0) / xs.length : x.get(n)!;
      });
      // Left to right keeping a slot apart, then right to left, then the mean of both.
      const left = [...want];
      for (let k = 1; k < left.length; k++) left[k] = Math.max(left[k], left[k - 1] + slot);
      const right = [...want];
      for (let k = right.length - 2; k >= 0; k--) right[k] = Math.min(right[k], right[k + 1] - slot);
      row.forEach((n, k) => x.set(n, (left[k] + right[k]) / 2));
      // The mean of two valid placements keeps the order but may pinch: fix the spacing once more.
      for (let k = 1; k < row.length; k++) {
        const prev = x.get(row[k - 1])!;
        if (x.get(row[k])! < prev + slot) x.set(row[k], prev + slot);
      }
    }
  }
  return x;
}

/** Top-left positions of every node. */
export function layered(g: LayoutGraph, o: LayoutOptions): Map<string, [number, number]> {
  const depth = layers(g);
  const { order, edges } = proper(g, depth);
  const best = reduceCrossings(order, edges);
  const x = place(best, edges, o.width + o.gapX);
  const pos = new Map<string, [number, number]>();
  best.forEach((row, l) => {
    for (const n of row) if (!n.startsWith('\u0000')) pos.set(n, [Math.round(x.get(n)! - o.width / 2), l * (o.height + o.gapY)]);
  });
  return pos;
}

/** The ordering `layered` settles on, for tests: layers of real nodes. */
export function layeredOrder(g: LayoutGraph): Order {
  const depth = layers(g);
  const { order, edges } = proper(g, depth);
  return reduceCrossings(order, edges);
}
