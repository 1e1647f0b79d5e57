// The parameter panel, generated from the node type's declarations: sliders over declared ranges, vectors, menus, toggles, text, files, list rows, ramps (rampeditor.ts), code editors for snippets; keys at the current frame; animated values marked; errors by parameter, with an expression's column pointed at.

import { knownVexFunctions, loadVexFunctions, SnippetEditor } from './code';
import { channelAt, isChannel, isExpr, join, nodeAt, parentOf } from './network';
import type { Expr } from './network';
import { freshCookErrors, rampFields, spareDecls, uniqueProblems } from './protocol';
import { rampRows, RampWidget } from './rampeditor';
import type { DocNode, NodeType, ParamDecl, Problem } from './protocol';
import { viewedAttributes } from './sheet';
import type { AppStore } from './store';

export interface ParamActions {
  edit(edit: Record<string, unknown>, merge?: boolean): Promise<boolean>;
  /** A node's parameters as evaluated at the current frame, by name (a failing one as `{error}`). */
  values(path: string): Promise<Record<string, unknown>>;
}

/** A parameter as the panel shows it: its declaration and where its value lives. */
interface Row {
  decl: ParamDecl;
  /** The node whose document holds the value, and the name there. */
  path: string;
  name: string;
  /** For promoted parameters: the inner node it drives. */
  drives?: string;
  /** A spare parameter the node declares (removable). */
  spare?: boolean;
}

/** A typed text as the document stores it: a number when it reads as one, else the text (the loader then says what was expected). */
export function parseNumber(text: string): number | string {
  const t = text.trim();
  if (t !== '' && Number.isFinite(Number(t))) return Number(t);
  return text;
}

/** What a numeric field's text stores: a number when it reads as one, else an expression (as Houdini turns `sin($F)` typed in a field into one). */
export function parseComponent(text: string): number | Expr {
  const v = parseNumber(text);
  return typeof v === 'number' ? v : { expr: text.trim() };
}

