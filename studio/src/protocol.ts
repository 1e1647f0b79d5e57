// The studio's side of the protocol: message types, the binary geometry decoder, and the socket with request/reply ids.

export interface ParamDecl {
  name: string;
  label: string;
  type: 'float' | 'int' | 'toggle' | 'vec2' | 'vec3' | 'vec4' | 'string' | 'file' | 'menu' | 'list' | 'ramp' | 'colorramp';
  default: unknown;
  min: number | null;
  max: number | null;
  animatable: boolean;
  help: string;
  affects: string | null;
  items?: string[];
  fields?: ParamDecl[];
  /** A string holding code: a multi-line editor. */
  code?: boolean;
}

export interface NodeType {
  name: string;
  label: string;
  category: string;
  summary: string;
  help: string;
  inputs: { name: string; type: string; required: boolean }[];
  variadic: boolean;
  output: string;
  params: ParamDecl[];
  timeDependent: boolean;
  /** Holds a network (subnet, loop, solver, for_each). */
  network?: boolean;
  /** Its network reads `@meta` (the blocks). */
  meta?: boolean;
  /** Takes spare parameters declared in the network. */
  spare?: boolean;
}

export interface DocNode {
  type: string;
  params?: Record<string, unknown>;
  inputs?: (string | null)[];
  bypass?: boolean;
  display?: boolean;
  /** Houdini's template flag: drawn as a ghost beside the viewed node. */
  template?: boolean;
  network?: DocNetwork;
  promote?: Record<string, string>;
  /** Spare parameters: name -> type (float, int, toggle, vector2, vector, vector4, string, ramp, colorramp). */
  spare?: Record<string, string>;
  /** Editor data the file keeps: position and colour (`#rrggbb`). */
  ui?: { pos?: [number, number]; color?: string };
  [extra: string]: unknown;
}

export interface StickyNote {
  text: string;
  pos: [number, number];
  size: [number, number];
  color?: string;
}

export interface NetworkBox {
  label: string;
  nodes: string[];
  color?: string;
}

export interface DocNetwork {
  nodes: Record<string, DocNode>;
  output?: string;
  notes?: Record<string, StickyNote>;
  boxes?: Record<string, NetworkBox>;
}

export interface Problem {
  path: string;
  param: string | null;
  message: string;
  level?: string;
  /** `parameter`, `input`, `resource`, `kernel`, `io`, `network`, `cancelled` (cook errors). */
  kind?: string;
  /** Where in the parameter's text (a snippet, an expression), from 1. */
  line?: number | null;
  column?: number | null;
}

export interface StateMsg {
  type: 'state';
  version: number;
  generation: number;
  path: string | null;
  /** The document; `frames` and `fps` are the network's timeline, where set. */
  document: DocNetwork & { geode: string; version: number; frames?: [number, number]; fps?: number };
  problems: Problem[];
  dirty: boolean;
  canUndo: boolean;
  canRedo: boolean;
  /** The tab (see HelloMsg) whose step is next to undo or redo: only it may. */
  undoBy: number | null;
  redoBy: number | null;
  output: string | null;
  view: { solo: string | null; auto: boolean; frame: number };
}

export interface CookEventMsg {
  path: string;
  type: string;
  hit: boolean;
  start: number;
  ms: number;
  bytes: number;
  /** What the cook warned of (a feature lost, a value clamped). */
  warnings?: string[];
}

export interface GeometryStats {
  points: number;
  vertices: number;
  primitives: number;
  kinds: Record<string, number>;
  bounds: [number[], number[]] | null;
  memory: number;
}

export interface CookedMsg {
  type: 'cooked';
  generation: number;
  node: string | null;
  frame?: number;
  ok: boolean;
  errors: Problem[];
  events: CookEventMsg[];
  stats?: GeometryStats | { bundle: Record<string, GeometryStats> } | { field: true } | null;
  ms?: number;
  hasGeometry?: boolean;
  /** Milliseconds the server spent encoding the geometry for the viewport. */
  encodeMs?: number;
}

export interface ProgressMsg {
  type: 'progress';
  generation: number;
  node: string;
  fraction: number;
}

