// Browser tests of the studio in Debian's Chromium against a real `geode serve`: live edits, errors kept local, the Tab menu, wiring, undo and redo, the timeline and its cache, solo and auto-solo, latest-wins cooking, saving, the pictures in the docs (the README screenshot, the VEX coral), and the million-instance example.

import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync, copyFileSync } from 'node:fs';
import { after, before, describe, test } from 'node:test';
import { boxOf, browser, clickNode, drawn, generation, geodeBin, nextCook, open, serve, setParam } from './harness.mjs';

let chrome;
before(async () => {
  chrome = await browser();
});
after(async () => {
  await chrome?.close();
});

describe('the coral', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('coral.json');
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0, 120_000);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('a space-colonization parameter edited in the panel changes the drawn geometry', async () => {
    await clickNode(page, 'grow');
    await page.waitForSelector('.param[data-param="kill"]');
    const before = await drawn(page);
    const g = await generation(page);
    await setParam(page, 'step', '0.09');
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    const now = await drawn(page);
    assert.notEqual(now.checksum, before.checksum, 'the viewport shows new geometry');
    const doc = await page.evaluate(() => window.__geode.store.state.document.nodes.grow.params.step);
    assert.equal(doc, 0.09);
  });

  test('a bad value shows the node error, and fixing it clears it', async () => {
    await clickNode(page, 'grow');
    let g = await generation(page);
    await setParam(page, 'kill', '-1');
    await nextCook(page, g);
    await page.waitForSelector('g.node.error[data-node="grow"]');
    const message = await page.locator('.param[data-param="kill"] .param-error').textContent();
    assert.match(message, /below the minimum/);
    g = await generation(page);
    await setParam(page, 'kill', '0.1');
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok);
    assert.equal(await page.locator('g.node.error').count(), 0);
  });

  test('Tab menu creates a node, a drag wires it, undo and redo', async () => {
    const count = () => page.evaluate(() => Object.keys(window.__geode.store.state.document.nodes).length);
    const n0 = await count();
    await page.locator('#editor svg').hover({ position: { x: 60, y: 60 } });
    await page.keyboard.press('Tab');
    await page.locator('.tab-menu input').fill('box');
    await page.locator('.tab-item[data-type="box"]').waitFor();
    await page.keyboard.press('Enter');
    await page.waitForFunction((n) => Object.keys(window.__geode.store.state.document.nodes).length === n + 1, n0);
    const name = await page.evaluate(() => Object.entries(window.__geode.store.state.document.nodes).find(([, n]) => n.type === 'box')[0]);
    // Drag from the box's output to the merge's free input.
    const out = page.locator(`g.node[data-node="${name}"] circle.port.out`);
    const free = page.locator('g.node[data-node="both"] circle.port.in:not(.connected)').first();
    const a = await boxOf(out);
    const b = await boxOf(free);
    await page.mouse.move(a.x + a.width / 2, a.y + a.height / 2);
    await page.mouse.down();
    await page.mouse.move((a.x + b.x) / 2, (a.y + b.y) / 2, { steps: 4 });
    await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2, { steps: 4 });
    await page.mouse.up();
    const wired = (n) => page.evaluate((n) => window.__geode.store.state.document.nodes.both.inputs.includes(n), n);
    await page.waitForFunction((n) => window.__geode.store.state.document.nodes.both.inputs.includes(n), name);
    await page.locator('#editor svg').focus();
    await page.keyboard.press('Control+z');
    await page.waitForFunction((n) => !window.__geode.store.state.document.nodes.both.inputs.includes(n), name);
    assert.equal(await wired(name), false);
    await page.keyboard.press('Control+Shift+z');
    await page.waitForFunction((n) => window.__geode.store.state.document.nodes.both.inputs.includes(n), name);
    // Undo the wire and the node: the network is as it was.
    await page.keyboard.press('Control+z');
    await page.keyboard.press('Control+z');
    await page.waitForFunction((n) => Object.keys(window.__geode.store.state.document.nodes).length === n, n0);
  });

  test('a node added unwired is an error of its own, and the display still draws', async () => {
    const g = await generation(page);
    const names = await page.evaluate(() => Object.keys(window.__geode.store.state.document.nodes));
    // Nothing selected (a node added with one selected is wired after it).
    await page.evaluate(() => {
      const s = window.__geode.store;
      s.selected = new Set();
      s.current = null;
      s.notify();
    });
    await page.locator('#editor svg').hover({ position: { x: 60, y: 120 } });
    await page.keyboard.press('Tab');
    await page.locator('.tab-menu input').fill('transform');
    await page.locator('.tab-item[data-type="transform"]').waitFor();
    await page.keyboard.press('Enter');
    const added = await page.waitForFunction((old) => Object.keys(window.__geode.store.state.document.nodes).find((n) => !old.includes(n)), names);
    const loose = await added.jsonValue();
    await page.waitForSelector(`g.node.error[data-node="${loose}"]`);
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    assert.ok(cooked.hasGeometry);
    assert.ok((await drawn(page)).generation >= cooked.generation, 'the coral is drawn');
    assert.equal(await page.locator('g.node.error').count(), 1, 'only the loose node is marked');
    await page.locator('#editor svg').focus();
    await page.keyboard.press('Control+z');
    await page.waitForFunction((n) => !(n in window.__geode.store.state.document.nodes), loose);
  });

  test('scrubbing the timeline recooks at the new frame', async () => {
    const before = await drawn(page);
    const g = await generation(page);
    await page.locator('#timeline .frame').fill('40');
    await page.locator('#timeline .frame').press('Enter');
    // The previous test's undo recooks at the old frame; that cook may
    // land after `g` was read: wait for the cook at frame 40.
    let cooked = await nextCook(page, g);
    while (cooked.frame !== 40) cooked = await nextCook(page, cooked.generation);
    assert.equal(cooked.frame, 40);
    assert.notEqual((await drawn(page)).checksum, before.checksum);
  });

  test('playing a range twice serves the second pass from the cache', async () => {
    await page.locator('#timeline .start').fill('2');
    await page.locator('#timeline .start').press('Enter');
    await page.locator('#timeline .end').fill('6');
    await page.locator('#timeline .end').press('Enter');
    await page.evaluate(() => window.__geode.timeline.playLog.splice(0));
    await page.locator('#timeline .play').click();
    await page.waitForFunction(() => window.__geode.timeline.playLog.length >= 12, null, { timeout: 120_000 });
    await page.locator('#timeline .play').click();
    const log = await page.evaluate(() => window.__geode.timeline.playLog.slice());
    // The first pass starts wherever the frame was; a full pass is frames 2-6 in order.
    const firstStart = log.findIndex((e) => e.frame === 2);
    const first = log.slice(firstStart, firstStart + 5);
    const second = log.slice(firstStart + 5, firstStart + 10);
    assert.deepEqual(first.map((e) => e.frame), [2, 3, 4, 5, 6]);
    assert.deepEqual(second.map((e) => e.frame), [2, 3, 4, 5, 6]);
    assert.ok(first.some((e) => e.misses > 0), 'the first pass cooks');
    assert.ok(second.every((e) => e.misses === 0 && e.hits > 0), `the second pass is all cache hits: ${JSON.stringify(second)}`);
    await page.locator('.panel-tabs button[data-panel="trace"]').click();
    assert.ok((await page.locator('.trace-row.hit').count()) > 0, 'the trace panel shows the hits');
    await page.locator('.panel-tabs button[data-panel="sheet"]').click();
  });

  test('an edit during a long cook wins over it', async () => {
    // At the last frame the coral is fully grown: meshing it at depth 10 takes seconds.
    let g = await generation(page);
    await page.locator('#timeline .frame').fill('61');
    await page.locator('#timeline .frame').press('Enter');
    await nextCook(page, g, 120_000);
    await clickNode(page, 'smooth');
    const g0 = await generation(page);
    await setParam(page, 'depth', '10');
    // The deep cook starts; change the depth again while it runs.
    await page.waitForFunction((g) => window.__geode.store.state.generation > g, g0);
    const slow = await page.evaluate(() => window.__geode.store.state.generation);
    // Progress streams while the deep cook runs, and the node shows it.
    await page.waitForFunction((g) => window.__geode.progress.some((p) => p.generation === g && p.node === '/smooth' && p.fraction > 0 && p.fraction < 1), slow, { timeout: 20_000 });
    await page.waitForSelector('g.node[data-node="smooth"] rect.progress');
    await setParam(page, 'depth', '5');
    await page.waitForFunction((g) => window.__geode.store.state.generation > g, slow);
    const fast = await page.evaluate(() => window.__geode.store.state.generation);
    const cooked = await nextCook(page, slow);
    assert.equal(cooked.generation, fast, 'the newer edit is the one shown');
    await page.waitForTimeout(1500);
    const late = await page.evaluate((g) => window.__geode.cooks.filter((c) => c.generation === g).length, slow);
    assert.equal(late, 0, 'the cancelled cook never delivered a result');
    assert.equal((await drawn(page)).generation, fast);
  });

  test('copy and paste, a key set and deleted at the current frame', async () => {
    await clickNode(page, 'beside');
    await page.keyboard.press('Control+c');
    await page.keyboard.press('Control+v');
    await page.waitForFunction(() => 'beside1' in window.__geode.store.state.document.nodes);
    const pasted = await page.evaluate(() => window.__geode.store.state.document.nodes.beside1);
    // As in Houdini, a pasted node keeps its parameters, not wires from outside the copy.
    assert.equal(pasted.type, 'transform');
    assert.deepEqual(pasted.params.translate, [3, 0, 0]);
    assert.equal(pasted.inputs, undefined);
    await clickNode(page, 'beside');
    const frame = await page.evaluate(() => window.__geode.store.state.view.frame);
    await page.locator('.param[data-param="translate"] button.key').click();
    await page.waitForFunction(() => Array.isArray(window.__geode.store.state.document.nodes.beside.params.translate?.[0]?.keys));
    const t = await page.evaluate(() => window.__geode.store.state.document.nodes.beside.params.translate);
    assert.deepEqual(t[0], { keys: [{ frame, value: 3 }] });
    await page.waitForSelector('.param.keyed[data-param="translate"]');
    await page.locator('.param[data-param="translate"] button.key').click();
    await page.waitForFunction(() => typeof window.__geode.store.state.document.nodes.beside.params.translate[0] === 'number');
    // Delete removes the selected node.
    await clickNode(page, 'beside1');
    await page.keyboard.press('Delete');
    await page.waitForFunction(() => !('beside1' in window.__geode.store.state.document.nodes));
  });

  test('save writes the canonical form, byte-identical to geode fmt', async () => {
    assert.ok(await page.evaluate(() => window.__geode.store.state.dirty));
    await page.locator('#editor svg').focus();
    await page.keyboard.press('Control+s');
    await page.waitForFunction(() => !window.__geode.store.state.dirty);
    const saved = readFileSync(server.network, 'utf8');
    const copy = server.network.replace(/\.json$/, '.fmt.json');
    copyFileSync(server.network, copy);
    execFileSync(geodeBin, ['fmt', copy]);
    assert.equal(readFileSync(copy, 'utf8'), saved);
    assert.match(saved, /"depth": 5/);
  });
});

