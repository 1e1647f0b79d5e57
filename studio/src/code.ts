// The wrangle snippet editor: CodeMirror 6 with VEX highlighting, line numbers, bracket matching and undo; completion of the library (the server's own table), attributes, bindings and ch() names; cook errors underlined at their line and column. Applied on leaving it or Ctrl/Cmd+Enter.

import { autocompletion, closeBrackets, closeBracketsKeymap, completionKeymap, type Completion, type CompletionContext, type CompletionResult, type CompletionSource } from '@codemirror/autocomplete';
import { defaultKeymap, history, historyKeymap, indentLess, indentMore } from '@codemirror/commands';
import { bracketMatching, ensureSyntaxTree, HighlightStyle, indentUnit, StreamLanguage, StringStream, syntaxHighlighting, type StreamParser } from '@codemirror/language';
import { lintGutter, setDiagnostics, type Diagnostic } from '@codemirror/lint';
import { EditorSelection, EditorState, Prec, StateEffect, StateField, type Extension, type Text } from '@codemirror/state';
import { Decoration, drawSelection, EditorView, highlightActiveLine, highlightActiveLineGutter, keymap, lineNumbers, tooltips, type Command, type DecorationSet } from '@codemirror/view';
import { tags } from '@lezer/highlight';
import type { Problem } from './protocol';

/** One form of a library function, as `GET /api/vex` serves geode-vex's table. */
export interface VexFunction {
  name: string;
  ret: string;
  args: { type: string; name: string }[];
  optional: number;
  variadic: boolean;
  /** `float fit01(float x, float nmin, float nmax)`. */
  display: string;
  summary: string;
}

/** What completion offers besides the language: the geometry's attributes and the node's parameters. */
export interface CompletionInfo {
  functions: VexFunction[];
  /** Attribute names with their class (`point`, `primitive`, ...). */
  attributes: { name: string; cls: string }[];
  /** Names `ch()` reads: the node's spare parameters (`../name` for an enclosing block's). */
  channels: string[];
}

export const VEX_TYPES = ['float', 'vector', 'vector2', 'vector4', 'int', 'string', 'matrix', 'matrix3', 'dict', 'void'];
export const VEX_KEYWORDS = ['if', 'else', 'for', 'foreach', 'while', 'do', 'break', 'continue', 'return', 'function', 'const', 'export'];

/** Bindings every wrangle has, whatever its input: VEX's implicit names and the frame; `common` ones are offered first. */
export const STANDARD_BINDINGS: { name: string; type: string; info: string; common?: boolean }[] = [
  { name: 'P', type: 'vector', info: 'position', common: true },
  { name: 'N', type: 'vector', info: 'normal', common: true },
  { name: 'Cd', type: 'vector', info: 'colour', common: true },
  { name: 'v', type: 'vector', info: 'velocity' },
  { name: 'orient', type: 'vector4', info: 'orientation (quaternion)' },
  { name: 'ptnum', type: 'int', info: 'the point number', common: true },
  { name: 'primnum', type: 'int', info: 'the primitive number', common: true },
  { name: 'vtxnum', type: 'int', info: 'the vertex number' },
  { name: 'elemnum', type: 'int', info: 'the element number' },
  { name: 'numpt', type: 'int', info: 'number of points', common: true },
  { name: 'numprim', type: 'int', info: 'number of primitives' },
  { name: 'numvtx', type: 'int', info: 'number of vertices' },
  { name: 'numelem', type: 'int', info: 'number of elements run over' },
  { name: 'Frame', type: 'float', info: 'the current frame', common: true },
  { name: 'Time', type: 'float', info: 'the current time in seconds (frame 1 at 0, 24 a second)', common: true },
];

