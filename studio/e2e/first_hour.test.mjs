// Browser tests of the studio's first hour in Debian's Chromium against a real `geode serve`: a long cook's progress and cancel button, the stale viewport, files confined to the network's folder (a link to /dev/zero, a write outside), export with the writer's warnings, wires into a loop's and a solver's inputs, a 5M-triangle result drawn reduced, the network's frame range and rate, the Tab menu at the mouse wiring after the selection, no 404s.

import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, symlinkSync, existsSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';
import { boxOf, browser, clickNode, generation, nextCook, open, repo, serve, setParam, network } from './harness.mjs';

let chrome;
before(async () => {
  chrome = await browser();
});
after(async () => {
  await chrome?.close();
});


describe('a long cook', () => {
  let server;
  let page;
  before(async () => {
    const slow = network(
      {
        ball: { type: 'frep_sphere' },
        mesh: { type: 'polygonise', inputs: ['ball'], params: { min: [-1.2, -1.2, -1.2], max: [1.2, 1.2, 1.2], depth: 5 } },
      },
      'mesh',
    );
    server = await serve('slow.json', [], { 'slow.json': slow });
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('names the cooking node with a progress bar, cancels from its button, and marks the viewport', async () => {
    await clickNode(page, 'mesh');
    await page.waitForSelector('.param[data-param="depth"]');
    await setParam(page, 'depth', '11');
    await page.waitForSelector('#cook-state.cooking:not([hidden])', { timeout: 10_000 });
    assert.equal(await page.locator('#cook-state .what').textContent(), 'cooking /mesh');
    assert.ok(await page.locator('#viewport-wrap.stale').count(), 'the viewport is marked stale while it cooks');
    // The polygoniser reports its fraction as it goes.
    await page.waitForFunction(() => Number(document.querySelector('#cook-state progress')?.getAttribute('value') ?? 0) > 0, null, { timeout: 20_000 });
    await page.locator('#cancel-cook').click();
    await page.waitForSelector('#cook-state.cancelled:not([hidden])');
    assert.match(await page.locator('#cook-state .what').textContent(), /cancelled/);
    assert.ok(await page.locator('#viewport-wrap.stale').count(), 'the older result is marked');
    // A cheap value cooks again and clears the marks.
    const g = await generation(page);
    await setParam(page, 'depth', '4');
    const cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    await page.waitForSelector('#viewport-wrap:not(.stale)');
    assert.ok(await page.locator('#cook-state[hidden]').count());
  });
});

describe('files', () => {
  let server;
  let page;
  const outside = mkdtempSync(join(tmpdir(), 'geode-outside-'));
  before(async () => {
    const files = network(
      {
        ring: { type: 'torus' },
        zero: { type: 'file', params: { file: '$HIP/zero.obj' } },
        out: { type: 'write', inputs: ['ring'], params: { file: '$HIP/ring.obj' } },
      },
      'ring',
    );
    server = await serve('files.json', [], { 'files.json': files });
    symlinkSync('/dev/zero', join(server.dir, 'zero.obj'));
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
    rmSync(outside, { recursive: true, force: true });
  });

  test('a file node on a link to /dev/zero is refused with a message, and the studio stays responsive', async () => {
    await clickNode(page, 'zero');
    const g = await generation(page);
    await page.keyboard.press('w');
    const cooked = await nextCook(page, g, 20_000);
    assert.equal(cooked.ok, false);
    assert.match(cooked.errors[0].message, /zero\.obj \(which leads to \/dev\/zero\): outside the folders this studio may read/);
    await page.waitForSelector('g.node.error[data-node="zero"]');
    assert.match(await page.locator('.param[data-param="file"] .param-error').textContent(), /\/dev\/zero/);
  });

  test('a click in the middle of a file field edits it (the revert button sits beside it, never over it)', async () => {
    await clickNode(page, 'zero');
    const field = page.locator('.param[data-param="file"] input[type=text]');
    const box = await field.boundingBox();
    await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
    assert.equal(await page.evaluate(() => document.activeElement?.closest('.param')?.dataset.param), 'file');
    assert.equal(await page.evaluate(() => window.__geode.store.state.document.nodes.zero.params.file), '$HIP/zero.obj');
    const reset = await page.locator('.param[data-param="file"] button.reset').boundingBox();
    assert.ok(reset.width <= 24 && reset.x >= box.x + box.width, `reset at ${JSON.stringify(reset)}, field ${JSON.stringify(box)}`);
    await page.keyboard.press('Escape');
  });

  test('a write inside the folder writes; one outside is refused and writes nothing', async () => {
    await clickNode(page, 'out');
    let g = await generation(page);
    await page.keyboard.press('w');
    let cooked = await nextCook(page, g);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    assert.ok(existsSync(join(server.dir, 'ring.obj')));
    g = await generation(page);
    const away = join(outside, 'ring.obj');
    await setParam(page, 'file', away);
    cooked = await nextCook(page, g);
    assert.equal(cooked.ok, false);
    assert.match(cooked.errors[0].message, /outside the folders this studio may write/);
    assert.equal(existsSync(away), false);
  });

  test('export offers Houdini formats and reports what a format could not hold', async () => {
    const options = await page.locator('#export option').evaluateAll((os) => os.map((o) => o.value));
    for (const f of ['glb', 'obj', 'stl', 'ply', 'usda', 'bgeo', 'geo']) assert.ok(options.includes(f), `${f} offered`);
    const g = await generation(page);
    await page.keyboard.press('Escape');
    await page.locator('#solo-state').click();
    await nextCook(page, g);
    const download = page.waitForEvent('download');
    await page.locator('#export').selectOption('bgeo');
    const file = await download;
    assert.equal(file.suggestedFilename(), 'ring.bgeo');
    await page.waitForFunction(() => /exported ring\.bgeo/.test(document.querySelector('#status').textContent));
  });
});

describe('loops and solvers', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('primitives.json');
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  for (const type of ['loop', 'solver']) {
    test(`a wire into a ${type}'s second input is accepted`, async () => {
      const names = await page.evaluate(() => Object.keys(window.__geode.store.state.document.nodes));
      await page.locator('#editor svg').hover({ position: { x: 80, y: 80 } });
      await page.keyboard.press('Tab');
      await page.locator('.tab-menu input').fill(type);
      await page.locator(`.tab-item[data-type="${type}"]`).waitFor();
      await page.keyboard.press('Enter');
      const added = await (await page.waitForFunction((old) => Object.keys(window.__geode.store.state.document.nodes).find((n) => !old.includes(n)), names)).jsonValue();
      const ports = page.locator(`g.node[data-node="${added}"] circle.port.in`);
      // Four inputs, from the declaration (once the editor drew the node).
      await page.waitForFunction((n) => document.querySelectorAll(`g.node[data-node="${n}"] circle.port.in`).length === 4, added);
      const out = await boxOf(page.locator('g.node[data-node="ring"] circle.port.out'));
      const second = await boxOf(ports.nth(1));
      await page.mouse.move(out.x + out.width / 2, out.y + out.height / 2);
      await page.mouse.down();
      await page.mouse.move((out.x + second.x) / 2, (out.y + second.y) / 2, { steps: 4 });
      await page.mouse.move(second.x + second.width / 2, second.y + second.height / 2, { steps: 4 });
      await page.mouse.up();
      await page.waitForFunction((n) => window.__geode.store.state.document.nodes[n].inputs?.[1] === 'ring', added);
      assert.doesNotMatch(await page.locator('#status').textContent(), /refused|takes/);
    });
  }
});

describe('a for-each block', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('primitives.json');
    ({ page } = await open(chrome.b, server.url));
    await nextCook(page, 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  /** Drags from `from`'s centre to `to`'s. */
  async function drag(from, to) {
    const a = await boxOf(from);
    const b = await boxOf(to);
    await page.mouse.move(a.x + a.width / 2, a.y + a.height / 2);
    await page.mouse.down();
    await page.mouse.move((a.x + b.x) / 2, (a.y + b.y) / 2, { steps: 4 });
    await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2, { steps: 4 });
    await page.mouse.up();
  }

  test('a new one passes its piece through, and inside, @0 and @meta wire like outputs', async () => {
    const names = await page.evaluate(() => Object.keys(window.__geode.store.state.document.nodes));
    await clickNode(page, 'ring');
    await page.locator('#editor svg').hover({ position: { x: 80, y: 80 } });
    await page.keyboard.press('Tab');
    await page.locator('.tab-menu input').fill('for_each');
    await page.locator('.tab-item[data-type="for_each"]').waitFor();
    await page.keyboard.press('Enter');
    const added = await (await page.waitForFunction((old) => Object.keys(window.__geode.store.state.document.nodes).find((n) => !old.includes(n)), names)).jsonValue();
    // Its network passes @0 through, so it cooks without error from the start.
    const inner = await page.evaluate((n) => window.__geode.store.state.document.nodes[n].network, added);
    assert.equal(inner.output, 'output');
    assert.deepEqual(inner.nodes.output.inputs, ['@0']);
    await page.waitForFunction((n) => !window.__geode.store.state.problems.some((p) => p.path.startsWith('/' + n)), added);
    // Inside: a marker per input and @meta, with the wire from @0 drawn.
    await clickNode(page, added);
    await page.keyboard.press('Enter');
    await page.waitForSelector('g.inner-input[data-marker="@0"]');
    await page.waitForSelector('g.inner-input[data-marker="@meta"]');
    await page.waitForSelector('path.wire.from-\\@0.to-output');
    // A wrangle added inside is wired from the markers by dragging.
    const before = await page.evaluate((n) => Object.keys(window.__geode.store.state.document.nodes[n].network.nodes), added);
    await page.locator('#editor svg').hover({ position: { x: 300, y: 300 } });
    await page.keyboard.press('Tab');
    await page.locator('.tab-menu input').fill('wrangle');
    await page.locator('.tab-item[data-type="wrangle"]').waitFor();
    await page.keyboard.press('Enter');
    const w = await (await page.waitForFunction(([n, old]) => Object.keys(window.__geode.store.state.document.nodes[n].network.nodes).find((k) => !old.includes(k)), [added, before])).jsonValue();
    const ports = page.locator(`g.node[data-node="${w}"] circle.port.in`);
    await drag(page.locator('g.inner-input[data-marker="@0"] circle.port.out'), ports.nth(0));
    await page.waitForFunction(([n, k]) => window.__geode.store.state.document.nodes[n].network.nodes[k].inputs?.[0] === '@0', [added, w]);
    await drag(page.locator('g.inner-input[data-marker="@meta"] circle.port.out'), ports.nth(1));
    await page.waitForFunction(([n, k]) => window.__geode.store.state.document.nodes[n].network.nodes[k].inputs?.[1] === '@meta', [added, w]);
    assert.doesNotMatch(await page.locator('#status').textContent(), /refused/);
  });
});

