// The Tab menu: the node catalogue by category, filtered as you type (name, label, words of the summary), Enter or click to place a node.

import type { NodeType } from './protocol';

/** Node types matching a query, best first: name prefix, then label or name substring, then summary words. */
export function filterCatalogue(types: NodeType[], query: string): NodeType[] {
  const q = query.trim().toLowerCase();
  if (!q) return types;
  const score = (t: NodeType): number => {
    const name = t.name.toLowerCase();
    const label = t.label.toLowerCase();
    if (name === q) return 0;
    if (name.startsWith(q) || label.startsWith(q)) return 1;
    if (name.includes(q) || label.includes(q)) return 2;
    if (q.split(/\s+/).every((w) => t.summary.toLowerCase().includes(w) || t.category.toLowerCase().includes(w))) return 3;
    return -1;
  };
  return types
    .map((t) => [score(t), t] as const)
    .filter(([s]) => s >= 0)
    .sort((a, b) => a[0] - b[0] || a[1].name.localeCompare(b[1].name))
    .map(([, t]) => t);
}

export class TabMenu {
  private box: HTMLDivElement;
  private input: HTMLInputElement;
  private list: HTMLDivElement;
  private shown: NodeType[] = [];
  private active = 0;
  private onPick: ((t: NodeType) => void) | null = null;

  constructor(private types: () => NodeType[]) {
    this.box = document.createElement('div');
    this.box.className = 'tab-menu';
    this.box.hidden = true;
    this.input = document.createElement('input');
    this.input.placeholder = 'Search nodes…';
    this.list = document.createElement('div');
    this.list.className = 'tab-list';
    this.box.append(this.input, this.list);
    document.body.appendChild(this.box);
    this.input.addEventListener('input', () => {
      this.active = 0;
      this.fill();
    });
    this.input.addEventListener('keydown', (e) => {
      e.stopPropagation();
      if (e.key === 'Escape') this.close();
      else if (e.key === 'ArrowDown') this.move(1);
      else if (e.key === 'ArrowUp') this.move(-1);
      else if (e.key === 'Enter' && this.shown[this.active]) this.pick(this.shown[this.active]);
      else return;
      e.preventDefault();
    });
    this.input.addEventListener('blur', () => setTimeout(() => this.close(), 150));
  }

  open(x: number, y: number, onPick: (t: NodeType) => void) {
    this.onPick = onPick;
    this.box.hidden = false;
    this.box.style.left = `${Math.min(x, window.innerWidth - 320)}px`;
    this.box.style.top = `${Math.min(y, window.innerHeight - 400)}px`;
    this.input.value = '';
    this.active = 0;
    this.fill();
    this.input.focus();
  }

  close() {
    this.box.hidden = true;
    this.onPick = null;
  }

  private move(d: number) {
    this.active = Math.max(0, Math.min(this.shown.length - 1, this.active + d));
    this.fill();
  }

  private pick(t: NodeType) {
    const f = this.onPick;
    this.close();
    f?.(t);
  }

  private fill() {
    this.shown = filterCatalogue(this.types(), this.input.value);
    this.list.replaceChildren();
    let category = '';
    this.shown.forEach((t, i) => {
      if (!this.input.value && t.category !== category) {
        category = t.category;
        const h = document.createElement('div');
        h.className = 'tab-category';
        h.textContent = category;
        this.list.appendChild(h);
      }
      const row = document.createElement('div');
      row.className = 'tab-item' + (i === this.active ? ' active' : '');
      row.dataset.type = t.name;
      row.innerHTML = `<b></b><span></span>`;
      row.querySelector('b')!.textContent = t.label;
      row.querySelector('span')!.textContent = t.summary;
      row.addEventListener('mousedown', (e) => {
        e.preventDefault();
        this.pick(t);
      });
      this.list.appendChild(row);
      if (i === this.active) row.scrollIntoView({ block: 'nearest' });
    });
  }
}
