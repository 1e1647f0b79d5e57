// Unit tests of the snippet editor's language: the VEX tokenizer's classes, cook errors placed as diagnostics from their line and column, and completion of functions, bindings and ch() names.
import { CompletionContext, type CompletionResult } from '@codemirror/autocomplete';
import { EditorState, Text } from '@codemirror/state';
import { describe, expect, test } from 'vitest';
import { problemDiagnostics, tokenize, vexCompletions, vexLanguage, type CompletionInfo, type VexFunction } from '../src/code';
import { attributeNames } from '../src/sheet';

describe('the VEX tokenizer', () => {
  test('classes of a sample snippet', () => {
    const snippet = [
      '#include <voplib.h>',
      '// lift the points',
      'float amp = ch("amp") * 1.5e2; /* a block',
      'comment */ v@N = normalize(@P);',
      'i[]@near = nearpoints(0, @P, 0.5f);',
      "3@m = ident(); s@name = 'a\\'b';",
      'foreach (int i; vector2 uv; u[]@uvs) { if (i > 0x1F) break; }',
    ].join('\n');
    expect(tokenize(snippet)).toEqual([
      ['#include <voplib.h>', 'meta'],
      ['// lift the points', 'comment'],
      ['float', 'typeName'],
      ['amp', 'variableName'],
      ['=', 'operator'],
      ['ch', 'variableName.function'],
      ['(', 'bracket'],
      ['"amp"', 'string'],
      [')', 'bracket'],
      ['*', 'operator'],
      ['1.5e2', 'number'],
      [';', 'punctuation'],
      ['/* a block', 'comment'],
      ['comment */', 'comment'],
      ['v@N', 'attributeName'],
      ['=', 'operator'],
      ['normalize', 'variableName.function'],
      ['(', 'bracket'],
      ['@P', 'attributeName'],
      [')', 'bracket'],
      [';', 'punctuation'],
      ['i[]@near', 'attributeName'],
      ['=', 'operator'],
      ['nearpoints', 'variableName.function'],
      ['(', 'bracket'],
      ['0', 'number'],
      [',', 'punctuation'],
      ['@P', 'attributeName'],
      [',', 'punctuation'],
      ['0.5f', 'number'],
      [')', 'bracket'],
      [';', 'punctuation'],
      ['3@m', 'attributeName'],
      ['=', 'operator'],
      ['ident', 'variableName.function'],
      ['(', 'bracket'],
      [')', 'bracket'],
      [';', 'punctuation'],
      ['s@name', 'attributeName'],
      ['=', 'operator'],
      ["'a\\'b'", 'string'],
      [';', 'punctuation'],
      ['foreach', 'keyword'],
      ['(', 'bracket'],
      ['int', 'typeName'],
      ['i', 'variableName'],
      [';', 'punctuation'],
      ['vector2', 'typeName'],
      ['uv', 'variableName'],
      [';', 'punctuation'],
      ['u[]@uvs', 'attributeName'],
      [')', 'bracket'],
      ['{', 'bracket'],
      ['if', 'keyword'],
      ['(', 'bracket'],
      ['i', 'variableName'],
      ['>', 'operator'],
      ['0x1F', 'number'],
      [')', 'bracket'],
      ['break', 'keyword'],
      [';', 'punctuation'],
      ['}', 'bracket'],
    ]);
  });

  test('every type the brief names is a type, dict included', () => {
    for (const t of ['float', 'vector', 'vector2', 'vector4', 'int', 'string', 'matrix', 'matrix3', 'dict']) {
      expect(tokenize(`${t} x;`)[0]).toEqual([t, 'typeName']);
    }
  });
});

describe('diagnostics from cook errors', () => {
  const doc = Text.of(['float a = 1;', '@P.y += nope;', 'v@N = set(1, 2);', '', '  f@x = "𝒳" + zz;']);
  const at = (line: number, column?: number) => ({ path: '/w', param: 'snippet', message: 'm', kind: 'kernel', line, column: column ?? null });
  const text = (d: { from: number; to: number }) => doc.sliceString(d.from, d.to);

  test('underline from the column to the end of the token', () => {
    const [d] = problemDiagnostics(doc, [at(2, 9)]);
    expect(d.from).toBe(doc.line(2).from + 8);
    expect(text(d)).toBe('nope');
    expect(d.severity).toBe('error');
    expect(d.message).toBe('m');
  });

  test('a binding with its prefix, a punctuation mark, a whole line without a column', () => {
    expect(text(problemDiagnostics(doc, [at(3, 1)])[0])).toBe('v@N');
    expect(text(problemDiagnostics(doc, [at(3, 10)])[0])).toBe('(');
    expect(text(problemDiagnostics(doc, [at(1)])[0])).toBe('float a = 1;');
  });

  test('columns count characters, as the VEX lexer does, not UTF-16 units', () => {
    // `zz` is the 15th character of the line; the astral character before it is two units.
    const [d] = problemDiagnostics(doc, [at(5, 15)]);
    expect(text(d)).toBe('zz');
    expect(d.from).toBe(doc.line(5).from + 15);
  });

  test('past the end of a line: its last character; an empty line: a point; beyond the text: the last line', () => {
    expect(text(problemDiagnostics(doc, [at(1, 40)])[0])).toBe(';');
    const [empty] = problemDiagnostics(doc, [at(4, 1)]);
    expect([empty.from, empty.to]).toEqual([doc.line(4).from, doc.line(4).from]);
    expect(problemDiagnostics(doc, [at(9, 3)])[0].from).toBe(doc.line(5).from + 2);
  });

  test('problems without a line are not placed (the panel shows them as text)', () => {
    expect(problemDiagnostics(doc, [{ path: '/w', param: 'snippet', message: 'no input', line: null, column: null }])).toEqual([]);
  });
});