describe('a result beyond the viewport budget', () => {
  let server;
  let page;
  before(async () => {
    // 1250 x 2000 quads: 5 million triangles.
    const big = network({ ball: { type: 'sphere', params: { rows: 1250, columns: 2000 } } }, 'ball');
    server = await serve('big.json', [], { 'big.json': big });
    ({ page } = await open(chrome.b, server.url));
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('is drawn reduced with a notice, never not at all', async () => {
    const cooked = await nextCook(page, 0, 240_000);
    assert.ok(cooked.ok, JSON.stringify(cooked.errors));
    assert.ok(cooked.hasGeometry);
    assert.equal(cooked.stats.primitives, 2_500_000);
    await page.waitForFunction(() => /reduced for the viewport/.test(document.querySelector('#hud').textContent), null, { timeout: 60_000 });
    const hud = await page.locator('#hud').textContent();
    const [, drawn, of] = /reduced for the viewport: ([\d,]+) of ([\d,]+) triangles drawn/.exec(hud).map((s) => Number(String(s).replaceAll(',', '')));
    assert.ok(of >= 4_990_000, hud);
    assert.ok(drawn <= 3_000_000 && drawn > 1_000_000, hud);
    const d = await page.evaluate(() => window.__geode.drawn);
    assert.equal(d.triangles, drawn);
  });
});

describe('daily work in the editor', () => {
  let server;
  let page;
  let errors;
  before(async () => {
    const doc = JSON.parse(readFileSync(join(repo, 'examples', 'primitives.json'), 'utf8'));
    doc.frames = [1, 90];
    doc.fps = 30;
    server = await serve('timed.json', [], { 'timed.json': JSON.stringify(doc) });
    ({ page, errors } = await open(chrome.b, server.url));
    await nextCook(page, 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('the timeline takes its range and rate from the network, and keeps edits there', async () => {
    assert.equal(await page.locator('#timeline .end').inputValue(), '90');
    assert.equal(await page.locator('#timeline .fps').inputValue(), '30');
    await page.locator('#timeline .end').fill('120');
    await page.locator('#timeline .end').press('Enter');
    await page.waitForFunction(() => window.__geode.store.state.document.frames?.[1] === 120);
    assert.equal(await page.evaluate(() => window.__geode.store.state.document.fps), 30);
  });

  test('the Tab menu opens at the mouse and wires the new node after the selected one', async () => {
    await clickNode(page, 'ball');
    const svg = await page.locator('#editor svg').boundingBox();
    const at = { x: svg.x + svg.width * 0.2, y: svg.y + svg.height * 0.4 };
    await page.mouse.move(at.x, at.y);
    await page.keyboard.press('Tab');
    const menu = await page.locator('.tab-menu').boundingBox();
    assert.ok(Math.abs(menu.x - at.x) < 2 && Math.abs(menu.y - at.y) < 2, `menu at ${JSON.stringify(menu)}, mouse at ${JSON.stringify(at)}`);
    await page.locator('.tab-menu input').fill('transform');
    await page.locator('.tab-item[data-type="transform"]').waitFor();
    await page.keyboard.press('Enter');
    await page.waitForFunction(() => Object.entries(window.__geode.store.state.document.nodes).some(([n, d]) => d.type === 'transform' && d.inputs?.[0] === 'ball' && n !== 'spin'));
    // The new node is selected and its parameters shown, as Houdini does.
    await page.waitForFunction(() => {
      const s = window.__geode.store;
      return s.current && s.state.document.nodes[s.current.slice(1)]?.type === 'transform' && s.current !== '/spin';
    });
    await page.waitForSelector('.param[data-param="translate"]');
    // One undo step takes node and wire back.
    const count = await page.evaluate(() => Object.keys(window.__geode.store.state.document.nodes).length);
    await page.locator('#editor svg').focus();
    await page.keyboard.press('Control+z');
    await page.waitForFunction((n) => Object.keys(window.__geode.store.state.document.nodes).length === n - 1, count);
  });

  test('two tabs keep their own undo: neither undoes an edit of the other', async () => {
    const { page: other } = await open(chrome.b, server.url);
    const step = (p) => p.evaluate(() => window.__geode.store.state.document.nodes.ball.params?.radius);
    await page.evaluate(() => window.__geode.request({ op: 'edit', edit: { kind: 'set_param', path: '/ball', param: 'radius', value: 0.7 } }));
    await other.evaluate(() => window.__geode.request({ op: 'edit', edit: { kind: 'set_param', path: '/ball', param: 'radius', value: 0.8 } }));
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.ball.params.radius === 0.8);
    // The undo button follows the history the server sends after the
    // change itself: wait for it rather than read it at once.
    await page.waitForSelector('#undo:disabled', { timeout: 5000 }).catch(() => {
      assert.fail("this tab's undo waits for the other tab's change");
    });
    const refused = await page.evaluate(() => window.__geode.request({ op: 'undo' }));
    assert.equal(refused.ok, false);
    assert.match(refused.error, /another tab made the latest change/);
    assert.equal(await step(page), 0.8);
    await other.locator('#editor svg').focus();
    await other.keyboard.press('Control+z');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.ball.params.radius === 0.7);
    await page.waitForSelector('#undo:not(:disabled)');
    await page.locator('#undo').click();
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.ball.params.radius === 0.6);
    await other.close();
  });

  test('frames shown one after another compile no shader again', async () => {
    const programs = () => page.evaluate(() => window.__geode.viewport.renderer.info.programs.map((p) => p.id).join(' '));
    let g = await generation(page);
    await page.evaluate(() => window.__geode.request({ op: 'frame', frame: 2 }));
    await nextCook(page, g);
    const before = await programs();
    for (const frame of [3, 4, 5]) {
      g = await generation(page);
      await page.evaluate((f) => window.__geode.request({ op: 'frame', frame: f }), frame);
      await nextCook(page, g);
    }
    assert.equal(await programs(), before, 'materials (and their programs) are reused across frames');
  });

  test('the nodes below a failed node are marked as failed with it', async () => {
    const g = await generation(page);
    await page.evaluate(() => window.__geode.edit({ kind: 'set_param', path: '/ball', param: 'radius', value: 'big' }));
    const cooked = await nextCook(page, g);
    assert.equal(cooked.ok, false);
    await page.waitForSelector('g.node.error[data-node="ball"]');
    for (const below of ['top', 'open_ball', 'all', 'colour', 'out']) {
      await page.waitForSelector(`g.node.input-error[data-node="${below}"]`);
    }
    assert.match(await page.locator('g.node[data-node="all"] text.error-text').textContent(), /an input failed: \/ball/);
    assert.equal(await page.locator('g.node.input-error[data-node="ring"]').count(), 0, 'a branch that does not read it is untouched');
    const again = await generation(page);
    await page.evaluate(() => window.__geode.edit({ kind: 'set_param', path: '/ball', param: 'radius', value: null }));
    assert.ok((await nextCook(page, again)).ok);
    assert.equal(await page.locator('g.node.input-error').count(), 0);
  });

  test('a long status message never widens the page past the window', async () => {
    const long = 'x'.repeat(2000);
    await page.evaluate((name) => window.__geode.edit({ kind: 'set_param', path: `/${name}`, param: 'radius', value: 1 }), long);
    await page.waitForFunction(() => document.querySelector('#status').textContent.length > 1000);
    const widths = await page.evaluate(() => [document.documentElement.scrollWidth, window.innerWidth]);
    assert.ok(widths[0] <= widths[1], `page ${widths[0]} px wide in a ${widths[1]} px window`);
    const timeline = await page.locator('#timeline .fps').boundingBox();
    assert.ok(timeline.x + timeline.width <= widths[1], 'the timeline stays on screen');
  });

  test('the page asks for nothing that is not there (a favicon included)', async () => {
    const missing = [];
    page.on('response', (r) => r.status() === 404 && missing.push(r.url()));
    await page.reload();
    await page.waitForFunction(() => window.__geode?.store.state);
    assert.deepEqual(missing, []);
    assert.ok(await page.locator('link[rel="icon"]').count());
    assert.deepEqual(errors, []);
  });
});