describe('the rig (subnet)', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('rig.json');
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0, 60_000);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('dive into the subnet and solo an inner node', async () => {
    await clickNode(page, 'rig');
    await page.keyboard.press('Enter');
    await page.waitForSelector('g.node[data-node="post"]');
    await clickNode(page, 'post');
    const g = await generation(page);
    await page.keyboard.press('w');
    const cooked = await nextCook(page, g);
    assert.equal(cooked.node, '/rig/post');
    assert.equal((await drawn(page)).node, '/rig/post');
    await page.keyboard.press('u');
    await page.waitForSelector('g.node[data-node="welded"]');
    const g2 = await generation(page);
    await page.locator('#solo-state').click();
    assert.equal((await nextCook(page, g2)).node, '/welded');
  });

  test('auto-solo: a promoted parameter shows the node it drives', async () => {
    await clickNode(page, 'rig');
    await page.waitForSelector('.param[data-param="lift"]');
    const g = await generation(page);
    await setParam(page, 'lift', '3', 1);
    const cooked = await nextCook(page, g);
    assert.equal(cooked.node, '/rig/raise');
    const view = await page.evaluate(() => window.__geode.store.state.view);
    assert.deepEqual([view.solo, view.auto], ['/rig/raise', true]);
    assert.match(await page.locator('#hud').textContent(), /auto-solo/);
  });
});