const NOISE: VexFunction = {
  name: 'noise',
  ret: 'float',
  args: [{ type: 'vector', name: 'pos' }],
  optional: 0,
  variadic: false,
  display: 'float noise(vector pos)',
  summary: 'Perlin noise in [0, 1] at pos; a vector when one is declared.',
};
const NORMALIZE: VexFunction = { ...NOISE, name: 'normalize', ret: 'vector', display: 'vector normalize(vector v)', summary: 'The vector scaled to length 1.' };
const INFO: CompletionInfo = {
  functions: [NOISE, { ...NOISE, ret: 'vector', display: 'vector noise(vector pos)', summary: 'Three Perlin noises.' }, NORMALIZE],
  attributes: [
    { name: 'P', cls: 'point' },
    { name: 'width', cls: 'point' },
    { name: 'name', cls: 'primitive' },
  ],
  channels: ['amp', '../speed'],
};

/** The completion offered with the cursor at the end of `doc`. */
function complete(doc: string, explicit = false): CompletionResult | null {
  const state = EditorState.create({ doc, extensions: [vexLanguage] });
  const result = vexCompletions(() => INFO)(new CompletionContext(state, doc.length, explicit));
  return result instanceof Promise ? null : result;
}

describe('completion', () => {
  test('typing `noi` offers noise with its signature and its forms', () => {
    const r = complete('float n = noi')!;
    expect(r.from).toBe('float n = '.length);
    const noise = r.options.find((o) => o.label === 'noise')!;
    expect(noise.detail).toBe('(vector pos) → float · 2 forms');
    expect(noise.type).toBe('function');
    expect(noise.info).toContain('float noise(vector pos)\n  Perlin noise in [0, 1] at pos');
    expect(noise.info).toContain('vector noise(vector pos)');
    expect(r.options.find((o) => o.label === 'normalize')!.detail).toBe('(vector v) → vector');
    expect(r.options.filter((o) => o.label === 'noise')).toHaveLength(1);
    expect(r.options.some((o) => o.label === 'vector' && o.type === 'type')).toBe(true);
  });

  test('after @ (with a type prefix too): the input attributes, then the standard bindings', () => {
    for (const doc of ['@P.y += @', 'v@', 'i[]@wi']) {
      const r = complete(doc)!;
      expect(r.from).toBe(doc.lastIndexOf('@') + 1);
      const labels = r.options.map((o) => o.label);
      for (const name of ['P', 'width', 'name', 'N', 'Cd', 'ptnum', 'primnum', 'numpt', 'Frame', 'Time']) expect(labels).toContain(name);
      expect(labels.filter((l) => l === 'P')).toHaveLength(1);
      expect(r.options.find((o) => o.label === 'width')!.detail).toBe('point attribute');
      // The input's attributes first, then the common bindings.
      const boost = (label: string) => r.options.find((o) => o.label === label)!.boost ?? 0;
      expect(boost('width')).toBeGreaterThan(boost('ptnum'));
      expect(boost('ptnum')).toBeGreaterThan(boost('numvtx'));
    }
  });

  test('inside ch("…"): the node\'s parameter names', () => {
    const r = complete('@P.y += chf("a')!;
    expect(r.from).toBe('@P.y += chf("'.length);
    expect(r.options.map((o) => o.label)).toEqual(['amp', '../speed']);
  });

  test('nothing in comments and strings, nothing unasked without a word', () => {
    expect(complete('// noi')).toBeNull();
    expect(complete('s@x = "noi')).toBeNull();
    expect(complete('@P.y = ')).toBeNull();
    expect(complete('@P.y = ', true)!.options.length).toBeGreaterThan(0);
  });
});

describe('attributes from the spreadsheet', () => {
  test('column labels name their attributes once, without built-ins and groups', () => {
    expect(attributeNames(['Type', 'Vertices', 'P[x]', 'P[y]', 'P[z]', 'width', 'xform[0]', 'xform[1]', 'group:top', 'Point'])).toEqual(['P', 'width', 'xform']);
  });
});
