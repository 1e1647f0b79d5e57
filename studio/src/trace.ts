// The trace panel: the last cook's spans (node, start, time, cache hit or cook) as a waterfall, and the Chrome trace to download.

import type { CookedMsg } from './protocol';

export function renderTrace(host: HTMLElement, cooked: CookedMsg | null) {
  host.replaceChildren();
  const bar = document.createElement('div');
  bar.className = 'trace-bar';
  const events = [...(cooked?.events ?? [])].sort((a, b) => a.start - b.start);
  const hits = events.filter((e) => e.hit).length;
  bar.innerHTML = `<span class="trace-summary"></span> <a class="download" href="/api/trace.json" download="geode-trace.json">Download Chrome trace</a>`;
  bar.querySelector('.trace-summary')!.textContent = cooked
    ? `${cooked.node ?? ''} · ${events.length} nodes · ${hits} from cache · ${events.length - hits} cooked · ${(cooked.ms ?? 0).toFixed(1)} ms`
    : 'No cook yet.';
  host.appendChild(bar);
  const end = Math.max(1e-3, ...events.map((e) => e.start + e.ms));
  const table = document.createElement('div');
  table.className = 'trace-table';
  for (const e of events) {
    const row = document.createElement('div');
    row.className = 'trace-row ' + (e.hit ? 'hit' : 'miss');
    row.dataset.path = e.path;
    row.innerHTML = `<span class="p"></span><span class="t"></span><span class="ms"></span><span class="h"></span><span class="lane"><i></i></span>`;
    row.querySelector('.p')!.textContent = e.path;
    row.querySelector('.t')!.textContent = e.type;
    row.querySelector('.ms')!.textContent = `${e.ms.toFixed(2)} ms`;
    row.querySelector('.h')!.textContent = e.hit ? 'hit' : 'cook';
    const i = row.querySelector('i')!;
    i.style.left = `${(100 * e.start) / end}%`;
    i.style.width = `${Math.max(0.5, (100 * e.ms) / end)}%`;
    table.appendChild(row);
  }
  host.appendChild(table);
}
