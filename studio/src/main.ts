// The studio page: connects to `geode serve`, wires the editor, parameter panel, timeline, viewport, spreadsheet and trace to the session, and does what keymap.ts's keys ask.

import './style.css';
import { NetworkEditor } from './editor';
import { join, lastKeyFrame, nodeAt, parentOf } from './network';
import { ParamPanel } from './params';
import { CurveEditor, curvesOf } from './curves';
import { human, showInfo, type NodeInfo } from './info';
import { CookBar } from './cookbar';
import { bindingFor, type Action } from './keymap';
import { Connection, decodeGeometry, reducedNotice, type CookedMsg, type DocNetwork, type NodeType, type ProgressMsg, type ServerMsg } from './protocol';
import { Spreadsheet, type SheetClass } from './sheet';
import { createStore } from './store';
import { TabMenu } from './tabmenu';
import { Timeline } from './timeline';
import { renderTrace } from './trace';
import { Viewport, type Drawn, type ViewName, type ViewportHit } from './viewport';

const $ = <T extends HTMLElement>(sel: string) => document.querySelector(sel) as T;

const store = createStore();
const token = new URLSearchParams(location.search).get('token') ?? '';
const status = $('#status');
const log: string[] = [];

function say(text: string, bad = false) {
  status.textContent = text;
  // One line in the bar; the whole message on hover.
  status.title = text;
  status.classList.toggle('bad', bad);
  log.push(text);
}

/** Undo or redo this tab's latest step; says why when refused (another tab's change is the latest). */
async function history(op: 'undo' | 'redo') {
  const r = await conn.request({ op });
  if (!r.ok) say(r.error ?? `nothing to ${op}`, r.kind === 'history' && !/^nothing/.test(r.error ?? ''));
}

/** Resolves when the next state arrives (or after `timeout` ms). */
const stateWaiters: (() => void)[] = [];
function nextState(timeout: number): Promise<void> {
  return new Promise((resolve) => {
    stateWaiters.push(resolve);
    setTimeout(resolve, timeout);
  });
}

async function edit(e: Record<string, unknown>, merge = false): Promise<boolean> {
  const r = await conn.request({ op: 'edit', edit: e, merge });
  if (!r.ok) say(r.error ?? 'refused', true);
  return r.ok;
}

function select(paths: string[], current?: string | null) {
  store.selected = new Set(paths);
  if (current !== undefined) store.current = current;
  store.notify();
}

function view(path: string | null) {
  void conn.request({ op: 'view', node: path });
}

function setFrame(f: number) {
  void conn.request({ op: 'frame', frame: Math.round(f) });
}

const viewport = new Viewport($('#viewport'));
const editor = new NetworkEditor($('#editor'), store, {
  edit,
  view,
  select,
  openTabMenu: () => undefined,
  info: (path: string) => void openInfo(path),
});

/** The node info panel for `path`, over the network editor. */
async function openInfo(path: string) {
  const r = await conn.request({ op: 'info', path });
  if (!r.ok) {
    say(`info: ${r.error ?? 'failed'}`, true);
    return;
  }
  showInfo($('#editor'), r.info as NodeInfo);
}
const params = new ParamPanel($('#params'), store, {
  edit,
  values: async (path: string) => {
    const r = await conn.request({ op: 'values', path });
    return (r.values ?? {}) as Record<string, unknown>;
  },
});
const timeline = new Timeline($('#timeline'), store, setFrame, (frames, fps) => void edit({ kind: 'set_timeline', frames, fps }));
const curves = new CurveEditor($('#curves'), store, {
  setParam: (path, param, value, merge) => edit({ kind: 'set_param', path, param, value }, merge),
  setFrame,
});
const tabMenu = new TabMenu(() => [...store.catalogue.values()]);
const sheet = new Spreadsheet(
  $('#sheet'),
  async (cls: SheetClass, start: number, count: number) => {
    const r = await conn.request({ op: 'sheet', class: cls, start, count });
    return r.ok ? (r as never) : null;
  },
  (row) => {
    const p = ['P[x]', 'P[y]', 'P[z]'].map((k) => Number(row[k]));
    viewport.select(p.every(Number.isFinite) ? [p as [number, number, number]] : []);
  },
);

/** What tests and benchmarks read: the last state, cook and drawing. */
const probe = {
  store,
  timeline,
  viewport,
  log,
  drawn: null as Drawn | null,
  cooks: [] as CookedMsg[],
  progress: [] as ProgressMsg[],
  /** The last redraws' times: editor, parameters, the rest (ms). */
  panes: [] as number[][],
  received: 0,
  /** The last pick's point, vertex and primitive. */
  picked: null as { point: number; vertex: number | null; primitive: number | null } | null,
  /** When the last `cooked` message arrived (performance.now()). */
  cookedAt: 0,
  edit,
  request: (body: Record<string, unknown>) => conn.request(body),
};
(window as unknown as { __geode: typeof probe }).__geode = probe;