const TYPE_SET = new Set(VEX_TYPES);
const KEYWORD_SET = new Set(VEX_KEYWORDS);
/** `@name` with an optional type prefix as the VEX lexer folds it: `v@N`, `i[]@list`, `3@m`. */
const BINDING = /^(?:[fiuvps234d](?:\[\])?)?@[A-Za-z_]\w*/;
const NUMBER = /^(?:0[xX][0-9a-fA-F_]+|(?:\d[\d_]*(?:\.[\d_]*)?|\.\d[\d_]*)(?:[eE][+-]?\d+)?[fF]?)/;
const OPERATOR = /^[-+*/%=<>!&|^~?:]+/;

interface VexState {
  /** Inside a block comment that continues on the next line. */
  comment: boolean;
}

function blockComment(stream: StringStream, state: VexState): string {
  if (stream.skipTo('*/')) {
    stream.pos += 2;
    state.comment = false;
  } else {
    stream.skipToEnd();
    state.comment = true;
  }
  return 'comment';
}

/** The VEX tokenizer; token names are @lezer/highlight tag names. */
export const vexParser: StreamParser<VexState> = {
  name: 'vex',
  startState: () => ({ comment: false }),
  token(stream, state) {
    if (state.comment) return blockComment(stream, state);
    // Preprocessor lines (#include, #pragma), which the compiler skips whole.
    if (stream.sol() && stream.peek() === '#') {
      stream.skipToEnd();
      return 'meta';
    }
    if (stream.eatSpace()) return null;
    if (stream.match('//')) {
      stream.skipToEnd();
      return 'comment';
    }
    if (stream.match('/*')) return blockComment(stream, state);
    if (stream.match(BINDING)) return 'attributeName';
    if (stream.match(NUMBER)) return 'number';
    const quote = stream.peek();
    if (quote === '"' || quote === "'") {
      stream.next();
      let escaped = false;
      while (!stream.eol()) {
        const c = stream.next();
        if (c === quote && !escaped) break;
        escaped = !escaped && c === '\\';
      }
      return 'string';
    }
    if (stream.match(/^[A-Za-z_]\w*/)) {
      const word = stream.current();
      if (TYPE_SET.has(word)) return 'typeName';
      if (KEYWORD_SET.has(word)) return 'keyword';
      return stream.match(/^\s*\(/, false) ? 'variableName.function' : 'variableName';
    }
    if (stream.match(OPERATOR)) return 'operator';
    if (stream.match(/^[()[\]{}]/)) return 'bracket';
    stream.next();
    return 'punctuation';
  },
  languageData: {
    commentTokens: { line: '//', block: { open: '/*', close: '*/' } },
    closeBrackets: { brackets: ['(', '[', '{', '"', "'"] },
  },
};

export const vexLanguage = StreamLanguage.define(vexParser);

/** The tokens of a text with their classes (the parser run line by line, as the editor runs it). */
export function tokenize(text: string): [string, string | null][] {
  const state = vexParser.startState!(4);
  const out: [string, string | null][] = [];
  for (const line of text.split('\n')) {
    const stream = new StringStream(line, 4, 4);
    while (!stream.eol()) {
      const style = vexParser.token(stream, state);
      const token = stream.current();
      if (style !== null || token.trim()) out.push([token, style]);
      stream.start = stream.pos;
    }
  }
  return out;
}

const vexHighlight = HighlightStyle.define([
  { tag: tags.keyword, color: '#c792ea' },
  { tag: tags.typeName, color: '#e6c15a' },
  { tag: tags.attributeName, color: '#5fd0d8' },
  { tag: tags.number, color: '#f0a070' },
  { tag: tags.string, color: '#a5d68a' },
  { tag: tags.comment, color: '#7d8794', fontStyle: 'italic' },
  { tag: tags.meta, color: '#ff8a8a' },
  { tag: tags.function(tags.variableName), color: '#7ab8ff' },
  { tag: tags.operator, color: '#b8c2cf' },
]);

/** UTF-16 offset in `text` of a column counted in characters from 1 (as the VEX lexer counts). */
function offsetOfColumn(text: string, column: number): number {
  let offset = 0;
  for (let c = 1; c < column && offset < text.length; c++) offset += (text.codePointAt(offset) ?? 0) > 0xffff ? 2 : 1;
  return offset;
}

/** The end of the token starting at `at`: a binding, a word or number, a string, else one character. */
function tokenEnd(text: string, at: number): number {
  const m = /^(?:(?:[fiuvps234d](?:\[\])?)?@\w+|[\w.]+|"(?:[^"\\]|\\.)*"?|'(?:[^'\\]|\\.)*'?)/.exec(text.slice(at));
  return at + (m ? m[0].length : 1);
}