const LOOPED_WRANGLE = JSON.stringify({
  geode: 'network',
  version: 1,
  output: 'l',
  nodes: {
    g: { type: 'grid', params: { rows: 4, columns: 4 } },
    l: {
      type: 'loop',
      inputs: ['g'],
      params: { iterations: 3 },
      network: {
        output: 'w',
        nodes: { w: { type: 'wrangle', inputs: ['@0'], spare: { amp: 'float' }, params: { snippet: '@P.y += ch("amp");', amp: 0.5 } } },
      },
    },
  },
});

describe('a wrangle in a loop', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('looped.json', [], { 'looped.json': LOOPED_WRANGLE });
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0, 60_000);
    await clickNode(page, 'l');
    await page.keyboard.press('Enter');
    await page.waitForSelector('g.node[data-node="w"]');
    await clickNode(page, 'w');
    await page.waitForSelector('.param[data-param="snippet"] .cm-editor');
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  const editor = () => page.locator('.param[data-param="snippet"] .cm-content');

  /** The editor's text, line by line as it shows it. */
  const editorText = async () => (await page.locator('.param[data-param="snippet"] .cm-line').allTextContents()).join('\n');

  /** Replaces the editor's text without applying it (select all, delete, insert: exactly the text). */
  async function replaceText(text) {
    await editor().click();
    await page.keyboard.press('Control+a');
    await page.keyboard.press('Backspace');
    await page.keyboard.insertText(text);
    assert.equal(await editorText(), text);
  }

  /** Replaces the snippet in its code editor and commits it (Ctrl+Enter). */
  async function setSnippet(text) {
    await replaceText(text);
    await editor().press('Control+Enter');
  }

  /** Waits until the completion list offers `labels` (and nothing else when `only`). */
  async function offered(labels, only = false) {
    await page.waitForFunction(
      ([want, only]) => {
        const shown = [...document.querySelectorAll('.cm-tooltip-autocomplete li')].map((li) => li.querySelector('.cm-completionLabel')?.textContent);
        return want.every((l) => shown.includes(l)) && (!only || shown.length === want.length);
      },
      [labels, only],
    );
  }

  /** The snippet as the document holds it. */
  const storedSnippet = () => page.evaluate(() => window.__geode.store.state.document.nodes.l.network.nodes.w.params.snippet);

  test('the snippet is edited as code and the loop recooks', async () => {
    const before = await drawn(page);
    const g = await generation(page);
    await setSnippet('@P.y += ch("amp") * 2;');
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    const doc = await page.evaluate(() => window.__geode.store.state.document.nodes.l.network.nodes.w.params.snippet);
    assert.equal(doc, '@P.y += ch("amp") * 2;');
    assert.notEqual((await drawn(page)).checksum, before.checksum);
  });

  test('a compile error shows at the snippet with its line and column', async () => {
    const g = await generation(page);
    await setSnippet('float a = 1;\n@P.y += nope;');
    await nextCook(page, g);
    const message = await page.locator('.param[data-param="snippet"] .param-error').textContent();
    assert.match(message, /line 2, column 9: undeclared variable 'nope'/);
    // In the editor: underlined on line 2 from column 9 to the end of the word, the line marked, a
    // marker in the gutter, the message on hover.
    const line2 = page.locator('.param[data-param="snippet"] .cm-line').nth(1);
    await line2.locator('.cm-lintRange-error').waitFor();
    assert.equal(await line2.locator('.cm-lintRange-error').textContent(), 'nope');
    assert.equal(await page.locator('.param[data-param="snippet"] .cm-line').nth(0).locator('.cm-lintRange-error').count(), 0);
    assert.match(await line2.getAttribute('class'), /cm-errorLine/);
    assert.equal(await page.locator('.param[data-param="snippet"] .cm-lint-marker-error').count(), 1);
    await line2.locator('.cm-lintRange-error').hover();
    const tip = page.locator('.cm-tooltip-lint');
    await tip.waitFor();
    assert.match(await tip.textContent(), /undeclared variable 'nope'/);
    await page.mouse.move(0, 0);
    const g2 = await generation(page);
    await setSnippet('@P.y += ch("amp");');
    assert.ok((await nextCook(page, g2)).ok);
  });

  test('the snippet editor is as wide as the parameter panel', async () => {
    const panel = await page.locator('#params').evaluate((e) => e.clientWidth);
    const box = await page.locator('.param[data-param="snippet"] .cm-editor').boundingBox();
    assert.ok(box.width >= 0.9 * panel, `editor ${box.width}px in a ${panel}px panel`);
    assert.ok(box.height >= 100, `editor ${box.height}px high`);
  });

  test('typing does not recook; leaving the editor applies the snippet once', async () => {
    const g = await generation(page);
    const before = await storedSnippet();
    await editor().click();
    await page.keyboard.press('Control+End');
    await page.keyboard.type(' @P.x += 0;');
    await page.waitForTimeout(400);
    assert.equal(await generation(page), g, 'no cook while typing');
    assert.equal(await storedSnippet(), before);
    await page.locator('.param-head').click();
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    assert.equal(await storedSnippet(), `${before} @P.x += 0;`);
    const g2 = await generation(page);
    await setSnippet(before);
    await nextCook(page, g2);
  });

  test('typing `noi` offers noise with its signature, `@` the attributes, `ch("` the spare parameters', async () => {
    const before = await storedSnippet();
    await editor().click();
    await page.keyboard.press('Control+End');
    await page.keyboard.type('\nfloat n = noi');
    await offered(['noise']);
    // Keys are ignored for a moment after the list changes (CodeMirror's guard against picking by accident).
    await page.waitForTimeout(200);
    const selected = page.locator('.cm-tooltip-autocomplete li[aria-selected]');
    assert.match(await selected.textContent(), /^noise\(<float\|vector> pos\) → float/);
    // The selected option's forms and summaries aside.
    assert.match(await page.locator('.cm-completionInfo').textContent(), /float noise\(<float\|vector> pos\)\s+Perlin noise/);
    await page.keyboard.press('Enter');
    await page.keyboard.type('(@');
    await offered(['P', 'N', 'Cd', 'ptnum', 'primnum', 'numpt', 'Frame', 'Time']);
    await page.keyboard.press('Escape');
    await page.keyboard.type('P) * ch("');
    await offered(['amp'], true);
    await page.keyboard.press('Escape');
    assert.equal(await editorText(), `${before}\nfloat n = noise(@P) * ch("")`);
    // Back to the stored text: leaving applies nothing.
    const g = await generation(page);
    await replaceText(before);
    await page.locator('.param-head').click();
    await page.waitForTimeout(300);
    assert.equal(await generation(page), g);
  });

  test('Tab in the editor indents and opens no node menu; Backspace deletes text, not the node', async () => {
    const before = await storedSnippet();
    await editor().click();
    await page.keyboard.press('Control+Home');
    await page.keyboard.press('Tab');
    assert.equal(await page.locator('.tab-menu').isVisible(), false);
    assert.equal(await editorText(), `    ${before}`);
    await page.keyboard.press('Backspace');
    await page.keyboard.press('Delete');
    assert.equal(await editorText(), before.slice(1));
    assert.ok(await page.evaluate(() => !!window.__geode.store.state.document.nodes.l.network.nodes.w));
    // Undone step by step in the editor (the studio's own undo is not asked).
    const version = await page.evaluate(() => window.__geode.store.state.version);
    for (let i = 0; i < 4 && (await editorText()) !== before; i++) await page.keyboard.press('Control+z');
    assert.equal(await editorText(), before);
    assert.equal(await page.evaluate(() => window.__geode.store.state.version), version);
    const g = await generation(page);
    await page.locator('.param-head').click();
    await page.waitForTimeout(300);
    assert.equal(await generation(page), g, 'the text is as stored: nothing to apply');
  });

  test('spare parameters are declared, set and removed in the panel', async () => {
    assert.equal(await page.locator('.param[data-param="amp"]').count(), 1);
    await page.locator('.spare-adder input').fill('freq');
    await page.locator('.spare-adder select').selectOption('vector');
    await page.locator('.spare-adder button').click();
    await page.waitForSelector('.param[data-param="freq"]');
    const spare = await page.evaluate(() => window.__geode.store.state.document.nodes.l.network.nodes.w.spare);
    assert.deepEqual(spare, { amp: 'float', freq: 'vector' });
    await page.locator('.param[data-param="freq"] button.remove').click();
    await page.waitForFunction(() => !window.__geode.store.state.document.nodes.l.network.nodes.w.spare.freq);
  });
});