function onMessage(msg: ServerMsg) {
  switch (msg.type) {
    case 'state': {
      store.state = msg;
      // The network's own timeline wins; else one that covers its keys.
      if (msg.document.frames) store.range = [...msg.document.frames];
      else if (!store.rangeSet) store.range = [1, Math.max(24, lastKeyFrame(msg.document))];
      store.fps = msg.document.fps ?? 24;
      for (const resolve of stateWaiters.splice(0)) queueMicrotask(resolve);
      if (store.at !== '/' && !nodeAt(msg.document, store.at)) store.at = '/';
      store.selected = new Set([...store.selected].filter((p) => nodeAt(msg.document, p)));
      if (store.current && !nodeAt(msg.document, store.current)) store.current = null;
      if (!store.current && msg.view.solo) store.current = msg.view.solo;
      store.progress.clear();
      viewport.keepTemplates(templatedPaths());
      break;
    }
    case 'progress':
      if (msg.generation === store.state?.generation) store.progress.set(msg.node, msg.fraction);
      probe.progress.push(msg);
      if (probe.progress.length > 1000) probe.progress.shift();
      break;
    case 'cooked': {
      if (store.cooked && msg.generation < store.cooked.generation) return;
      store.cooked = msg;
      probe.cooks.push(msg);
      probe.cookedAt = performance.now();
      for (const e of msg.events) store.badges.set(e.path, { ms: e.ms, hit: e.hit, warnings: e.warnings ?? [] });
      store.progress.clear();
      const misses = msg.events.filter((e) => !e.hit).length;
      const warned = msg.events.flatMap((e) => (e.warnings ?? []).map((w) => `${e.path}: ${w}`));
      if (msg.ok && warned.length) say(`warning: ${warned.join('; ')}`);
      else if (msg.ok) say(`${msg.node} cooked in ${(msg.ms ?? 0).toFixed(1)} ms (${msg.events.length - misses} from cache, ${misses} cooked)`);
      else if (!msg.errors.every((e) => e.kind === 'cancelled')) say(msg.errors.map((e) => `${e.path}: ${e.message}`).join('; '), true);
      if (!msg.hasGeometry && msg.ok) viewport.clear();
      sheet.invalidate(msg.generation);
      if (msg.frame !== undefined && (msg.ok || !msg.hasGeometry)) timeline.cooked(msg.frame, msg.events.length - misses, misses);
      renderTrace($('#trace'), msg);
      break;
    }
    case 'hello':
      store.client = msg.client;
      break;
    case 'cancelled':
      store.cancelled = Math.max(store.cancelled, msg.generation);
      store.progress.clear();
      say('cook cancelled');
      break;
    case 'reply':
      break;
  }
  store.notify();
}

function onBinary(buf: ArrayBuffer) {
  const received = performance.now();
  probe.received = received;
  const g = decodeGeometry(buf);
  if (g.template) {
    if (templatedPaths().has(g.node)) viewport.showTemplate(g);
    return;
  }
  if (store.cooked && g.generation < store.cooked.generation) return;
  if (g.deltaOf !== undefined) {
    const applied = viewport.applyDelta(g, received);
    if (applied) {
      void applied.then((d) => {
        probe.drawn = d;
        renderHud();
      });
      if (viewport.display.primNumbers) void loadPrimCenters();
    } else {
      // The delta's base is not what this page drew: ask for the whole geometry.
      void fetch('/api/geometry').then(async (r) => r.ok && onBinary(await r.arrayBuffer()));
    }
    return;
  }
  // A newly viewed node is framed; a recook of the same node keeps the camera.
  const framed = g.node !== viewport.drawn?.node;
  void viewport.show(g, received, framed).then((d) => {
    probe.drawn = d;
    notice = reducedNotice(g.parts);
    renderHud();
  });
  viewport.mark(null);
  if (viewport.display.primNumbers) void loadPrimCenters();
}

/** Paths of the nodes with the template flag. */
function templatedPaths(): Set<string> {
  const out = new Set<string>();
  const walk = (net: DocNetwork, at: string) => {
    for (const [name, node] of Object.entries(net.nodes)) {
      const path = join(at, name);
      if (node.template) out.add(path);
      if (node.network) walk(node.network, path);
    }
  };
  if (store.state) walk(store.state.document, '/');
  return out;
}