/**
 * Lint diagnostics for the problems that carry a position in the snippet (a cook error's line and
 * column, from 1): underlined from the column to the end of its token, or the line's last token when
 * the column is past its end (an expected `;`), the whole line when no column is given.
 */
export function problemDiagnostics(doc: Text, problems: Problem[]): Diagnostic[] {
  return problems.flatMap((p) => {
    if (typeof p.line !== 'number') return [];
    const line = doc.line(Math.min(Math.max(1, p.line), doc.lines));
    const text = line.text;
    let from: number;
    let to: number;
    if (typeof p.column !== 'number') {
      from = 0;
      to = text.length;
    } else {
      from = offsetOfColumn(text, p.column);
      const end = text.trimEnd().length;
      if (from >= end) {
        from = Math.max(0, end - 1);
        to = end;
      } else {
        to = Math.min(tokenEnd(text, from), text.length);
      }
    }
    return [{ from: line.from + from, to: line.from + to, severity: p.level === 'warning' ? 'warning' : 'error', message: p.message, source: p.kind ?? undefined }];
  });
}

const setErrorLines = StateEffect.define<number[]>();

/** The lines of the current problems, highlighted whole. */
const errorLines = StateField.define<DecorationSet>({
  create: () => Decoration.none,
  update(lines, tr) {
    for (const e of tr.effects) {
      if (e.is(setErrorLines)) {
        const starts = [...new Set(e.value)].sort((a, b) => a - b);
        return Decoration.set(starts.map((at) => Decoration.line({ class: 'cm-errorLine' }).range(at)));
      }
    }
    return lines.map(tr.changes);
  },
  provide: (f) => EditorView.decorations.from(f),
});

function functionOptions(functions: VexFunction[]): Completion[] {
  const byName = new Map<string, VexFunction[]>();
  for (const f of functions) byName.set(f.name, [...(byName.get(f.name) ?? []), f]);
  return [...byName.values()].map((forms) => {
    // The first form's arguments and result beside the name; every form with its summary aside.
    const first = forms[0];
    const args = first.display.slice(first.ret.length + 1 + first.name.length);
    const more = forms.length > 1 ? ` · ${forms.length} forms` : '';
    return {
      label: first.name,
      type: 'function',
      detail: `${args} → ${first.ret}${more}`,
      info: forms.map((f) => `${f.display}\n  ${f.summary}`).join('\n'),
    };
  });
}

/** The node type's words: keywords, types. */
const WORD_OPTIONS: Completion[] = [
  ...VEX_KEYWORDS.map((k) => ({ label: k, type: 'keyword' })),
  ...VEX_TYPES.map((t) => ({ label: t, type: 'type' })),
];

/**
 * Completion for VEX: parameter names inside `ch("`, attributes and bindings after `@` (with any
 * type prefix), and library functions with their signatures, keywords and types for words. Nothing
 * inside comments and other strings.
 */
