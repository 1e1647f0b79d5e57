// The node info panel (Houdini's middle-click info): what the node cooked to at the viewed frame (counts, memory, attributes by class, groups), its cook time and cache key, and its warnings or errors, in a popup over the network editor.

import { describeValue } from './params';

export interface GeometryInfo {
  points: number;
  vertices: number;
  primitives: number;
  memory: number;
  kinds: Record<string, number>;
  attributes: { class: string; name: string; type: string }[];
  pointGroups: string[];
  primGroups: string[];
}

export interface NodeInfo {
  path: string;
  type: string | null;
  frame: number;
  animated: boolean;
  key?: string;
  hit?: boolean;
  ms?: number;
  upstreamMs?: number;
  bytes?: number;
  warnings?: string[];
  errors?: { message: string; param?: string | null }[];
  value?: GeometryInfo | { bundle: Record<string, GeometryInfo> } | { field: true };
}

/** Bytes as the HUD and the info panel show them (binary units). */
export function human(b: number): string {
  const u = ['B', 'KiB', 'MiB', 'GiB'];
  let i = 0;
  while (b >= 1024 && i < 3) {
    b /= 1024;
    i++;
  }
  return `${b.toFixed(i ? 1 : 0)} ${u[i]}`;
}

function section(title: string, lines: string[]): string {
  const esc = (s: string) => s.replace(/[&<>]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;' })[c]!);
  return lines.length ? `<h4>${esc(title)}</h4>${lines.map((l) => `<div>${esc(l)}</div>`).join('')}` : '';
}

function geometryLines(g: GeometryInfo, label = ''): string {
  const kinds = Object.entries(g.kinds).map(([k, n]) => `${n.toLocaleString('en')} ${k}`).join(', ');
  const byClass = ['point', 'vertex', 'primitive', 'detail'].map((c) => [c, g.attributes.filter((a) => a.class === c).map((a) => `${a.name} (${a.type})`)] as const).filter(([, l]) => l.length);
  return (
    section(label || 'Geometry', [
      `${g.points.toLocaleString('en')} points, ${g.primitives.toLocaleString('en')} primitives, ${g.vertices.toLocaleString('en')} vertices`,
      ...(kinds ? [kinds] : []),
      `${human(g.memory)} in memory`,
    ]) +
    section('Attributes', byClass.map(([c, l]) => `${c}: ${l.join(', ')}`)) +
    section('Groups', [...g.pointGroups.map((n) => `point: ${n}`), ...g.primGroups.map((n) => `primitive: ${n}`)])
  );
}

/** The panel's HTML for an info reply. */
export function infoHtml(i: NodeInfo): string {
  const cook = [
    i.ms !== undefined ? `${i.hit ? 'from the cache' : `cooked in ${describeValue(Number(i.ms.toFixed(2)))} ms`} at frame ${i.frame}${i.animated ? ' (animated)' : ''}` : '',
    i.upstreamMs !== undefined ? `with its inputs: ${describeValue(Number(i.upstreamMs.toFixed(2)))} ms` : '',
    i.bytes !== undefined ? `result: ${human(i.bytes)}` : '',
    i.key ? `cache key ${i.key}` : '',
  ].filter(Boolean);
  let value = '';
  if (i.value && 'points' in i.value) value = geometryLines(i.value);
  else if (i.value && 'bundle' in i.value) value = Object.entries(i.value.bundle).map(([n, g]) => geometryLines(g, `Entry ${n}`)).join('');
  else if (i.value) value = section('Value', ['a field (no geometry)']);
  return (
    `<div class="info-head"><b></b> <span class="dim"></span><button class="info-close" title="Close (Esc)">×</button></div>` +
    section('Cook', cook) +
    value +
    section('Warnings', i.warnings ?? []) +
    section('Errors', (i.errors ?? []).map((e) => (e.param ? `${e.param}: ${e.message}` : e.message)))
  );
}

/** Shows the panel in `host` for `info`; Esc or × closes it. */
export function showInfo(host: HTMLElement, info: NodeInfo): HTMLElement {
  host.querySelector('.node-info')?.remove();
  const panel = document.createElement('div');
  panel.className = 'node-info';
  panel.tabIndex = -1;
  panel.innerHTML = infoHtml(info);
  panel.querySelector('.info-head b')!.textContent = info.path;
  panel.querySelector('.info-head .dim')!.textContent = info.type ?? '';
  const close = () => panel.remove();
  panel.querySelector('.info-close')!.addEventListener('click', close);
  panel.addEventListener('keydown', (e) => {
    if (e.key === 'Escape') {
      e.stopPropagation();
      close();
    }
  });
  host.appendChild(panel);
  panel.focus();
  return panel;
}