/** The viewed geometry's primitive centres for the primitive numbers. */
async function loadPrimCenters() {
  const r = await conn.request({ op: 'centers', limit: 50_000 });
  viewport.setPrimCenters(r.ok ? new Float32Array(r.centers as number[]) : null);
}

/** A click in the viewport: the element under it selected in the spreadsheet (its tab's class) and marked. */
async function pickAt(hit: ViewportHit | null) {
  if (!hit) {
    viewport.mark(null);
    return;
  }
  const r = await conn.request({ op: 'pick', entry: hit.entry, hit: hit.hit, at: hit.at });
  if (!r.ok) {
    say(`pick: ${r.error ?? 'nothing there'}`, true);
    return;
  }
  const p = r.picked as { point: number; vertex: number | null; primitive: number | null };
  probe.picked = p;
  const cls = sheet.cls === 'detail' ? 'point' : sheet.cls;
  const row = cls === 'point' ? p.point : cls === 'vertex' ? p.vertex : p.primitive;
  if (row !== null) sheet.reveal(cls, row);
  viewport.mark(hit.at);
  say(`picked point ${p.point}${p.primitive !== null ? `, primitive ${p.primitive}` : ''}${p.vertex !== null ? `, vertex ${p.vertex}` : ''}`);
}
viewport.onPick = (hit) => void pickAt(hit);

const conn = new Connection(
  `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws?token=${encodeURIComponent(token)}`,
  onMessage,
  onBinary,
  () => say('Disconnected from geode serve: restart it and reload this page.', true),
);


/** What the viewport says of a result it draws reduced. */
let notice = '';

function renderHud() {
  const s = store.state;
  const c = store.cooked;
  const viewed = s?.view.solo ?? s?.output ?? '—';
  // The counts are the drawn result's: name its node, and the one cooking if another.
  const shown = c?.node && c.node !== viewed ? `${c.node} (showing it until ${viewed} has cooked)` : viewed;
  const st = c?.stats as { points?: number; primitives?: number; vertices?: number; memory?: number; bounds?: number[][] | null } | null | undefined;
  const d = viewport.drawn;
  const lines = [
    `${shown}${s?.view.solo ? (s.view.auto ? ' (auto-solo)' : ' (solo)') : ''}`,
    st?.points !== undefined ? `${st.points} points · ${st.primitives} prims · ${st.vertices} vertices · ${human(st.memory ?? 0)}` : '',
    st?.bounds ? `bounds ${st.bounds.map((v) => `(${v.map((x) => x.toFixed(2)).join(', ')})`).join(' – ')}` : '',
    d ? `${d.triangles} triangles drawn${d.instances ? ` · ${d.instances} instances${d.instancesAsPoints ? ' as points' : ''}` : ''}` : '',
    notice,
    viewport.antialias ? '' : 'software rendering (no GPU): antialiasing off',
  ];
  $('#hud').textContent = lines.filter(Boolean).join('\n');
}

function renderTop() {
  const s = store.state;
  $('#file').textContent = (s?.path ?? 'untitled') + (s?.dirty ? ' ●' : '');
  $('#file').classList.toggle('dirty', !!s?.dirty);
  for (const [id, by, verb] of [['#undo', s?.undoBy, 'Undo (Ctrl-Z)'], ['#redo', s?.redoBy, 'Redo (Ctrl-Shift-Z)']] as const) {
    const b = $(id) as HTMLButtonElement;
    b.disabled = by !== store.client;
    b.title = by === null || by === undefined || by === store.client ? verb : `${verb}: another tab made the latest change; undo it there`;
  }
  const crumbs = $('#crumbs');
  crumbs.replaceChildren();
  const parts = store.at.split('/').filter(Boolean);
  ['/', ...parts].forEach((p, i) => {
    const b = document.createElement('button');
    b.textContent = i === 0 ? 'obj' : p;
    const at = i === 0 ? '/' : '/' + parts.slice(0, i).join('/');
    b.addEventListener('click', () => {
      store.at = at;
      store.notify();
    });
    crumbs.appendChild(b);
  });
  const solo = $('#solo-state');
  solo.textContent = s?.view.solo ? `viewing ${s.view.solo}${s.view.auto ? ' (auto)' : ''} ✕` : '';
}

const cookBar = new CookBar($('#viewport-wrap'), () => void conn.request({ op: 'cancel' }));
store.subscribe(() => cookBar.update(store));
store.subscribe(() => {
  const t0 = performance.now();
  editor.render();
  const t1 = performance.now();
  params.render();
  const t2 = performance.now();
  timeline.render(keyFrames());
  curves.render();
  renderTop();
  renderHud();
  probe.panes.push([t1 - t0, t2 - t1, performance.now() - t2]);
  if (probe.panes.length > 100) probe.panes.shift();
});

