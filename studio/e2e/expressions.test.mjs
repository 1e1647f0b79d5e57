// Browser tests of expressions and animation curves in Debian's Chromium against a real `geode serve`: `$F` typed in a vector field animates the result and shows its value on hover, a ch() cycle and a bad variable are shown on the parameter with the column, and the curve editor draws the engine's curve, edits keys, interpolation and tangents, and ticks the timeline.

import assert from 'node:assert/strict';
import { after, before, describe, test } from 'node:test';
import { boxOf, browser, clickNode, generation, nextCook, open, serve, setParam, network } from './harness.mjs';

let chrome;
before(async () => {
  chrome = await browser();
});
after(async () => {
  await chrome?.close();
});

const width = (cooked) => cooked.stats.bounds[1][0] - cooked.stats.bounds[0][0];

async function frame(page, f) {
  const g = await generation(page);
  await page.evaluate((f) => window.__geode.request({ op: 'frame', frame: f }), f);
  return nextCook(page, g);
}

describe('expressions in parameters', () => {
  let server;
  let page;
  before(async () => {
    const files = {
      'expr.json': network(
        {
          b: { type: 'box', display: true },
          other: { type: 'box', params: { size: [1.5, 1, 1] } },
        },
        'b',
      ),
    };
    server = await serve('expr.json', [], files);
    ({ page } = await open(chrome.b, server.url));
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('$F typed in a vector field animates the result, its value shown on hover', async () => {
    await clickNode(page, 'b');
    let g = await generation(page);
    await setParam(page, 'size', '$F', 0);
    let c = await nextCook(page, g);
    const field = page.locator('.param[data-param="size"] input[type=text]').first();
    assert.match(await field.getAttribute('class'), /\bexpr\b/);
    assert.equal(await field.inputValue(), '$F');
    c = await frame(page, 3);
    assert.ok(Math.abs(width(c) - 3) < 1e-5, `width ${width(c)} at frame 3`);
    await page.waitForFunction(() => /= 3$/.test(document.querySelector('.param[data-param="size"] input.expr')?.title ?? ''));
    c = await frame(page, 5);
    assert.ok(Math.abs(width(c) - 5) < 1e-5, `width ${width(c)} at frame 5`);
    // ch() reads another node's parameter, relative to this node.
    g = await generation(page);
    await setParam(page, 'size', 'ch("../other/sizex") * 2', 0);
    c = await nextCook(page, g);
    assert.ok(Math.abs(width(c) - 3) < 1e-5, `width ${width(c)} from ch()`);
    // A number typed over the expression makes it a constant again.
    g = await generation(page);
    await setParam(page, 'size', '2', 0);
    c = await nextCook(page, g);
    assert.ok(Math.abs(width(c) - 2) < 1e-5);
    assert.doesNotMatch((await field.getAttribute('class')) ?? '', /\bexpr\b/);
  });

  test('a bad variable is shown on the parameter with a caret at its column', async () => {
    await clickNode(page, 'b');
    await setParam(page, 'size', '1 + $FOO', 1);
    const error = page.locator('.param[data-param="size"] .param-error');
    await error.first().waitFor();
    assert.match(await error.first().textContent(), /unknown variable \$FOO/);
    assert.match(await error.locator('.caret').first().textContent(), /\n {4}\^$/);
    await setParam(page, 'size', '1', 1);
  });

  test('an expression typed over keys replaces them; an error shows on hover', async () => {
    await page.evaluate(() =>
      window.__geode.edit({ kind: 'set_param', path: '/b', param: 'size', value: [{ keys: [{ frame: 1, value: 1 }, { frame: 10, value: 4 }] }, 1, 1] }),
    );
    await clickNode(page, 'b');
    await page.waitForSelector('.param.animated[data-param="size"]');
    await setParam(page, 'size', '$F * 0.5', 0);
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0]?.expr === '$F * 0.5');
    await setParam(page, 'size', '$NOPE', 0);
    await page.waitForFunction(() => /unknown variable/.test(document.querySelector('.param[data-param="size"] input.expr')?.title ?? ''));
    await setParam(page, 'size', '1', 0);
  });

  test('a cycle of references is reported on each parameter in it', async () => {
    await page.evaluate(() =>
      window.__geode.edit({ kind: 'set_param', path: '/other', param: 'size', value: [{ expr: 'ch("../b/sizex")' }, 1, 1] }),
    );
    await page.evaluate(() =>
      window.__geode.edit({ kind: 'set_param', path: '/b', param: 'size', value: [{ expr: 'ch("../other/sizex")' }, 1, 1] }),
    );
    await clickNode(page, 'b');
    const error = page.locator('.param[data-param="size"] .param-error').first();
    await error.waitFor();
    assert.match(await error.textContent(), /cycle: \/b\/size → \/other\/size → \/b\/size/);
  });
});

