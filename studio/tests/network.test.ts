// Unit tests of document reading: paths, wires, the automatic layout and channel evaluation.
import { describe, expect, test } from 'vitest';
import { channelAt, join, lastKeyFrame, layout, networkAt, nodeAt, parentOf, wires } from '../src/network';
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