export interface ReplyMsg {
  type: 'reply';
  id: number | null;
  ok: boolean;
  error?: string;
  /** Why it was refused: `edit`, `io`, `request`, `protocol`, `internal`. */
  kind?: string;
  /** The node a refused edit concerns. */
  path?: string | null;
  [extra: string]: unknown;
}

/** The first message on a socket: this tab's number (each tab undoes its own edits). */
export interface HelloMsg {
  type: 'hello';
  client: number;
}

/** The server stopped the cook of `generation` (Esc, the cancel button): no result will come for it. */
export interface CancelledMsg {
  type: 'cancelled';
  generation: number;
}

export type ServerMsg = HelloMsg | StateMsg | CookedMsg | ProgressMsg | ReplyMsg | CancelledMsg;

/** One drawable part of a decoded geometry: typed-array views into the message. */
export interface GeometryPart {
  name: string;
  positions: Float32Array;
  /** Polygons as point indices and vertex counts (the server's form); `triangles` are made from them. */
  polygons?: Uint32Array;
  polygonSizes?: Uint32Array;
  /** The vertex count of every polygon, when they all have the same. */
  polygonSize?: number;
  triangles?: Uint32Array;
  normals?: Float32Array;
  colors?: Float32Array;
  normalsUniform?: number[];
  colorsUniform?: number[];
  corners?: Float32Array;
  cornerNormals?: Float32Array;
  cornerColors?: Float32Array;
  /** Triangles over the corner vertices (split where values differ). */
  cornerTriangles?: Uint32Array;
  lines?: Uint32Array;
  points?: Uint32Array;
  instances?: Float32Array;
  protoBounds?: [number[], number[]];
  /** Drawn reduced (too large for the viewport): `[drawn, of]` triangles or points. */
  reduced?: { triangles?: [number, number]; points?: [number, number] };
}

/** The viewport's notice for a reduced geometry, or '' when drawn whole. */
export function reducedNotice(parts: GeometryPart[]): string {
  const sum = (k: 'triangles' | 'points') =>
    parts.reduce<[number, number] | null>((acc, p) => {
      const r = p.reduced?.[k];
      return r ? [(acc?.[0] ?? 0) + r[0], (acc?.[1] ?? 0) + r[1]] : acc;
    }, null);
  const say = (k: 'triangles' | 'points', r: [number, number] | null) => (r ? `${r[0].toLocaleString('en')} of ${r[1].toLocaleString('en')} ${k}` : '');
  const what = [say('triangles', sum('triangles')), say('points', sum('points'))].filter(Boolean).join(', ');
  return what ? `reduced for the viewport: ${what} drawn` : '';
}

export interface DecodedGeometry {
  generation: number;
  node: string;
  bounds: [number[], number[]] | null;
  parts: GeometryPart[];
  bytes: number;
  /** A templated node's result: drawn as a ghost beside the viewed one. */
  template?: boolean;
  /** A delta: only the arrays that changed since this generation (the parts hold just those). */
  deltaOf?: number;
}


const FLOAT_KEYS = ['positions', 'normals', 'colors', 'corners', 'cornerNormals', 'cornerColors', 'instances'] as const;
const UINT_KEYS = ['polygons', 'polygonSizes', 'cornerTriangles', 'lines', 'points'] as const;

/** Decodes a `GEO1` message (see crates/server/src/viewport.rs) without copying its arrays. */
/** The fan triangles (first vertex as apex) of polygons given as point indices and vertex counts (one count for all, or one each): the server's order, which picking relies on. */
export function fanTriangles(points: Uint32Array, sizes: Uint32Array | number): Uint32Array {
  const count = typeof sizes === 'number' ? Math.floor(points.length / sizes) : sizes.length;
  const size = (i: number) => (typeof sizes === 'number' ? sizes : sizes[i]);
  let tris = 0;
  for (let i = 0; i < count; i++) tris += Math.max(0, size(i) - 2);
  const out = new Uint32Array(tris * 3);
  let at = 0;
  let o = 0;
  for (let i = 0; i < count; i++) {
    const n = size(i);
    for (let k = 1; k < n - 1; k++) {
      out[o++] = points[at];
      out[o++] = points[at + k];
      out[o++] = points[at + k + 1];
    }
    at += n;
  }
  return out;
}

