// Browser tests of the ramp widget in Debian's Chromium against a real `geode serve`: the curve drawn through the keys, a key dragged (one undo step, the cook following), a click adding a key, its interpolation chosen, Delete removing it, and a colour ramp's gradient. With GEODE_SHOTS set, screenshots of both widgets are written there.

import assert from 'node:assert/strict';
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

describe('the ramp widget', () => {
  let server;
  let page;
  const rows = () => page.evaluate(() => window.__geode.store.state.document.nodes.r.params.ramp);
  const widget = '.param[data-param="ramp"] .ramp';
  const marks = `${widget} circle.ramp-key-mark`;
  /** Waits until the ramp in the document stops changing (a drag's last moves may land late on a loaded machine). */
  const settled = async () => {
    for (let last = ''; ; ) {
      const now = JSON.stringify(await rows());
      if (now === last) return JSON.parse(now);
      last = now;
      await page.waitForTimeout(300);
    }
  };
  before(async () => {
    const files = {
      'ramps.json': network(
        {
          l: { type: 'curve_line', params: { points: 11, end: [1, 0, 0] } },
          r: {
            type: 'attribute_remap',
            inputs: ['l'],
            display: true,
            params: { name: 'P', ramp: [{ pos: 0, value: 0, interp: 'linear' }, { pos: 1, value: 1, interp: 'linear' }] },
          },
          w: { type: 'wrangle', inputs: ['r'], spare: { tint: 'colorramp' }, params: { tint: [{ pos: 0, value: [0.1, 0.2, 0.8], interp: 'linear' }, { pos: 1, value: [1, 0.6, 0.1], interp: 'catmull-rom' }] } },
        },
        'r',
      ),
    };
    server = await serve('ramps.json', [], files);
    ({ page } = await open(chrome.b, server.url));
    await clickNode(page, 'r');
    await page.locator(marks).nth(1).waitFor();
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('draws the curve through its keys', async () => {
    assert.equal(await page.locator(marks).count(), 2);
    const ends = await page.$eval(`${widget} polyline.ramp-curve`, (p) => {
      const pts = p.getAttribute('points').split(' ').map((xy) => xy.split(',').map(Number));
      return [pts[0], pts[pts.length - 1]];
    });
    const keys = await page.$$eval(marks, (cs) => cs.map((c) => [Number(c.getAttribute('cx')), Number(c.getAttribute('cy'))]));
    for (const [k, end] of [[0, 0], [1, 1]]) {
      assert.ok(Math.abs(ends[end][0] - keys[k][0]) < 0.6 && Math.abs(ends[end][1] - keys[k][1]) < 0.6, `${ends} vs ${keys}`);
    }
  });

  test('a key dragged down lowers the cooked result; one undo takes the whole drag back', async () => {
    const box = await boxOf(page.locator(marks).nth(1));
    const g = await generation(page);
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.down();
    for (let i = 1; i <= 6; i++) await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2 + i * 6);
    await page.mouse.up();
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.r.params.ramp[1].value < 0.95);
    const keys = await settled();
    assert.equal(keys[1].pos, 1, 'dragged straight down, the key stays at the end');
    // x = 1 maps through the ramp's end key: the cooked width is its value.
    let c = await nextCook(page, g);
    while (Math.abs(c.stats.bounds[1][0] - keys[1].value) > 1e-4) c = await nextCook(page, c.generation);
    await page.click('#undo');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.r.params.ramp[1].value === 1);
  });

  test('a click adds a key there; its interpolation is chosen below; Delete removes it', async () => {
    const plot = await boxOf(page.locator(`${widget} svg.ramp-plot`));
    // A quarter of the way along, near the top.
    await page.mouse.click(plot.x + 8 + (plot.width - 16) * 0.25, plot.y + 12);
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.r.params.ramp.length === 3);
    const added = (await settled())[2];
    assert.ok(Math.abs(added.pos - 0.25) < 0.02, `pos ${added.pos}`);
    assert.ok(added.value > 0.8, `value ${added.value}`);
    assert.equal(added.interp, 'linear', 'takes the interpolation of the key before it');
    await page.locator(`${widget} .ramp-fields [data-field="interp"] select`).selectOption('monotonecubic');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.r.params.ramp[2].interp === 'monotonecubic');
    await page.locator(marks).nth(2).click();
    await page.keyboard.press('Delete');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.r.params.ramp.length === 2);
    if (process.env.GEODE_SHOTS) {
      await page.locator(marks).nth(0).click();
      await page.locator('.param[data-param="ramp"]').screenshot({ path: join(process.env.GEODE_SHOTS, 'ramp-float.png') });
    }
  });

  test("a colour ramp draws its gradient; a click on the strip adds the colour there", async () => {
    await clickNode(page, 'w');
    const strip = page.locator('.param[data-param="tint"] .ramp rect.ramp-strip');
    await strip.waitFor();
    const stops = await page.$$eval('.param[data-param="tint"] .ramp stop', (s) => s.map((x) => x.getAttribute('stop-color')));
    assert.equal(stops[0], '#1a33cc');
    assert.equal(stops[stops.length - 1], '#ff991a');
    const b = await boxOf(strip);
    await page.mouse.click(b.x + b.width / 2, b.y + b.height / 2);
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.w.params.tint.length === 3);
    const key = await page.evaluate(() => window.__geode.store.state.document.nodes.w.params.tint[2]);
    assert.ok(Math.abs(key.pos - 0.5) < 0.02, `pos ${key.pos}`);
    // Halfway along a linear segment: the mean of its two colours.
    key.value.forEach((c, i) => assert.ok(Math.abs(c - [0.55, 0.4, 0.45][i]) < 0.02, `${key.value}`));
    if (process.env.GEODE_SHOTS) await page.locator('.param[data-param="tint"]').screenshot({ path: join(process.env.GEODE_SHOTS, 'ramp-colour.png') });
  });
});