export function vexCompletions(info: () => CompletionInfo): CompletionSource {
  let table: VexFunction[] | null = null;
  let options: Completion[] = [];
  return (context: CompletionContext): CompletionResult | null => {
    const channel = context.matchBefore(/\bch[fivsup]?\(\s*["'][\w./]*/);
    if (channel) {
      const typed = /[\w./]*$/.exec(channel.text)![0];
      return {
        from: context.pos - typed.length,
        options: info().channels.map((name) => ({ label: name, type: 'property', detail: 'parameter' })),
        validFor: /^[\w./]*$/,
      };
    }
    const node = ensureSyntaxTree(context.state, context.pos, 50)?.resolveInner(context.pos, -1);
    if (node && /comment|string|meta/.test(node.type.name)) return null;
    const binding = context.matchBefore(/@\w*/);
    if (binding) {
      const seen = new Set<string>();
      const attributes: Completion[] = [];
      for (const a of info().attributes) {
        if (seen.has(a.name)) continue;
        seen.add(a.name);
        attributes.push({ label: a.name, type: 'variable', detail: `${a.cls} attribute`, boost: 2 });
      }
      const standard = STANDARD_BINDINGS.filter((b) => !seen.has(b.name)).map((b) => ({ label: b.name, type: 'variable', detail: b.type, info: b.info, boost: b.common ? 1 : 0 }));
      return { from: binding.from + 1, options: [...attributes, ...standard], validFor: /^\w*$/ };
    }
    const word = context.matchBefore(/\w+/);
    if (!word && !context.explicit) return null;
    const functions = info().functions;
    if (functions !== table) {
      table = functions;
      options = [...functionOptions(functions), ...WORD_OPTIONS];
    }
    return { from: word?.from ?? context.pos, options, validFor: /^\w*$/ };
  };
}

/** Tab indents: spaces to the next stop at the cursor, the lines of a selection. */
const indentOrInsert: Command = (view) => {
  if (view.state.selection.ranges.some((r) => !r.empty)) return indentMore(view);
  view.dispatch(
    view.state.changeByRange((range) => {
      const line = view.state.doc.lineAt(range.head);
      const spaces = 4 - ((range.head - line.from) % 4);
      return { changes: { from: range.head, insert: ' '.repeat(spaces) }, range: EditorSelection.cursor(range.head + spaces) };
    }),
    { scrollIntoView: true, userEvent: 'input' },
  );
  return true;
};

/** Ctrl/Cmd+Enter: leaves the editor, which applies the text (as the textarea it replaces did). */
const applyByLeaving: Command = (view) => {
  view.contentDOM.blur();
  return true;
};

const theme = EditorView.theme(
  {
    '&': { color: '#d8dee9', backgroundColor: '#15171a', border: '1px solid #333', borderRadius: '3px', fontSize: '12px' },
    '&.cm-focused': { outline: '1px solid var(--accent)' },
    '.cm-scroller': { fontFamily: 'ui-monospace, SFMono-Regular, Menlo, Consolas, monospace', lineHeight: '1.4' },
    '.cm-content': { caretColor: '#e8edf3' },
    '.cm-cursor, .cm-dropCursor': { borderLeftColor: '#e8edf3' },
    '&.cm-focused .cm-selectionBackground, .cm-selectionBackground, ::selection': { backgroundColor: '#34465e' },
    '.cm-gutters': { backgroundColor: '#1b1e22', color: '#6b7380', border: 'none' },
    '.cm-activeLine': { backgroundColor: '#ffffff08' },
    '.cm-activeLineGutter': { backgroundColor: '#ffffff10' },
    '.cm-errorLine': { backgroundColor: '#ff5c5c1c' },
    '.cm-matchingBracket': { backgroundColor: '#3b4350', outline: '1px solid #5aa0ff80' },
    '.cm-tooltip': { backgroundColor: '#262a30', border: '1px solid #3a3f48', color: '#d7dce3' },
    '.cm-tooltip-autocomplete ul li[aria-selected]': { backgroundColor: '#34465e', color: '#fff' },
    '.cm-completionDetail': { color: '#8d95a1', fontStyle: 'normal', marginLeft: '1em' },
    '.cm-completionInfo': { whiteSpace: 'pre-wrap', fontFamily: 'ui-monospace, monospace', maxWidth: '420px' },
    '.cm-diagnostic-error': { borderLeftColor: '#ff5c5c' },
  },
  { dark: true },
);

export interface SnippetEditorOptions {
  text: string;
  /** Applies the text (a parameter edit); called on leaving the editor or Ctrl/Cmd+Enter when it changed. */
  commit(text: string): void;
  info(): CompletionInfo;
}

/** A snippet's editor, kept by the panel across redraws so that its undo history and size survive a cook. */
export class SnippetEditor {
  readonly view: EditorView;
  /** The text the document holds (what was applied last or came from the server). */
  private committed: string;
  private problems: Problem[] = [];

  constructor(private options: SnippetEditorOptions) {
    this.committed = options.text;
    this.view = new EditorView({ state: this.freshState(options.text) });
    const lines = options.text.split('\n').length;
    this.view.dom.style.height = `${Math.min(24, Math.max(6, lines + 1)) * 17 + 8}px`;
    this.view.contentDOM.addEventListener('blur', () => this.commit());
    // The studio's keys (Tab menu, Delete, U, ...) are not for text being typed; Ctrl/Cmd+S saves
    // what was typed too.
    this.view.dom.addEventListener('keydown', (e) => {
      if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 's') this.commit();
      else e.stopPropagation();
    });
  }

  get dom(): HTMLElement {
    return this.view.dom;
  }

  get text(): string {
    return this.view.state.doc.toString();
  }

  private freshState(text: string): EditorState {
    const extensions: Extension[] = [
      lineNumbers(),
      highlightActiveLineGutter(),
      highlightActiveLine(),
      drawSelection(),
      history(),
      bracketMatching(),
      closeBrackets(),
      vexLanguage,
      syntaxHighlighting(vexHighlight),
      indentUnit.of('    '),
      EditorState.tabSize.of(4),
      autocompletion({ override: [vexCompletions(() => this.options.info())], icons: false }),
      lintGutter(),
      errorLines,
      tooltips({ parent: document.body }),
      Prec.highest(
        keymap.of([
          { key: 'Mod-Enter', run: applyByLeaving },
          { key: 'Tab', run: indentOrInsert, shift: indentLess },
        ]),
      ),
      keymap.of([...closeBracketsKeymap, ...completionKeymap, ...historyKeymap, ...defaultKeymap]),
      theme,
    ];
    return EditorState.create({ doc: text, extensions });
  }

  /** Applies the text if it changed since it was last applied. */
  commit() {
    const text = this.text;
    if (text === this.committed) return;
    this.committed = text;
    this.options.commit(text);
  }

  /** The document's value now (after an undo, another page's edit): shown unless it is being typed over. */
  update(text: string, options: SnippetEditorOptions) {
    this.options = options;
    if (text === this.committed) return;
    this.committed = text;
    if (this.view.hasFocus) return;
    this.view.setState(this.freshState(text));
    this.showProblems(this.problems);
  }

  /** Underlines the problems that carry a line and highlights their lines. */
  showProblems(problems: Problem[]) {
    this.problems = problems;
    const diagnostics = problemDiagnostics(this.view.state.doc, problems);
    this.view.dispatch(setDiagnostics(this.view.state, diagnostics));
    this.view.dispatch({ effects: setErrorLines.of(diagnostics.map((d) => this.view.state.doc.lineAt(d.from).from)) });
  }

  destroy() {
    this.view.destroy();
  }
}

let vexTable: Promise<VexFunction[]> | null = null;
let vexFunctions: VexFunction[] = [];

/** The library's signatures, fetched once from the server (`GET /api/vex`). */
export function loadVexFunctions(): Promise<VexFunction[]> {
  vexTable ??= fetch('/api/vex')
    .then((r) => (r.ok ? (r.json() as Promise<{ functions: VexFunction[] }>) : { functions: [] }))
    .then((t) => (vexFunctions = t.functions))
    .catch(() => {
      vexTable = null;
      return [];
    });
  return vexTable;
}

/** The signatures fetched so far (none before the first answer). */
export function knownVexFunctions(): VexFunction[] {
  return vexFunctions;
}