/** The edges of polygons (point index pairs, each polygon closed), as a template or wireframe draws them. */
export function polygonEdges(points: Uint32Array, sizes: Uint32Array | number): Uint32Array {
  const count = typeof sizes === 'number' ? Math.floor(points.length / sizes) : sizes.length;
  const out = new Uint32Array(points.length * 2);
  let at = 0;
  let o = 0;
  for (let i = 0; i < count; i++) {
    const n = typeof sizes === 'number' ? sizes : sizes[i];
    for (let k = 0; k < n; k++) {
      out[o++] = points[at + k];
      out[o++] = points[at + ((k + 1) % n)];
    }
    at += n;
  }
  return out.subarray(0, o);
}

export function decodeGeometry(buf: ArrayBuffer): DecodedGeometry {
  const magic = new TextDecoder().decode(new Uint8Array(buf, 0, 4));
  if (magic !== 'GEO1') throw new Error(`not a geometry message (${JSON.stringify(magic)})`);
  const headerLen = new DataView(buf).getUint32(4, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 8, headerLen))) as {
    generation: number;
    node: string;
    bounds: [number[], number[]] | null;
    parts: Record<string, unknown>[];
    template?: boolean;
    deltaOf?: number;
  };
  const base = 8 + headerLen;
  const parts = header.parts.map((p) => {
    const part: GeometryPart = { name: String(p.name), positions: new Float32Array(0) };
    const out = part as unknown as Record<string, unknown>;
    for (const k of FLOAT_KEYS) {
      const r = p[k] as [number, number] | undefined;
      if (r) out[k] = new Float32Array(buf, base + r[0], r[1]);
    }
    for (const k of UINT_KEYS) {
      const r = p[k] as [number, number] | undefined;
      if (r) out[k] = new Uint32Array(buf, base + r[0], r[1]);
    }
    for (const k of ['normalsUniform', 'colorsUniform', 'protoBounds', 'reduced'] as const) {
      if (p[k]) out[k] = p[k];
    }
    if (p.polygonSize) part.polygonSize = Number(p.polygonSize);
    if (part.polygons) part.triangles = fanTriangles(part.polygons, part.polygonSizes ?? part.polygonSize ?? 3);
    return part;
  });
  return { generation: header.generation, node: header.node, bounds: header.bounds, parts, bytes: buf.byteLength, template: header.template === true, deltaOf: header.deltaOf };
}

/** The arrays a part may carry. */
export const PART_ARRAYS = [...FLOAT_KEYS, ...UINT_KEYS];

/** `base` with the arrays a delta carries put in (same parts, in order). */
export function mergeDelta(base: DecodedGeometry, delta: DecodedGeometry): DecodedGeometry {
  const parts = base.parts.map((p, i) => {
    const d = delta.parts[i] as unknown as Record<string, unknown>;
    const out = { ...p } as unknown as Record<string, unknown>;
    for (const k of PART_ARRAYS) if (d && d[k] !== undefined && (d[k] as ArrayLike<number>).length) out[k] = d[k];
    return out as unknown as GeometryPart;
  });
  return { ...delta, parts, deltaOf: undefined };
}

/** The array keys a delta changes, per part. */
export function deltaKeys(delta: DecodedGeometry): string[][] {
  return delta.parts.map((p) => PART_ARRAYS.filter((k) => ((p as unknown as Record<string, unknown>)[k] as ArrayLike<number> | undefined)?.length));
}

type Listener = (msg: ServerMsg) => void;
type BinaryListener = (buf: ArrayBuffer) => void;

/** The studio's socket: requests carry ids and resolve with their reply. */
export class Connection {
  private ws: WebSocket;
  private nextId = 1;
  private pending = new Map<number, (r: ReplyMsg) => void>();
  private opened: Promise<void>;

  constructor(
    url: string,
    private onMessage: Listener,
    private onBinary: BinaryListener,
    onClose: () => void,
  ) {
    this.ws = new WebSocket(url);
    this.ws.binaryType = 'arraybuffer';
    this.opened = new Promise((resolve) => this.ws.addEventListener('open', () => resolve()));
    this.ws.addEventListener('close', onClose);
    this.ws.addEventListener('message', (ev) => {
      if (typeof ev.data !== 'string') {
        this.onBinary(ev.data as ArrayBuffer);
        return;
      }
      const msg = JSON.parse(ev.data) as ServerMsg;
      if (msg.type === 'reply' && msg.id != null) {
        this.pending.get(msg.id)?.(msg);
        this.pending.delete(msg.id);
      }
      this.onMessage(msg);
    });
  }