describe('the curve editor', () => {
  let server;
  let page;
  const keysOf = () =>
    page.evaluate(() => window.__geode.store.state.document.nodes.b.params.size[0].keys);
  before(async () => {
    const files = {
      'curves.json': network(
        {
          b: {
            type: 'box',
            display: true,
            params: { size: [{ keys: [{ frame: 1, value: 0.5 }, { frame: 11, value: 2 }, { frame: 21, value: 1 }] }, 1, 1] },
          },
        },
        'b',
      ),
    };
    server = await serve('curves.json', [], files);
    ({ page } = await open(chrome.b, server.url));
    await clickNode(page, 'b');
    await page.click('.panel-tabs button[data-panel="curves"]');
    await page.locator('#curves rect.curve-key').nth(2).waitFor();
  });
  after(async () => {
    await page?.close();
    await server?.stop();
  });

  test('draws the keys and ticks them on the timeline', async () => {
    assert.equal(await page.locator('#curves rect.curve-key').count(), 3);
    assert.equal(await page.locator('#curves polyline.curve-line').count(), 1);
    const ticks = await page.$$eval('#timeline .ticks i', (t) => t.map((i) => Number(i.dataset.frame)));
    assert.deepEqual(ticks.sort((a, b) => a - b), [1, 11, 21]);
  });

  test('a key dragged up changes its value and the cook follows; one undo takes the whole drag back', async () => {
    const key = page.locator('#curves rect.curve-key[data-key="1"]');
    const box = await boxOf(key);
    const g = await generation(page);
    await page.mouse.move(box.x + 4, box.y + 4);
    await page.mouse.down();
    for (let i = 1; i <= 5; i++) await page.mouse.move(box.x + 4, box.y + 4 - i * 8);
    await page.mouse.up();
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0].keys[1].value > 2.05);
    // On a loaded machine the drag's last moves land after the first one
    // passes 2.05: wait until the value stops changing before cooking.
    for (let last = NaN; ; ) {
      const now = (await keysOf())[1].value;
      if (now === last) break;
      last = now;
      await page.waitForTimeout(250);
    }
    await frame(page, 11);
    const keys = await keysOf();
    assert.equal(keys[1].frame, 11, 'the frame stays on a whole frame');
    const c = await page.evaluate(() => window.__geode.store.cooked);
    assert.ok(c.generation > g);
    assert.ok(Math.abs(width(c) - keys[1].value) < 1e-4, `cooked ${width(c)}, key ${keys[1].value}`);
    await page.click('#undo');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0].keys[1].value === 2);
  });

  test('interpolation and tangents: Bezier shows handles, a dragged handle sets both slopes', async () => {
    const key = page.locator('#curves rect.curve-key[data-key="1"]');
    const box = await boxOf(key);
    await page.mouse.click(box.x + 4, box.y + 4);
    await page.locator('.curve-bar select.curve-interp').selectOption('bezier');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0].keys[1].interp === 'bezier');
    // The previous key's segment decides the incoming handle.
    const first = page.locator('#curves rect.curve-key[data-key="0"]');
    const fb = await boxOf(first);
    await page.mouse.click(fb.x + 4, fb.y + 4);
    await page.locator('.curve-bar select.curve-interp').selectOption('bezier');
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0].keys[0].interp === 'bezier');
    const kb = await boxOf(page.locator('#curves rect.curve-key[data-key="1"]'));
    await page.mouse.click(kb.x + 4, kb.y + 4);
    const out = page.locator('#curves circle.curve-handle[data-side="out"]');
    assert.equal(await page.locator('#curves circle.curve-handle').count(), 2, 'in and out handles');
    const hb = await boxOf(out);
    await page.mouse.move(hb.x + 4, hb.y + 4);
    await page.mouse.down();
    await page.mouse.move(hb.x + 4, hb.y - 30, { steps: 4 });
    await page.mouse.up();
    await page.waitForFunction(() => window.__geode.store.state.document.nodes.b.params.size[0].keys[1].slope_out > 0);
    const keys = await keysOf();
    assert.equal(keys[1].slope_in, keys[1].slope_out, 'tied tangents');
  });

  test('a click on a label hides its curve; the wheel zooms and F frames again', async () => {
    const label = page.locator('#curves text.curve-label').first();
    await label.click();
    assert.equal(await page.locator('#curves polyline.curve-line').count(), 0);
    await page.locator('#curves text.curve-label').first().click();
    assert.equal(await page.locator('#curves polyline.curve-line').count(), 1);
    const ticks = () => page.$$eval('#curves text.curve-tick', (t) => t.map((x) => x.textContent).join());
    const before = await ticks();
    const svg = await boxOf(page.locator('#curves svg'));
    await page.mouse.move(svg.x + svg.width / 2, svg.y + svg.height / 2);
    await page.mouse.wheel(0, -600);
    assert.notEqual(await ticks(), before, 'zoomed in');
    await page.locator('#curves').press('f');
    assert.equal(await ticks(), before, 'framed as at first');
  });

  test('double-click adds a key on the curve, Delete removes it', async () => {
    const svg = await boxOf(page.locator('#curves svg'));
    const before = (await keysOf()).length;
    // Between keys 2 and 3, on the curve: the key lands where the curve is.
    const k2 = await boxOf(page.locator('#curves rect.curve-key[data-key="1"]'));
    const k3 = await boxOf(page.locator('#curves rect.curve-key[data-key="2"]'));
    await page.mouse.dblclick((k2.x + k3.x) / 2 + 4, (k2.y + k3.y) / 2 + 4);
    await page.waitForFunction((n) => window.__geode.store.state.document.nodes.b.params.size[0].keys.length === n + 1, before);
    assert.ok(svg.width > 100);
    await page.locator('#curves').press('Delete');
    await page.waitForFunction((n) => window.__geode.store.state.document.nodes.b.params.size[0].keys.length === n, before);
  });
});
