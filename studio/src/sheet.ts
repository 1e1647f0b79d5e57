// The geometry spreadsheet (Houdini's): the viewed result's points, vertices, primitives or detail with every attribute and group, virtualised so that only the rows on screen exist and are fetched.

export const ROW_H = 20;
const CHUNK = 200;

export type SheetClass = 'point' | 'vertex' | 'primitive' | 'detail';

interface Window {
  columns: string[];
  total: number;
  start: number;
  rows: string[][];
  generation: number;
}

/** The chunks (of CHUNK rows) covering rows `first..last`. */
export function chunksFor(first: number, last: number): number[] {
  const out: number[] = [];
  for (let c = Math.floor(Math.max(0, first) / CHUNK); c * CHUNK <= last; c++) out.push(c);
  return out;
}

/** Columns that are not attributes: vertex and primitive built-ins, groups. */
const BUILTIN_COLUMNS = new Set(['Point', 'Type', 'Vertices']);

/** The attribute names behind a window's column labels (`P[x]`, `P[y]`, `P[z]` are `P`). */
export function attributeNames(columns: string[]): string[] {
  const names = columns.filter((c) => !BUILTIN_COLUMNS.has(c) && !c.startsWith('group:')).map((c) => c.replace(/\[\w+\]$/, ''));
  return [...new Set(names)];
}

/** The viewed result's attributes by class, as the spreadsheet last received them (what snippet completion offers). */
const seenAttributes = new Map<SheetClass, string[]>();

/** Attributes of the viewed result that the spreadsheet has seen, point ones first. */
export function viewedAttributes(): { name: string; cls: SheetClass }[] {
  return (['point', 'primitive', 'vertex', 'detail'] as SheetClass[]).flatMap((cls) => (seenAttributes.get(cls) ?? []).map((name) => ({ name, cls })));
}

export class Spreadsheet {
  cls: SheetClass = 'point';
  private chunks = new Map<number, string[][]>();
  private loading = new Set<number>();
  private columns: string[] = [];
  total = 0;
  private generation = -1;
  private body: HTMLDivElement;
  private spacer: HTMLDivElement;
  private head: HTMLDivElement;
  private rowsEl: HTMLDivElement;
  private selectedRow: number | null = null;

  constructor(
    private host: HTMLElement,
    private fetchRows: (cls: SheetClass, start: number, count: number) => Promise<Window | null>,
    private onPick: (row: Record<string, string>) => void,
  ) {
    const tabs = document.createElement('div');
    tabs.className = 'sheet-tabs';
    for (const c of ['point', 'vertex', 'primitive', 'detail'] as SheetClass[]) {
      const b = document.createElement('button');
      b.textContent = { point: 'Points', vertex: 'Vertices', primitive: 'Primitives', detail: 'Detail' }[c];
      b.dataset.cls = c;
      b.addEventListener('click', () => {
        this.cls = c;
        tabs.querySelectorAll('button').forEach((x) => x.classList.toggle('on', x === b));
        this.reset();
      });
      if (c === 'point') b.classList.add('on');
      tabs.appendChild(b);
    }
    this.head = document.createElement('div');
    this.head.className = 'sheet-head';
    this.body = document.createElement('div');
    this.body.className = 'sheet-body';
    this.spacer = document.createElement('div');
    this.rowsEl = document.createElement('div');
    this.rowsEl.className = 'sheet-rows';
    this.body.append(this.spacer, this.rowsEl);
    host.append(tabs, this.head, this.body);
    this.body.addEventListener('scroll', () => {
      this.head.scrollLeft = this.body.scrollLeft;
      this.draw();
    });
    this.rowsEl.addEventListener('click', (e) => {
      const r = (e.target as Element).closest('[data-row]') as HTMLElement | null;
      if (!r) return;
      this.selectedRow = Number(r.dataset.row);
      const cells = this.chunks.get(Math.floor(this.selectedRow / CHUNK))?.[this.selectedRow % CHUNK] ?? [];
      this.onPick(Object.fromEntries(this.columns.map((c, i) => [c, cells[i]])));
      this.draw();
    });
  }

  /** Shows row `row` of class `cls` selected and scrolled into view (a pick in the viewport). */
  reveal(cls: SheetClass, row: number) {
    if (cls !== this.cls) {
      this.cls = cls;
      this.host.querySelectorAll<HTMLButtonElement>('.sheet-tabs button').forEach((b) => b.classList.toggle('on', b.dataset.cls === cls));
      this.reset();
    }
    this.selectedRow = row;
    const top = row * ROW_H;
    if (top < this.body.scrollTop || top + ROW_H > this.body.scrollTop + this.body.clientHeight) {
      this.body.scrollTop = Math.max(0, top - this.body.clientHeight / 2);
    }
    this.draw();
  }

  /** A new result: forget the rows held. */
  invalidate(generation: number) {
    if (generation === this.generation) return;
    this.generation = generation;
    seenAttributes.clear();
    this.reset();
  }

  private reset() {
    this.chunks.clear();
    this.loading.clear();
    this.selectedRow = null;
    void this.load(Math.floor(this.body.scrollTop / ROW_H / CHUNK));
  }

  private async load(chunk: number) {
    if (this.loading.has(chunk)) return;
    this.loading.add(chunk);
    const generation = this.generation;
    const cls = this.cls;
    const w = await this.fetchRows(cls, chunk * CHUNK, CHUNK);
    if (!w || generation !== this.generation || cls !== this.cls) return;
    this.columns = w.columns;
    seenAttributes.set(cls, attributeNames(w.columns));
    this.total = w.total;
    this.chunks.set(chunk, w.rows);
    this.draw();
  }

  /** Column widths that fit their labels and the values of the rows held (at most 480 px). */
  private widths(): number[] {
    const longest = this.columns.map((c) => c.length);
    for (const rows of this.chunks.values()) {
      for (const r of rows) r.forEach((v, i) => (longest[i] = Math.max(longest[i] ?? 0, v.length)));
    }
    return longest.map((n) => Math.min(480, Math.max(96, n * 7.5 + 16)));
  }

  draw() {
    this.spacer.style.height = `${this.total * ROW_H}px`;
    const widths = this.widths();
    const row = (cells: string[], cls: string, index?: number) => {
      const d = document.createElement('div');
      d.className = cls;
      if (index !== undefined) d.dataset.row = String(index);
      const idx = document.createElement('span');
      idx.className = 'idx';
      idx.textContent = index === undefined ? '' : String(index);
      d.appendChild(idx);
      cells.forEach((c, i) => {
        const s = document.createElement('span');
        s.style.width = `${widths[i]}px`;
        s.textContent = c;
        d.appendChild(s);
      });
      return d;
    };
    this.head.replaceChildren(row(this.columns, 'sheet-row head'));
    const first = Math.floor(this.body.scrollTop / ROW_H);
    const last = Math.min(this.total - 1, first + Math.ceil(this.body.clientHeight / ROW_H) + 1);
    const out: HTMLElement[] = [];
    for (const c of chunksFor(first, last)) if (!this.chunks.has(c)) void this.load(c);
    for (let i = first; i <= last; i++) {
      const cells = this.chunks.get(Math.floor(i / CHUNK))?.[i % CHUNK];
      const r = row(cells ?? this.columns.map(() => '…'), 'sheet-row' + (i === this.selectedRow ? ' selected' : ''), i);
      r.style.top = `${i * ROW_H}px`;
      out.push(r);
    }
    this.rowsEl.replaceChildren(...out);
  }
}