describe('the print check', () => {
  test('a wall thinner than a cell is meshed without a warning; a tolerance the mesh cannot meet warns on the mesh node, and clearing it clears the warning', async () => {
    const server = await serve('frep_print_check.json');
    const { page } = await open(chrome.b, server.url);
    try {
      const first = await nextCook(page, 0, 120_000);
      assert.ok(first.ok, JSON.stringify(first.errors));
      assert.equal(await page.locator('g.node.warning').count(), 0);
      await clickNode(page, 'hollow');
      await page.waitForSelector('.param[data-param="thickness"]');
      let g = await generation(page);
      // A third of a cell: both sides of the wall are meshed, nothing warns.
      await setParam(page, 'thickness', '0.01');
      const thin = await nextCook(page, g, 120_000);
      assert.ok(thin.ok, JSON.stringify(thin.errors));
      const meshed = thin.events.find((e) => e.path === '/mesh');
      assert.deepEqual(meshed.warnings ?? [], []);
      await clickNode(page, 'mesh');
      await page.waitForSelector('.param[data-param="tolerance"]');
      g = await generation(page);
      await setParam(page, 'tolerance', '0.00001');
      const strict = await nextCook(page, g, 120_000);
      assert.ok(strict.ok, 'a warning is not an error');
      const warned = strict.events.find((e) => e.path === '/mesh');
      assert.match(warned.warnings[0], /beyond the tolerance/);
      await page.waitForSelector('g.node.warning[data-node="mesh"]');
      assert.match(await page.locator('g.node.warning[data-node="mesh"] .warning-text').textContent(), /^adaptive output strays/);
      assert.match(await page.locator('#status').textContent(), /^warning: \/mesh: /);
      g = await generation(page);
      await setParam(page, 'tolerance', '0');
      await nextCook(page, g, 120_000);
      await page.waitForFunction(() => document.querySelectorAll('g.node.warning').length === 0);
    } finally {
      await page.close();
      await server.stop();
    }
  });
});

