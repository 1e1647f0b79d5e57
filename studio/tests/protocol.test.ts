// Unit tests of the geometry decoder against a message laid out as the server lays it, and of the panel's text parsing.
import { describe, expect, it, test } from 'vitest';
import { decodeGeometry, fanTriangles, hasNetwork, polygonEdges, reducedNotice, uniqueProblems, type GeometryPart, type Problem } from '../src/protocol';
import { nodeTypes } from './protocol.fixture';
import { parseNumber } from '../src/params';
import { filterCatalogue } from '../src/tabmenu';
import { chunksFor } from '../src/sheet';
import { checksum, repairNormals } from '../src/viewport';
import * as THREE from 'three';
import type { NodeType } from '../src/protocol';

function message(header: object, arrays: ArrayBufferView[]): ArrayBuffer {
  let head = new TextEncoder().encode(JSON.stringify(header));
  const pad = (4 - (head.length % 4)) % 4;
  head = new Uint8Array([...head, ...new Array(pad).fill(32)]);
  const body = arrays.reduce((n, a) => n + a.byteLength, 0);
  const out = new Uint8Array(8 + head.length + body);
  out.set(new TextEncoder().encode('GEO1'));
  new DataView(out.buffer).setUint32(4, head.length, true);
  out.set(head, 8);
  let at = 8 + head.length;
  for (const a of arrays) {
    out.set(new Uint8Array(a.buffer, a.byteOffset, a.byteLength), at);
    at += a.byteLength;
  }
  return out.buffer;
}

test('decodes typed arrays at their offsets without copying', () => {
  const positions = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]);
  const triangles = new Uint32Array([0, 1, 2]);
  const buf = message(
    { generation: 7, node: '/a', bounds: [[0, 0, 0], [1, 1, 0]], parts: [{ name: '', positions: [0, 9], polygons: [36, 3], polygonSize: 3, colorsUniform: [1, 0, 0] }] },
    [positions, triangles],
  );
  const g = decodeGeometry(buf);
  expect(g.generation).toBe(7);
  expect(g.node).toBe('/a');
  expect([...g.parts[0].positions]).toEqual([...positions]);
  expect([...g.parts[0].triangles!]).toEqual([0, 1, 2]);
  expect(g.parts[0].colorsUniform).toEqual([1, 0, 0]);
  expect(g.parts[0].positions.buffer).toBe(buf);
});

test('refuses what is not a geometry message', () => {
  expect(() => decodeGeometry(new TextEncoder().encode('JSON{}  ').buffer)).toThrow(/not a geometry message/);
});

test('typed numbers become numbers, anything else stays text for the loader to judge', () => {
  expect(parseNumber(' 2.5 ')).toBe(2.5);
  expect(parseNumber('-1e3')).toBe(-1000);
  expect(parseNumber('abc')).toBe('abc');
  expect(parseNumber('')).toBe('');
});

test('the Tab menu ranks exact and prefix matches first', () => {
  const t = (name: string, label: string, summary = '', category = 'Geometry') => ({ name, label, summary, category }) as NodeType;
  const all = [t('frep_box', 'FRep Box'), t('box', 'Box'), t('group_bbox', 'Group by Bounding Box'), t('sphere', 'Sphere', 'a round ball')];
  expect(filterCatalogue(all, 'box').map((x) => x.name)).toEqual(['box', 'frep_box', 'group_bbox']);
  expect(filterCatalogue(all, 'round').map((x) => x.name)).toEqual(['sphere']);
  expect(filterCatalogue(all, '').length).toBe(4);
});

test('spreadsheet chunks cover the visible rows', () => {
  expect(chunksFor(0, 10)).toEqual([0]);
  expect(chunksFor(150, 450)).toEqual([0, 1, 2]);
});

test('the drawn-geometry checksum sees a changed value', () => {
  const a = new Float32Array([1, 2, 3]);
  const b = new Float32Array([1, 2, 3.5]);
  expect(checksum(a)).not.toBe(checksum(b));
  expect(checksum(a)).toBe(checksum(new Float32Array([1, 2, 3])));
});

test('zero normals are replaced by computed ones, the others kept', () => {
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), 3));
  geo.setIndex([0, 1, 2]);
  geo.setAttribute('normal', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 0, 0]), 3));
  repairNormals(geo);
  const n = geo.getAttribute('normal');
  expect([n.getX(0), n.getY(0), n.getZ(0)]).toEqual([0, 0, 1]);
  expect([n.getX(1), n.getY(1), n.getZ(1)]).toEqual([1, 0, 0]);
});

test('the catalogue, not a list in the page, says which node types hold a network', () => {
  const types = new Map(nodeTypes.map((t) => [t.name, t]));
  const container = nodeTypes.find((t) => t.network)!;
  expect(hasNetwork({ type: container.name }, types)).toBe(true);
  const plain = nodeTypes.find((t) => !t.network)!;
  expect(hasNetwork({ type: plain.name }, types)).toBe(false);
  expect(hasNetwork({ type: 'anything', network: { nodes: {} } }, types)).toBe(true);
});

test('a reduced geometry is announced with what was drawn of how much', () => {
  const part = (reduced?: GeometryPart['reduced']) => ({ name: '', positions: new Float32Array(0), reduced }) as GeometryPart;
  expect(reducedNotice([part()])).toBe('');
  expect(reducedNotice([part({ triangles: [2_999_000, 9_800_000] })])).toBe('reduced for the viewport: 2,999,000 of 9,800,000 triangles drawn');
  expect(reducedNotice([part({ triangles: [10, 20] }), part({ triangles: [5, 30] }), part({ points: [1, 9] })])).toBe(
    'reduced for the viewport: 15 of 50 triangles, 1 of 9 points drawn',
  );
});

test('a load problem and the cook error it causes are said once', () => {
  const p = (kind?: string) => ({ path: '/grow', param: 'kill', message: 'value -1 is below the minimum 0', kind }) as Problem;
  expect(uniqueProblems([p(), p('parameter'), { ...p(), param: 'step' }])).toHaveLength(2);
});

describe('fanTriangles', () => {
  it('fans each polygon from its first vertex, in order', () => {
    expect([...fanTriangles(new Uint32Array([0, 1, 2, 3, 4, 5, 6]), new Uint32Array([4, 3]))]).toEqual([0, 1, 2, 0, 2, 3, 4, 5, 6]);
    expect([...fanTriangles(new Uint32Array([0, 1, 2, 3, 4, 5, 6, 7]), 4)]).toEqual([0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]);
  });
});

test('polygon edges close each polygon and draw no diagonal', () => {
  expect([...polygonEdges(new Uint32Array([0, 1, 2, 3]), 4)]).toEqual([0, 1, 1, 2, 2, 3, 3, 0]);
  expect([...polygonEdges(new Uint32Array([0, 1, 2, 5, 6, 7, 8]), new Uint32Array([3, 4]))]).toEqual([0, 1, 1, 2, 2, 0, 5, 6, 6, 7, 7, 8, 8, 5]);
});
