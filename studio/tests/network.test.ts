// Unit tests of document reading: paths, wires, the automatic layout and channel evaluation.
import { describe, expect, test } from 'vitest';
import { channelAt, join, lastKeyFrame, layout, networkAt, NODE_H, NODE_W, nodeAt, parentOf, wires } from '../src/network';
import { crossings, layeredOrder } from '../src/layout';
import type { DocNetwork } from '../src/protocol';

const net: DocNetwork = {
  nodes: {
    a: { type: 'box' },
    b: { type: 'sphere' },
    m: { type: 'merge', inputs: ['a', 'b'] },
    t: { type: 'transform', inputs: ['m'], ui: { pos: [500, 700] } },
    sub: { type: 'subnet', network: { nodes: { inner: { type: 'box', params: { size: [1, { keys: [{ frame: 1, value: 0 }, { frame: 48, value: 2 }] }, 1] } } } } },
  },
};

describe('paths', () => {
  test('join and parent', () => {
    expect(join('/', 'a')).toBe('/a');
    expect(join('/sub', 'inner')).toBe('/sub/inner');
    expect(parentOf('/sub/inner')).toBe('/sub');
    expect(parentOf('/a')).toBe('/');
  });
  test('networks and nodes by path', () => {
    expect(networkAt(net, '/sub')?.nodes.inner.type).toBe('box');
    expect(nodeAt(net, '/sub/inner')?.type).toBe('box');
    expect(nodeAt(net, '/nope')).toBeNull();
    expect(networkAt(net, '/a')).toBeNull();
  });
});

test('wires list every connected input', () => {
  expect(wires(net)).toEqual([
    { from: 'a', to: 'm', input: 0 },
    { from: 'b', to: 'm', input: 1 },
    { from: 'm', to: 't', input: 0 },
  ]);
});

test('layout puts each node below its deepest input and keeps file positions', () => {
  const pos = layout(net);
  expect(pos.get('a')![1]).toBe(pos.get('b')![1]);
  expect(pos.get('m')![1]).toBeGreaterThan(pos.get('a')![1]);
  expect(pos.get('a')![0]).not.toBe(pos.get('b')![0]);
  expect(pos.get('t')).toEqual([500, 700]);
});

test('layout survives a cycle', () => {
  const cyc: DocNetwork = { nodes: { x: { type: 'box', inputs: ['y'] }, y: { type: 'box', inputs: ['x'] } } };
  expect(layout(cyc).size).toBe(2);
});

test('channels interpolate linearly and hold outside their keys', () => {
  const keys = [
    { frame: 1, value: 0 },
    { frame: 11, value: 10 },
  ];
  expect(channelAt(keys, 6)).toBe(5);
  expect(channelAt(keys, -3)).toBe(0);
  expect(channelAt(keys, 99)).toBe(10);
  expect(lastKeyFrame(net)).toBe(48);
});

describe('the layered layout', () => {
  /** A seeded random DAG: `n` nodes, each reading up to two earlier ones, names shuffled so document order says nothing. */
  function dag(n: number, seed: number): DocNetwork {
    let s = seed;
    const rnd = () => ((s = (s * 1103515245 + 12345) % 2 ** 31) / 2 ** 31);
    const names = Array.from({ length: n }, (_, i) => `n${String(i).padStart(3, '0')}`).sort(() => rnd() - 0.5);
    const nodes: DocNetwork['nodes'] = {};
    names.forEach((name, i) => {
      const inputs = i === 0 ? [] : [names[Math.floor(rnd() * i)], ...(rnd() < 0.4 ? [names[Math.floor(rnd() * i)]] : [])];
      nodes[name] = { type: 'merge', inputs: [...new Set(inputs)] };
    });
    return { nodes };
  }
  const graph = (net: DocNetwork) => ({
    nodes: Object.keys(net.nodes),
    edges: wires(net).map((w) => [w.from, w.to] as [string, string]),
  });

  test('crosses far fewer wires than rows in document order', () => {
    for (const seed of [1, 2, 3]) {
      const net = dag(80, seed);
      const g = graph(net);
      const order = layeredOrder(g);
      // The same layers in document order, for comparison.
      const naive = order.map((row) => [...row].sort((a, b) => g.nodes.indexOf(a) - g.nodes.indexOf(b)));
      expect(crossings(order, g.edges)).toBeLessThan(crossings(naive, g.edges) * 0.6);
    }
  });

  test('keeps nodes of a row apart and every reader below its inputs', () => {
    const net = dag(60, 7);
    const pos = layout(net);
    const rows = new Map<number, number[]>();
    for (const [, [x, y]] of pos) rows.set(y, [...(rows.get(y) ?? []), x]);
    for (const xs of rows.values()) {
      xs.sort((a, b) => a - b);
      for (let i = 1; i < xs.length; i++) expect(xs[i] - xs[i - 1]).toBeGreaterThanOrEqual(NODE_W);
    }
    for (const w of wires(net)) expect(pos.get(w.to)![1]).toBeGreaterThan(pos.get(w.from)![1]);
  });

  test('adding a node moves none of the others it was told to keep', () => {
    const net = dag(30, 4);
    const before = layout(net);
    const grown: DocNetwork = { nodes: { ...net.nodes, extra: { type: 'merge', inputs: [Object.keys(net.nodes)[3]] } } };
    const after = layout(grown, before);
    for (const [n, p] of before) expect(after.get(n)).toEqual(p);
    expect(after.has('extra')).toBe(true);
  });
});

test('a node laid out beside kept ones covers none of them', () => {
  const net: DocNetwork = { nodes: { a: { type: 'box' }, b: { type: 'box', inputs: ['a'] } } };
  const before = layout(net);
  const grown: DocNetwork = { nodes: { ...net.nodes, c: { type: 'box' } } };
  const after = layout(grown, before);
  const c = after.get('c')!;
  for (const n of ['a', 'b']) {
    const p = after.get(n)!;
    expect(Math.abs(p[0] - c[0]) >= NODE_W || Math.abs(p[1] - c[1]) >= NODE_H).toBe(true);
  }
});