describe('the README screenshot', () => {
  test('the coral fully grown, its network and parameters', async () => {
    const server = await serve('coral.json');
    const { page } = await open(chrome.b, server.url);
    try {
      await nextCook(page, 0, 120_000);
      const g = await generation(page);
      await page.locator('#timeline .frame').fill('61');
      await page.locator('#timeline .frame').press('Enter');
      await nextCook(page, g, 300_000);
      await clickNode(page, 'grow');
      await page.waitForSelector('.param[data-param="kill"]');
      await page.waitForTimeout(300);
      writeFileSync(process.env.GEODE_SCREENSHOT ?? `${server.dir}/studio.png`, await page.screenshot());
    } finally {
      await page.close();
      await server.stop();
    }
  });
});

describe('the VEX coral picture', () => {
  test('seed 001 grown by VEX, one tube per branch (docs/coral_vex.png)', async () => {
    const server = await serve('coral_vex.json');
    const { page } = await open(chrome.b, server.url, { width: 1500, height: 1100 });
    try {
      await nextCook(page, 0, 120_000);
      const g = await generation(page);
      await page.locator('#timeline .frame').fill('90');
      await page.locator('#timeline .frame').press('Enter');
      const cooked = await nextCook(page, g, 300_000);
      assert.ok(cooked.ok, JSON.stringify(cooked.errors));
      assert.ok((await drawn(page)).triangles > 10_000, 'the grown coral is drawn');
      // Frame the whole coral, as H over the viewport does (the frame field
      // typed in keeps the keys until it lets go of the focus), and leave
      // out the viewport's text and buttons.
      await page.locator('#timeline .frame').blur();
      const box = await boxOf(page.locator('#viewport canvas'));
      await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
      const before = await page.evaluate(() => window.__geode.viewport.camera.position.toArray());
      await page.keyboard.press('h');
      await page.waitForFunction((p) => window.__geode.viewport.camera.position.toArray().some((x, i) => x !== p[i]), before);
      // Closer than H frames it (its box's diagonal fills the view).
      for (let i = 0; i < Number(process.env.GEODE_CORAL_VEX_ZOOM ?? 3); i++) await page.mouse.wheel(0, -120);
      await page.addStyleTag({ content: '#hud, #view-tools { visibility: hidden; }' });
      await page.waitForTimeout(300);
      writeFileSync(process.env.GEODE_CORAL_VEX_PNG ?? `${server.dir}/coral_vex.png`, await page.locator('#viewport canvas').screenshot());
    } finally {
      await page.close();
      await server.stop();
    }
  });
});