  async request(body: Record<string, unknown>): Promise<ReplyMsg> {
    await this.opened;
    const id = this.nextId++;
    return new Promise((resolve) => {
      this.pending.set(id, resolve);
      this.ws.send(JSON.stringify({ ...body, id }));
    });
  }
}

/** The last cook's errors while they are about the shown state; none while a newer cook runs (they may be fixed). */
export function freshCookErrors(state: StateMsg | null, cooked: CookedMsg | null): Problem[] {
  if (!cooked || (state && cooked.generation < state.generation)) return [];
  return cooked.errors;
}

/**
 * Load problems and cook errors of one node, each said once: a node with a
 * load problem fails its cook with that same problem (kind aside).
 */
export function uniqueProblems(problems: Problem[]): Problem[] {
  const seen = new Set<string>();
  return problems.filter((p) => {
    const key = `${p.path}\u0000${p.param ?? ''}\u0000${p.message}`;
    if (seen.has(key)) return false;
    seen.add(key);
    return true;
  });
}

/** Whether a node holds a network the editor can dive into: the catalogue says which types do. */
export function hasNetwork(node: DocNode | null | undefined, types: ReadonlyMap<string, NodeType>): boolean {
  return !!node && (node.network !== undefined || types.get(node.type)?.network === true);
}

/** The fields of a ramp's keys, as the catalogue declares them (crates/op/src/param.rs). */
export function rampFields(colour: boolean): ParamDecl[] {
  const field = (name: string, label: string, type: ParamDecl['type'], dflt: unknown, help: string, extra: Partial<ParamDecl> = {}): ParamDecl => ({
    name, label, type, default: dflt, min: null, max: null, animatable: type !== 'menu', help, affects: null, ...extra,
  });
  return [
    field('pos', 'Position', 'float', 0, 'Where the key sits along the ramp (0 to 1).', { min: 0, max: 1 }),
    colour ? field('value', 'Colour', 'vec3', [0, 0, 0], "The key's colour.") : field('value', 'Value', 'float', 0, "The key's value."),
    field('interp', 'Interpolation', 'menu', 'linear', 'How the segment from this key to the next is drawn.', { items: ['constant', 'linear', 'catmull-rom', 'monotonecubic', 'bspline'] }),
  ];
}

const SPARE_TYPES: Record<string, { type: ParamDecl['type']; default: unknown }> = {
  float: { type: 'float', default: 0 },
  int: { type: 'int', default: 0 },
  toggle: { type: 'toggle', default: false },
  vector2: { type: 'vec2', default: [0, 0] },
  vector: { type: 'vec3', default: [0, 0, 0] },
  vector4: { type: 'vec4', default: [0, 0, 0, 0] },
  string: { type: 'string', default: '' },
  ramp: { type: 'ramp', default: [{ pos: 0, value: 0, interp: 'linear' }, { pos: 1, value: 1, interp: 'linear' }] },
  colorramp: { type: 'colorramp', default: [{ pos: 0, value: [0, 0, 0], interp: 'linear' }, { pos: 1, value: [1, 1, 1], interp: 'linear' }] },
};

/** Declarations of a node's spare parameters, as the panel shows them. */
export function spareDecls(node: DocNode): ParamDecl[] {
  return Object.entries(node.spare ?? {}).flatMap(([name, ty]) => {
    const t = SPARE_TYPES[ty];
    if (!t) return [];
    return [{
      name,
      label: name,
      type: t.type,
      default: t.default,
      min: null,
      max: null,
      animatable: t.type !== 'string',
      help: t.type === 'ramp' || t.type === 'colorramp' ? `Spare parameter (${ty}), read in the snippet with chramp("${name}", x).` : `Spare parameter (${ty}), read in the snippet with ch("${name}").`,
      affects: null,
      ...(t.type === 'ramp' || t.type === 'colorramp' ? { fields: rampFields(t.type === 'colorramp') } : {}),
    }];
  });
}