/** Whether a string parameter's text expands (variables or backticks), so its value is worth showing. */
export function expands(text: string): boolean {
  return /[$`]/.test(text);
}

/** An evaluated value as a hover shows it. */
export function describeValue(v: unknown): string {
  if (typeof v === 'number') return fmt(v);
  if (Array.isArray(v)) return v.map(describeValue).join(', ');
  if (typeof v === 'object' && v !== null && 'error' in v) return `error: ${String((v as { error: unknown }).error)}`;
  return String(v);
}

const COMPONENTS: Record<string, number> = { float: 1, int: 1, toggle: 1, vec2: 2, vec3: 3, vec4: 4 };

function components(decl: ParamDecl, value: unknown): unknown[] {
  const n = COMPONENTS[decl.type] ?? 0;
  if (n === 1) return [value];
  return Array.isArray(value) ? value : [value];
}

function fmt(v: number): string {
  return Number.isInteger(v) ? String(v) : String(Number(v.toPrecision(6)));
}

export class ParamPanel {
  private shownKey = '';
  private deferred = false;
  /** Snippet editors by place (node path and parameter), kept across redraws for their undo history and size. */
  private editors = new Map<string, SnippetEditor>();
  /** The places whose editors the current redraw showed; the others are closed after it. */
  private editorsShown = new Set<string>();
  /** The selected key of each ramp (by node path and parameter), kept across redraws. */
  private rampSelection = new Map<string, number | null>();

  constructor(
    private host: HTMLElement,
    private store: AppStore,
    private actions: ParamActions,
  ) {
    host.addEventListener('focusout', () => {
      if (this.deferred) {
        this.deferred = false;
        setTimeout(() => this.render(), 0);
      }
    });
  }

  private rows(path: string, node: DocNode): Row[] {
    const s = this.store;
    const promoted: Row[] = Object.entries(node.promote ?? {}).flatMap(([name, target]) => {
      const [inner, param] = target.split('/');
      const innerNode = nodeAt(s.state!.document, join(path, inner));
      const decl = s.catalogue.get(innerNode?.type ?? '')?.params.find((p) => p.name === param);
      return decl ? [{ decl: { ...decl, name, label: `${name} → ${target}` }, path, name, drives: join(path, inner) }] : [];
    });
    const own = (s.catalogue.get(node.type)?.params ?? []).map((decl) => ({ decl, path, name: decl.name }));
    const spare = spareDecls(node).map((decl) => ({ decl, path, name: decl.name, spare: true }));
    return [...own, ...spare, ...promoted];
  }

  render() {
    const s = this.store;
    const path = s.current;
    const node = path && s.state ? nodeAt(s.state.document, path) : null;
    const key = `${path}|${s.state?.version}|${s.state?.view.frame}|${JSON.stringify(freshCookErrors(s.state, s.cooked))}`;
    if (key === this.shownKey) return;
    // A field being typed in (a snippet editor's text too), a slider or a ramp's key being dragged is not swept away under the user.
    const active = document.activeElement;
    if ((active && this.host.contains(active) && active.matches('input, select, textarea, [contenteditable]')) || this.host.querySelector('.ramp[data-dragging]')) {
      this.deferred = true;
      return;
    }
    // A focused ramp keeps the focus (and with it Delete) across the redraw.
    const ramp = active instanceof HTMLElement && this.host.contains(active) && active.classList.contains('ramp') ? active.dataset.place : undefined;
    this.shownKey = key;
    this.host.replaceChildren();
    this.editorsShown.clear();
    try {
      this.fill(path, node);
      if (ramp !== undefined) {
        for (const r of this.host.querySelectorAll<HTMLElement>('.ramp')) if (r.dataset.place === ramp) r.focus({ preventScroll: true });
      }
    } finally {
      for (const [place, editor] of this.editors) {
        if (this.editorsShown.has(place)) continue;
        editor.destroy();
        this.editors.delete(place);
      }
    }
  }

  private fill(path: string | null, node: DocNode | null) {
    const s = this.store;
    if (!path || !node) {
      this.host.innerHTML = '<div class="empty">Select a node to see its parameters.</div>';
      return;
    }
    const type: NodeType | undefined = s.catalogue.get(node.type);
    const head = document.createElement('div');
    head.className = 'param-head';
    head.innerHTML = '<b></b> <span class="type"></span><div class="help"></div>';
    head.querySelector('b')!.textContent = path;
    head.querySelector('.type')!.textContent = type?.label ?? node.type;
    head.querySelector('.help')!.textContent = type?.summary ?? (node.type === 'subnet' ? 'Subnetwork: its promoted parameters.' : '');
    this.host.appendChild(head);
    const problems: Problem[] = uniqueProblems([
      ...(s.state?.problems ?? []).filter((p) => p.path === path),
      ...freshCookErrors(s.state, s.cooked).filter((p) => p.path === path && p.kind !== 'cancelled'),
    ]);
    const general = problems.filter((p) => !p.param);
    for (const p of general) {
      const d = document.createElement('div');
      d.className = p.level === 'note' ? 'note' : 'param-error';
      d.textContent = p.message;
      this.host.appendChild(d);
    }
    const rows = this.rows(path, node);
    if (!rows.length) {
      const d = document.createElement('div');
      d.className = 'empty';
      d.textContent = node.type === 'subnet' ? 'No promoted parameters.' : 'No parameters.';
      this.host.appendChild(d);
    }
    for (const row of rows) this.host.appendChild(this.rowElement(row, node, problems.filter((p) => p.param?.split(/[[.]/)[0] === row.name)));
    if (type?.spare) this.host.appendChild(this.spareAdder(path));
    if (this.host.querySelector('input.expr')) void this.showValues(path, this.shownKey);
  }

  /** Puts each expression's value at this frame on its field (shown on hover), unless the panel has moved on. */
  private async showValues(path: string, shown: string) {
    let values: Record<string, unknown>;
    try {
      values = await this.actions.values(path);
    } catch {
      return;
    }
    if (shown !== this.shownKey) return;
    for (const field of this.host.querySelectorAll<HTMLInputElement>('.param > .widgets > input.expr')) {
      const row = field.closest<HTMLElement>('.param');
      const name = row?.dataset.param ?? '';
      // A parameter in error has no value to show: its message instead.
      const error = row?.querySelector('.param-error')?.textContent;
      if (error) {
        field.title = `${field.value}\n${error}`;
        continue;
      }
      const v = values[name];
      const k = field.dataset.component;
      const one = k !== undefined && Array.isArray(v) ? v[Number(k)] : v;
      const text = describeValue(one);
      field.title = `${field.value}\n= ${text}`;
      field.dataset.value = text;
    }
  }

  private rowElement(row: Row, node: DocNode, problems: Problem[]): HTMLElement {
    const { decl } = row;
    const frame = this.store.state?.view.frame ?? 1;
    const stored = node.params?.[row.name];
    const value = stored ?? decl.default;
    const div = document.createElement('div');
    div.className = 'param';
    div.dataset.param = row.name;
    const label = document.createElement('label');
    label.textContent = decl.label;
    label.title = `${decl.name}: ${decl.help}${decl.affects ? `\n(shows ${decl.affects} when changed)` : ''}`;
    if (decl.affects || row.drives) label.classList.add('tagged');
    div.appendChild(label);
    const driver = this.promotedBy(row);
    if (driver) {
      // The subnet's promoted parameter sets this one: edit it there (Houdini shows a channel reference).
      div.classList.add('driven');
      label.title = `Set by ${driver} (promoted): edit it on the subnet`;
    }
    const comps = components(decl, value);
    const animated = comps.some(isChannel);
    const keyedHere = comps.some((c) => isChannel(c) && c.keys.some((k) => k.frame === frame));
    if (animated) div.classList.add('animated');
    if (keyedHere) div.classList.add('keyed');
    if (decl.animatable && (COMPONENTS[decl.type] ?? 0) > 0) {
      const key = document.createElement('button');
      key.className = 'key';
      key.textContent = keyedHere ? '◆' : '◇';
      key.title = keyedHere ? 'Delete the key at this frame' : 'Set a key at this frame';
      key.addEventListener('click', () => {
        comps.forEach((c, component) => {
          if (keyedHere) {
            if (isChannel(c) && c.keys.some((k) => k.frame === frame)) {
              void this.actions.edit({ kind: 'delete_key', path: row.path, param: row.name, component, frame });
            }
          } else {
            const v = isChannel(c) ? channelAt(c.keys, frame) : Number(c);
            void this.actions.edit({ kind: 'set_key', path: row.path, param: row.name, component, frame, value: Number.isFinite(v) ? v : 0 });
          }
        });
      });
      div.appendChild(key);
    }
    const widgets = document.createElement('div');
    widgets.className = 'widgets';
    div.appendChild(widgets);
    const set = (v: unknown, merge = false) => this.actions.edit({ kind: 'set_param', path: row.path, param: row.name, value: v }, merge);
    const place = `${row.path}\n${row.name}`;
    this.widgets(widgets, decl, value, frame, place, set, (component, v) =>
      this.actions.edit({ kind: 'set_key', path: row.path, param: row.name, component, frame, value: v }),
    );
    if (driver) {
      for (const w of widgets.querySelectorAll<HTMLInputElement | HTMLSelectElement>('input, select')) w.disabled = true;
      const note = document.createElement('div');
      note.className = 'note';
      note.textContent = `set by ${driver} (promoted)`;
      div.appendChild(note);
    }
    if (decl.type === 'ramp' || decl.type === 'colorramp') div.classList.add('wide');
    if (decl.code) {
      // Code takes the panel's width under its label.
      div.classList.add('code');
      this.editors.get(place)?.showProblems(problems);
    }
    if (row.spare) {
      const remove = document.createElement('button');
      remove.className = 'remove';
      remove.textContent = '×';
      remove.title = 'Remove this spare parameter';
      remove.addEventListener('click', () => void this.actions.edit({ kind: 'set_spare', path: row.path, name: row.name, type: null }));
      div.appendChild(remove);
    }
    if (stored !== undefined) {
      const reset = document.createElement('button');
      reset.className = 'reset';
      reset.textContent = '↺';
      reset.title = 'Revert to the default';
      reset.addEventListener('click', () => void set(null));
      div.appendChild(reset);
    }
    for (const p of problems) {
      const e = document.createElement('div');
      e.className = 'param-error';
      e.textContent = p.param && p.param !== row.name ? `${p.param}: ${p.message}` : p.message;
      const col = p.column ?? null;
      const text = widgets.querySelector('input[type=text]') as HTMLInputElement | null;
      if (col !== null && text) {
        const caret = document.createElement('pre');
        caret.className = 'caret';
        caret.textContent = `${text.value}\n${' '.repeat(Math.max(0, col - 1))}^`;
        e.appendChild(caret);
      }
      text?.classList.add('bad');
      div.appendChild(e);
    }
    return div;
  }

  /** The subnet parameter (`/rig detail`) that a promotion makes drive this row's parameter, if any. */
  private promotedBy(row: Row): string | null {
    if (row.drives || row.spare) return null;
    const doc = this.store.state?.document;
    const parent = parentOf(row.path);
    if (!doc || parent === '/' || parent === row.path) return null;
    const subnet = nodeAt(doc, parent);
    const inner = `${row.path.slice(row.path.lastIndexOf('/') + 1)}/${row.name}`;
    const name = Object.entries(subnet?.promote ?? {}).find(([, target]) => target === inner)?.[0];
    return name ? `${parent} ${name}` : null;
  }

  /** The input widgets for one declaration (also used for the fields of list rows); `place` names it (node path and parameter). */
  private widgets(
    host: HTMLElement,
    decl: ParamDecl,
    value: unknown,
    frame: number,
    place: string,
    set: (v: unknown, merge?: boolean) => unknown,
    setKey: (component: number, v: number) => unknown,
  ) {
    const n = COMPONENTS[decl.type] ?? 0;
    if (decl.type === 'toggle') {
      const c = document.createElement('input');
      c.type = 'checkbox';
      c.checked = value === true || value === 1;
      c.addEventListener('change', () => void set(c.checked));
      host.appendChild(c);
    } else if (n >= 1) {
      const comps = components(decl, value);
      const texts: HTMLInputElement[] = comps.map((c, k) => {
        const t = document.createElement('input');
        t.type = 'text';
        t.className = 'num' + (isChannel(c) ? ' animated' : '') + (isExpr(c) ? ' expr' : '');
        t.value = isChannel(c) ? fmt(channelAt(c.keys, frame)) : isExpr(c) ? c.expr : typeof c === 'number' ? fmt(c) : String(c);
        t.dataset.component = String(k);
        if (isExpr(c)) t.title = `expression: ${c.expr}`;
        t.addEventListener('change', () => {
          const v = parseComponent(t.value);
          if (isChannel(c) && typeof v === 'number') {
            void setKey(k, v);
            return;
          }
          // An expression typed over keys replaces them (a component is keys or an expression).
          const all = texts.map((x, i) => (x === t ? v : isExpr(comps[i]) && x.value.trim() === (comps[i] as Expr).expr ? comps[i] : parseComponent(x.value)));
          void set(n === 1 ? all[0] : all.map((x, i) => (i !== k && isChannel(comps[i]) ? comps[i] : x)));
        });
        t.addEventListener('keydown', (e) => e.key === 'Enter' && t.blur());
        host.appendChild(t);
        return t;
      });
      if (n === 1 && !isChannel(comps[0]) && !isExpr(comps[0])) {
        const cur = Number(comps[0]);
        const dflt = Number(decl.default) || 0;
        const lo = decl.min ?? Math.min(0, cur);
        const hi = decl.max ?? Math.max(1, Math.abs(dflt) * 2, Number.isFinite(cur) ? cur * 1.5 : 1);
        const slider = document.createElement('input');
        slider.type = 'range';
        slider.min = String(lo);
        slider.max = String(hi);
        slider.step = decl.type === 'int' ? '1' : String((hi - lo) / 1000);
        slider.value = String(Number.isFinite(cur) ? cur : lo);
        let dragging = false;
        slider.addEventListener('pointerdown', () => (dragging = false));
        slider.addEventListener('input', () => {
          const v = decl.type === 'int' ? Math.round(Number(slider.value)) : Number(Number(slider.value).toPrecision(6));
          texts[0].value = fmt(v);
          void set(v, dragging);
          dragging = true;
        });
        slider.addEventListener('change', () => slider.blur());
        host.appendChild(slider);
      }
    } else if (decl.type === 'menu') {
      const sel = document.createElement('select');
      for (const item of decl.items ?? []) {
        const o = document.createElement('option');
        o.value = o.textContent = item;
        sel.appendChild(o);
      }
      sel.value = String(value);
      sel.addEventListener('change', () => void set(sel.value));
      host.appendChild(sel);
    } else if (decl.type === 'list') {
      this.listWidget(host, decl, Array.isArray(value) ? value : [], frame, place, set);
    } else if (decl.type === 'ramp' || decl.type === 'colorramp') {
      this.rampWidget(host, decl, value, frame, place, set);
    } else if (decl.code) {
      host.appendChild(this.codeEditor(place, String(value ?? ''), set).dom);
    } else {
      const t = document.createElement('input');
      t.type = 'text';
      t.className = (decl.type === 'file' ? 'file' : 'text') + (expands(String(value ?? '')) ? ' expr' : '');
      t.value = String(value ?? '');
      if (decl.type === 'file') t.placeholder = '$HIP/… or a path';
      t.addEventListener('change', () => void set(t.value));
      t.addEventListener('keydown', (e) => e.key === 'Enter' && t.blur());
      host.appendChild(t);
    }
  }

  /** The snippet editor of a place, made once and then given the current text: applied on leaving it or Ctrl/Cmd+Enter. */
  private codeEditor(place: string, text: string, set: (v: unknown) => unknown): SnippetEditor {
    void loadVexFunctions();
    const path = place.slice(0, place.indexOf('\n'));
    const options = {
      text,
      commit: (t: string) => void set(t),
      info: () => ({ functions: knownVexFunctions(), attributes: viewedAttributes(), channels: this.channelNames(path) }),
    };
    let editor = this.editors.get(place);
    if (editor) editor.update(text, options);
    else {
      editor = new SnippetEditor(options);
      this.editors.set(place, editor);
    }
    this.editorsShown.add(place);
    return editor;
  }

  /** What `ch()` reads from a node: its spare parameters, and `../name` for those of the blocks around it. */
  private channelNames(path: string): string[] {
    const doc = this.store.state?.document;
    const names: string[] = [];
    let prefix = '';
    for (let at = path; doc && at !== '/'; at = parentOf(at), prefix += '../') {
      names.push(...Object.keys(nodeAt(doc, at)?.spare ?? {}).map((n) => prefix + n));
    }
    return names;
  }

  /** Declares a spare parameter (read in a snippet with ch()). */
  private spareAdder(path: string): HTMLElement {
    const div = document.createElement('div');
    div.className = 'param spare-adder';
    const name = document.createElement('input');
    name.type = 'text';
    name.placeholder = 'new spare parameter';
    name.className = 'text';
    const ty = document.createElement('select');
    for (const t of ['float', 'int', 'toggle', 'vector2', 'vector', 'vector4', 'string', 'ramp', 'colorramp']) {
      const o = document.createElement('option');
      o.value = o.textContent = t;
      ty.appendChild(o);
    }
    const add = document.createElement('button');
    add.textContent = '+';
    add.title = 'Add a spare parameter';
    const submit = () => {
      if (name.value.trim()) void this.actions.edit({ kind: 'set_spare', path, name: name.value.trim(), type: ty.value });
    };
    add.addEventListener('click', submit);
    name.addEventListener('keydown', (e) => e.key === 'Enter' && submit());
    div.append(name, ty, add);
    return div;
  }

  /** A ramp: its curve or gradient, keys added, dragged and removed there, the selected key's fields below. */
  private rampWidget(host: HTMLElement, decl: ParamDecl, value: unknown, frame: number, place: string, set: (v: unknown, merge?: boolean) => unknown) {
    const colour = decl.type === 'colorramp';
    const fields = decl.fields ?? rampFields(colour);
    const widget = new RampWidget({
      rows: rampRows(value),
      colour,
      frame,
      place,
      selected: this.rampSelection.get(place) ?? null,
      select: (k) => this.rampSelection.set(place, k),
      set: (rows, merge) => set(rows, merge),
      fields: (cells, row, k, setRow) => {
        for (const f of fields) {
          const cell = document.createElement('div');
          cell.className = 'list-cell';
          cell.dataset.field = f.name;
          cell.title = `${f.label}: ${f.help}`;
          const name = document.createElement('small');
          name.textContent = f.name;
          cell.appendChild(name);
          this.widgets(cell, f, row[f.name] ?? f.default, frame, `${place}[${k}].${f.name}`, (v, merge) => setRow({ ...row, [f.name]: v }, merge), () => undefined);
          cells.appendChild(cell);
        }
      },
      dragEnded: () => {
        if (this.deferred) {
          this.deferred = false;
          this.render();
        }
      },
    });
    host.appendChild(widget.dom);
  }

  private listWidget(host: HTMLElement, decl: ParamDecl, rows: unknown[], frame: number, place: string, set: (v: unknown) => unknown) {
    const table = document.createElement('div');
    table.className = 'list';
    const fields = decl.fields ?? [];
    rows.forEach((r, k) => {
      const row = (typeof r === 'object' && r !== null ? r : {}) as Record<string, unknown>;
      const line = document.createElement('div');
      line.className = 'list-row';
      const num = document.createElement('span');
      num.textContent = String(k);
      line.appendChild(num);
      for (const f of fields) {
        const cell = document.createElement('div');
        cell.className = 'list-cell';
        cell.title = `${f.label}: ${f.help}`;
        const name = document.createElement('small');
        name.textContent = f.name;
        cell.appendChild(name);
        this.widgets(cell, f, row[f.name] ?? f.default, frame, `${place}[${k}].${f.name}`, (v) => {
          const next = rows.map((x, i) => (i === k ? { ...row, [f.name]: v } : x));
          return set(next);
        }, () => undefined);
        line.appendChild(cell);
      }
      const del = document.createElement('button');
      del.textContent = '−';
      del.title = 'Remove this row';
      del.addEventListener('click', () => void set(rows.filter((_, i) => i !== k)));
      line.appendChild(del);
      table.appendChild(line);
    });
    const add = document.createElement('button');
    add.textContent = '+ row';
    add.addEventListener('click', () => {
      const fresh: Record<string, unknown> = {};
      for (const f of fields) fresh[f.name] = f.default;
      void set([...rows, fresh]);
    });
    table.appendChild(add);
    host.appendChild(table);
  }
}