let spaceHeld = false;
window.addEventListener('keydown', (e) => e.key === ' ' && (spaceHeld = true));
window.addEventListener('keyup', (e) => e.key === ' ' && (spaceHeld = false));
window.addEventListener('blur', () => (spaceHeld = false));

/** The frames where the selected node has keys (ticks on the timeline). */
function keyFrames(): number[] {
  const node = store.current && store.state ? nodeAt(store.state.document, store.current) : null;
  return [...new Set(curvesOf(node?.params).flatMap((c) => c.keys.map((k) => k.frame)))];
}

async function save(path?: string) {
  const r = await conn.request(path ? { op: 'save', path } : { op: 'save' });
  if (r.ok) say(`saved ${String(r.saved)}`);
  else say(r.error ?? 'save failed', true);
}

function copy() {
  const s = store.state;
  if (!s) return;
  const nodes: Record<string, unknown> = {};
  for (const p of store.selected) {
    if (parentOf(p) !== store.at) continue;
    nodes[p.slice(p.lastIndexOf('/') + 1)] = nodeAt(s.document, p);
  }
  localStorage.setItem('geode-clipboard', JSON.stringify(nodes));
  say(`copied ${Object.keys(nodes).length} nodes`);
}

async function paste() {
  const text = localStorage.getItem('geode-clipboard');
  if (!text) return;
  await edit({ kind: 'paste', parent: store.at, nodes: JSON.parse(text) as unknown, offset: [30, 30] });
}

/** The Tab menu, at the mouse when it is over the editor: the new node lands there, wired after the selected node when their ports agree (as Houdini does). */
function openTab() {
  const r = editor.svg.getBoundingClientRect();
  const at = editor.mouseWorld();
  const [x, y] = editor.mouseClient() ?? [r.left + r.width / 3, r.top + 40];
  const after = store.current && parentOf(store.current) === store.at && store.selected.size === 1 ? store.current : null;
  tabMenu.open(x, y, (t: NodeType) => {
    void (async () => {
      const before = new Set(Object.keys(store.state ? (nodeAt(store.state.document, store.at)?.network?.nodes ?? (store.at === '/' ? store.state.document.nodes : {})) : {}));
      const from = after ? store.catalogue.get(nodeAt(store.state!.document, after)?.type ?? '') : undefined;
      const wire = after && from && t.inputs[0]?.type === from.output ? after : undefined;
      if (await edit({ kind: 'add_node', parent: store.at, type: t.name, pos: at, after: wire })) {
        const fresh = () => {
          const net = store.at === '/' ? store.state!.document.nodes : (nodeAt(store.state!.document, store.at)?.network?.nodes ?? {});
          return Object.keys(net).find((n) => !before.has(n));
        };
        // The reply can come before the state that holds the new node.
        if (!fresh()) await nextState(1000);
        const name = fresh();
        if (name) select([join(store.at, name)], join(store.at, name));
      }
    })();
  });
}

document.addEventListener('keydown', (e) => {
  const target = e.target as HTMLElement;
  const overViewport = document.querySelector('#viewport:hover') !== null;
  const binding = bindingFor({
    key: e.key,
    mod: e.ctrlKey || e.metaKey,
    shift: e.shiftKey,
    typing: target.closest?.('input, select, textarea') != null,
    inViewport: target.closest?.('#viewport') != null || overViewport,
    overViewport,
    spaceHeld,
  });
  if (!binding) return;
  if (binding.prevent) e.preventDefault();
  act(binding.action);
});

