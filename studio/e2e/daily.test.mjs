// Browser tests of the studio for daily work in Debian's Chromium against a real `geode serve`: viewport display options (points, normals, point and primitive numbers), picking into the spreadsheet, Houdini's Space+1..4 views, sticky notes, network boxes and node colours kept in the saved file, the node info panel, and a layout that stays put when nodes are added.

import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';
import { boxOf, browser, clickNode, generation, nextCook, open, serve, network } from './harness.mjs';

let chrome;
before(async () => {
  chrome = await browser();
});
after(async () => {
  await chrome?.close();
});


describe('the viewport', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('grid.json', [], {
      'grid.json': network({ g: { type: 'grid', params: { rows: 6, columns: 6 } }, n: { type: 'normals', inputs: ['g'], display: true } }, 'n'),
    });
    ({ page } = await open(chrome.b, server.url));
    await page.waitForFunction(() => window.__geode.drawn?.triangles > 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  const objects = () => page.evaluate(() => window.__geode.viewport.content.children.length);

  test('draws points, normals and point and primitive numbers on demand', async () => {
    const before = await objects();
    await page.check('#show-points');
    await page.check('#show-normals');
    assert.equal(await objects(), before + 2, 'a points and a normals overlay');
    await page.check('#show-ptnum');
    await page.check('#show-primnum');
    await page.waitForFunction(() => {
      const [pt, prim] = window.__geode.viewport.labelCounts();
      return pt === 49 && prim === 36;
    });
    for (const id of ['#show-points', '#show-normals', '#show-ptnum', '#show-primnum']) await page.uncheck(id);
    assert.equal(await objects(), before);
    await page.waitForFunction(() => window.__geode.viewport.labelCounts().join() === '0,0');
  });

  test('a click on the mesh selects its point in the spreadsheet and marks it', async () => {
    const canvas = await boxOf(page.locator('#viewport canvas'));
    await page.mouse.click(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
    await page.waitForFunction(() => window.__geode.picked !== null);
    const picked = await page.evaluate(() => window.__geode.picked);
    assert.ok(picked.primitive >= 0 && picked.primitive < 36, JSON.stringify(picked));
    await page.waitForFunction((p) => document.querySelector('.sheet-row.selected')?.dataset.row === String(p), picked.point);
    assert.ok(await page.evaluate(() => window.__geode.viewport.marker.visible));
    // With the Primitives tab open a click selects the primitive's row.
    await page.click('.sheet-tabs button[data-cls="primitive"]');
    await page.mouse.click(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
    await page.waitForFunction((p) => document.querySelector('.sheet-row.selected')?.dataset.row === String(p), picked.primitive);
  });

  test('on a software GL (this SwiftShader) it draws without multisampling and says so', async () => {
    assert.equal(await page.evaluate(() => window.__geode.viewport.antialias), false);
    assert.match(await page.locator('#hud').textContent(), /software rendering \(no GPU\): antialiasing off/);
  });

  test('Space+2 shows the top view, Space+1 perspective again', async () => {
    const canvas = await boxOf(page.locator('#viewport canvas'));
    await page.mouse.move(canvas.x + 40, canvas.y + 40);
    await page.keyboard.down(' ');
    await page.keyboard.press('2');
    await page.keyboard.up(' ');
    assert.equal(await page.evaluate(() => window.__geode.viewport.view), 'top');
    assert.ok(await page.evaluate(() => window.__geode.viewport.camera.isOrthographicCamera));
    assert.equal(await page.locator('#view-name').inputValue(), 'top');
    await page.keyboard.down(' ');
    await page.keyboard.press('1');
    await page.keyboard.up(' ');
    assert.equal(await page.evaluate(() => window.__geode.viewport.view), 'persp');
  });
});

describe('recooks of the same topology', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('wave.json', [], {
      'wave.json': network(
        {
          g: { type: 'grid', params: { rows: 40, columns: 40 } },
          t: { type: 'transform', inputs: ['g'], display: true, params: { translate: [0, { keys: [{ frame: 1, value: 0 }, { frame: 10, value: 3 }] }, 0] } },
        },
        't',
      ),
    });
    ({ page } = await open(chrome.b, server.url));
    await page.waitForFunction(() => window.__geode.drawn?.triangles > 0);
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('send only the changed arrays, drawn in place exactly as a whole message would be', async () => {
    const g = await generation(page);
    await page.evaluate(() => window.__geode.request({ op: 'frame', frame: 5 }));
    await nextCook(page, g);
    const drawn = await page.evaluate(() => window.__geode.drawn);
    assert.equal(drawn.delta, true, 'drawn from a delta');
    assert.ok(drawn.triangles > 0);
    const bounds = await page.evaluate(() => window.__geode.store.cooked.stats.bounds);
    assert.ok(Math.abs(bounds[0][1] - 4 / 3) < 1e-4, JSON.stringify(bounds));
    // A page opened now gets the whole message for the same frame: the same drawing.
    const { page: fresh } = await open(chrome.b, server.url);
    await fresh.waitForFunction((gen) => window.__geode.drawn?.generation >= gen, drawn.generation);
    const whole = await fresh.evaluate(() => window.__geode.drawn);
    assert.equal(whole.delta, undefined);
    assert.equal(whole.checksum, drawn.checksum);
    await fresh.close();
  });
});

describe('the network editor', () => {
  let server;
  let page;
  before(async () => {
    server = await serve('chain.json');
    ({ page } = await open(chrome.b, server.url));
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  const doc = () => page.evaluate(() => window.__geode.store.state.document);

  test('sticky notes, network boxes and node colours are made with Houdini keys and saved', async () => {
    const names = Object.keys((await doc()).nodes);
    const editor = await boxOf(page.locator('#editor svg'));
    await page.mouse.move(editor.x + 30, editor.y + 30);
    await page.keyboard.press('Shift+P');
    await page.waitForFunction(() => Object.keys(window.__geode.store.state.document.notes ?? {}).length === 1);
    // Double-click writes into the note.
    const note = await boxOf(page.locator('g.note rect.note-body'));
    await page.mouse.dblclick(note.x + 20, note.y + 20);
    await page.locator('textarea.note-edit').fill('remember the base');
    await page.locator('textarea.note-edit').press('Control+Enter');
    await page.waitForFunction(() => Object.values(window.__geode.store.state.document.notes)[0].text === 'remember the base');
    // A box around two selected nodes.
    await clickNode(page, names[0]);
    const second = await boxOf(page.locator(`g.node[data-node="${names[1]}"] rect.body`));
    await page.keyboard.down('Shift');
    await page.mouse.click(second.x + second.width * 0.7, second.y + second.height * 0.8);
    await page.keyboard.up('Shift');
    await page.mouse.move(editor.x + 30, editor.y + 30);
    await page.keyboard.press('Shift+O');
    await page.waitForFunction(() => Object.values(window.__geode.store.state.document.boxes ?? {})[0]?.nodes.length === 2);
    // C colours the selected nodes.
    await page.keyboard.press('c');
    await page.locator('.palette .swatch').nth(3).click();
    await page.waitForFunction((n) => window.__geode.store.state.document.nodes[n].ui?.color === '#6fae4a', names[0]);
    await page.waitForFunction((n) => document.querySelector(`g.node[data-node="${n}"] rect.body`)?.style.fill === 'rgb(111, 174, 74)', names[0]);
    await page.click('#save');
    await page.waitForFunction(() => /saved/.test(document.querySelector('#status').textContent));
    const saved = JSON.parse(readFileSync(server.network, 'utf8'));
    assert.equal(Object.values(saved.notes)[0].text, 'remember the base');
    assert.deepEqual(Object.values(saved.boxes)[0].nodes.sort(), [names[0], names[1]].sort());
    assert.equal(saved.nodes[names[0]].ui.color, '#6fae4a');
  });

  test('the template flag (T) draws a second node as a ghost beside the viewed one', async () => {
    const d = await doc();
    const other = Object.keys(d.nodes).find((n) => n !== d.output);
    await clickNode(page, other);
    const editor = await boxOf(page.locator('#editor svg'));
    await page.mouse.move(editor.x + 10, editor.y + 10);
    await page.keyboard.press('t');
    await page.waitForFunction((p) => window.__geode.viewport.templateNodes().includes(p), `/${other}`);
    assert.ok(await page.locator(`g.node[data-node="${other}"] rect.template-flag.on`).count());
    await page.keyboard.press('t');
    await page.waitForFunction(() => window.__geode.viewport.templateNodes().length === 0);
  });

  test('info on a write node writes nothing', async () => {
    const out = (await doc()).output;
    await page.evaluate((out) => window.__geode.edit({ kind: 'add_node', parent: '/', type: 'write', name: 'saver', after: `/${out}` }), out);
    await page.evaluate(() => window.__geode.edit({ kind: 'set_param', path: '/saver', param: 'file', value: '$HIP/info_probe.obj' }));
    await page.locator('g.node[data-node="saver"]').waitFor();
    // Frame everything so the new node is on screen.
    const editor = await boxOf(page.locator('#editor svg'));
    await page.mouse.move(editor.x + 10, editor.y + 10);
    await page.keyboard.press('h');
    const body = await boxOf(page.locator('g.node[data-node="saver"] rect.body'));
    await page.mouse.click(body.x + body.width * 0.5, body.y + body.height * 0.5, { button: 'middle' });
    const panel = page.locator('.node-info');
    await panel.waitFor();
    assert.match(await panel.textContent(), /writes files/);
    assert.equal(existsSync(join(server.dir, 'info_probe.obj')), false, 'nothing written');
    await panel.press('Escape');
    await page.evaluate(() => window.__geode.edit({ kind: 'remove_nodes', paths: ['/saver'] }));
  });

  test('a middle-click on a node opens its info: cook, counts, attributes', async () => {
    const out = (await doc()).output;
    const body = await boxOf(page.locator(`g.node[data-node="${out}"] rect.body`));
    await page.mouse.click(body.x + body.width * 0.5, body.y + body.height * 0.5, { button: 'middle' });
    const panel = page.locator('.node-info');
    await panel.waitFor();
    const text = await panel.textContent();
    assert.match(text, /points, [\d,]+ primitives/);
    assert.match(text, /P \(vector3\)/);
    assert.match(text, /cache key [0-9a-f]{32}/);
    await panel.press('Escape');
    assert.equal(await page.locator('.node-info').count(), 0);
  });

  test('adding a node moves none of the nodes laid out automatically', async () => {
    const positions = () => page.$$eval('g.node', (gs) => Object.fromEntries(gs.map((g) => [g.dataset.node, g.getAttribute('transform')])));
    const before = await positions();
    const g = await generation(page);
    await page.evaluate(() => window.__geode.edit({ kind: 'add_node', parent: '/', type: 'sphere', name: 'extra' }));
    await page.locator('g.node[data-node="extra"]').waitFor();
    const now = await positions();
    for (const [n, t] of Object.entries(before)) assert.equal(now[n], t, `${n} moved`);
    await nextCook(page, g).catch(() => undefined);
  });
});

describe("a subnet's promoted parameter", () => {
  let server;
  let page;
  before(async () => {
    server = await serve('rig.json');
    ({ page } = await open(chrome.b, server.url));
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('shows the inner parameter it sets as set there, not editable', async () => {
    await page.evaluate(() => window.__geode.store.at = '/rig');
    await page.evaluate(() => window.__geode.store.notify());
    await clickNode(page, 'post');
    const row = page.locator('.param.driven[data-param="radius"]');
    await row.waitFor();
    assert.match(await row.textContent(), /set by \/rig detail/);
    assert.ok(await row.locator('input[type=text]').first().isDisabled());
  });
});