describe('the million instances', () => {
  test('load, draw and orbit interactively', async () => {
    const server = await serve('instances_million.json');
    const { page } = await open(chrome.b, server.url);
    try {
      await nextCook(page, 0, 300_000);
      const d = await drawn(page);
      assert.equal(d.instances, 1_000_000);
      // Orbit for a while and time the frames drawn.
      const box = await page.locator('#viewport canvas').boundingBox();
      await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
      await page.mouse.down();
      const t0 = Date.now();
      for (let i = 0; i < 10; i++) {
        await page.mouse.move(box.x + box.width / 2 + i * 15, box.y + box.height / 2 + i * 4);
        await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
      }
      await page.mouse.up();
      const perFrame = (Date.now() - t0) / 10;
      console.log(`million instances: drawn in ${d.drawMs.toFixed(0)} ms after receipt, ${perFrame.toFixed(0)} ms per orbit frame`);
      assert.ok(perFrame < 500, `orbiting stays interactive (${perFrame} ms per frame)`);
      // The spreadsheet holds a million points but only draws the rows on screen.
      await page.waitForFunction(() => document.querySelectorAll('.sheet-row[data-row]').length > 0);
      const body = page.locator('.sheet-body');
      const t1 = Date.now();
      await body.evaluate((el) => (el.scrollTop = el.scrollHeight));
      await page.waitForSelector('.sheet-row[data-row="999999"]');
      await page.waitForFunction(() => !document.querySelector('.sheet-row[data-row="999999"]').textContent.includes('…'));
      const scrolled = Date.now() - t1;
      const rows = await page.locator('.sheet-row[data-row]').count();
      console.log(`million instances: spreadsheet to row 999,999 in ${scrolled} ms, ${rows} rows in the page`);
      assert.ok(rows < 100, `only the visible rows exist (${rows})`);
    } finally {
      await page.close();
      await server.stop();
    }
  });
});