/** Does what a key asked for (see keymap.ts). */
function act(action: Action) {
  const current = store.current;
  const flagged = (flag: 'template' | 'bypass') => !!(current && nodeAt(store.state!.document, current)?.[flag]);
  switch (action) {
    case 'save':
      return void save();
    case 'undo':
    case 'redo':
      return void history(action);
    case 'copy':
      return copy();
    case 'paste':
      return void paste();
    case 'view-persp':
    case 'view-top':
    case 'view-front':
    case 'view-right': {
      const name = action.slice('view-'.length) as ViewName;
      viewport.setView(name);
      ($('#view-name') as HTMLSelectElement).value = name;
      return;
    }
    case 'tab-menu':
      return openTab();
    case 'delete':
      if (editor.deletePicked()) return;
      if (store.selected.size) void edit({ kind: 'remove_nodes', paths: [...store.selected] });
      return;
    case 'sticky-note':
      return editor.addNote();
    case 'network-box':
      return editor.boxSelection();
    case 'info':
      // A middle-click on a node shows it too.
      if (current) void openInfo(current);
      return;
    case 'template':
      // The current node drawn as a ghost beside the viewed one.
      if (current) void edit({ kind: 'set_flag', path: current, flag: 'template', on: !flagged('template') });
      return;
    case 'colour':
      return void editor.colour();
    case 'dive':
      if (current) editor.dive(current);
      return store.notify();
    case 'up':
      editor.up();
      return store.notify();
    case 'frame-selection-in-viewport':
      return viewport.frame(true);
    case 'frame-selection-in-editor':
      return editor.frame(store.selected.size > 0);
    case 'frame-all-in-viewport':
      return viewport.frame(false);
    case 'frame-all-in-editor':
      return editor.frame(false);
    case 'display':
      if (current) void edit({ kind: 'set_flag', path: current, flag: 'display', on: true });
      return;
    case 'bypass':
      if (current) void edit({ kind: 'set_flag', path: current, flag: 'bypass', on: !flagged('bypass') });
      return;
    case 'solo':
      // The view flag, where Houdini has template.
      if (current) view(store.state?.view.solo === current ? null : current);
      return;
    case 'cancel':
      return void conn.request({ op: 'cancel' });
    case 'rename':
      if (current && parentOf(current) === store.at) editor.rename(current.slice(current.lastIndexOf('/') + 1));
      return;
    case 'timeline':
      return timeline.toggle();
  }
}

$('#undo').addEventListener('click', () => void history('undo'));
$('#redo').addEventListener('click', () => void history('redo'));
$('#save').addEventListener('click', () => void save());
$('#save-as').addEventListener('click', () => {
  const p = window.prompt('Save the network as (a .json path on the machine running geode serve):', store.state?.path ?? 'network.json');
  if (p) void save(p);
});
/** Downloads the viewed node in `format`; says what the writer warned of (attributes a format left out). */
async function exportAs(format: string) {
  const r = await fetch(`/api/export?format=${encodeURIComponent(format)}`);
  if (!r.ok) {
    say(`export: ${await r.text()}`, true);
    return;
  }
  const name = /filename="([^"]+)"/.exec(r.headers.get('content-disposition') ?? '')?.[1] ?? `export.${format}`;
  const warnings = JSON.parse(r.headers.get('x-geode-warnings') ?? '[]') as string[];
  const a = document.createElement('a');
  a.href = URL.createObjectURL(await r.blob());
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 60_000);
  say(warnings.length ? `exported ${name}; ${warnings.join('; ')}` : `exported ${name}`, warnings.length > 0);
}
$('#export').addEventListener('change', () => {
  const sel = $('#export') as HTMLSelectElement;
  if (sel.value) void exportAs(sel.value);
  sel.value = '';
});
$('#solo-state').addEventListener('click', () => view(null));
$('#view-btn').addEventListener('click', () => store.current && view(store.current));
for (const [id, key] of [['#show-points', 'points'], ['#show-normals', 'normals'], ['#show-ptnum', 'pointNumbers'], ['#show-primnum', 'primNumbers']] as const) {
  $(id).addEventListener('change', () => {
    viewport.display[key] = ($(id) as HTMLInputElement).checked;
    if (key === 'primNumbers' && viewport.display.primNumbers) void loadPrimCenters();
    viewport.rebuild();
  });
}
$('#view-name').addEventListener('change', () => viewport.setView(($('#view-name') as HTMLSelectElement).value as ViewName));
for (const [id, key] of [['#wire', 'wireframe'], ['#flat', 'forceFlat']] as const) {
  $(id).addEventListener('change', () => {
    viewport[key] = ($(id) as HTMLInputElement).checked;
    viewport.rebuild();
  });
}
for (const b of document.querySelectorAll<HTMLButtonElement>('.panel-tabs button')) {
  b.addEventListener('click', () => {
    document.querySelectorAll<HTMLElement>('.panel-tabs button').forEach((x) => x.classList.toggle('on', x === b));
    $('#sheet').hidden = b.dataset.panel !== 'sheet';
    $('#trace').hidden = b.dataset.panel !== 'trace';
    $('#curves').hidden = b.dataset.panel !== 'curves';
    if (b.dataset.panel === 'sheet') sheet.draw();
    if (b.dataset.panel === 'curves') curves.render();
  });
}

void fetch(`/api/catalogue`)
  .then((r) => r.json() as Promise<{ nodes: NodeType[] }>)
  .then((c) => {
    for (const t of c.nodes) store.catalogue.set(t.name, t);
    store.notify();
  });
