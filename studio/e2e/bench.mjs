// Studio benchmarks in Chromium against a real `geode serve` (run: npm run bench, after building geode):
// a parameter edit to new geometry drawn in the page (median of 20, the chain and the coral at preview
// depth), a 1M-triangle result from cooked to drawn, and cached playback of the chain against its fps.

import { browser, example, nextCook, open, serve } from './harness.mjs';

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const fmt = (xs) => `median ${median(xs).toFixed(1)} ms (min ${Math.min(...xs).toFixed(1)}, max ${Math.max(...xs).toFixed(1)}, n=${xs.length})`;

/** Runs `body(page)` against a studio serving `name` (with extra `files` beside the examples). */
async function withStudio(name, files, body) {
  const server = await serve(name, [], files);
  const chrome = await browser();
  try {
    const { page } = await open(chrome.b, server.url);
    await nextCook(page, 0, 300_000);
    return await body(page);
  } finally {
    await chrome.close();
    await server.stop();
  }
}

/** Sends a request and waits until a result newer than the one shown is drawn; the drawn frame's time. */
const timed = (page, op) =>
  page.evaluate(async (op) => {
    const probe = window.__geode;
    const before = probe.store.state.generation;
    const t0 = performance.now();
    await (op.op ? probe.request(op) : probe.edit(op));
    await new Promise((resolve) => {
      const poll = () => (probe.drawn && probe.drawn.generation > before ? resolve() : requestAnimationFrame(poll));
      poll();
    });
    const c = probe.store.cooked;
    const total = probe.drawn.drawnAt - t0;
    // The cook's own time (request to result, before encoding) taken off: the rest is encoding, transfer, decoding, upload and drawing.
    return { total, cookedToDrawn: total - c.ms, ms: c.ms };
  }, op);

async function editBench(label, name, files, setup, editFor) {
  await withStudio(name, files, async (page) => {
    for (const op of setup) await timed(page, op);
    for (let i = 0; i < 3; i++) await timed(page, editFor(i)); // warm-up
    const t = [];
    for (let i = 0; i < 20; i++) t.push((await timed(page, editFor(i + 3))).total);
    console.log(`${label}: parameter edit to new geometry drawn, ${fmt(t)}`);
  });
}

await editBench('chain', 'chain.json', {}, [], (i) => ({ kind: 'set_param', path: '/frames', param: 'roll_per_point', value: 60 + i }));

// The coral fully grown (frame 61) with the polygoniser at preview depth 6 (the example's 7 is final quality).
const preview = example('coral.json').replace('"depth": 7', '"depth": 6');
await editBench('coral (depth 6, frame 61)', 'coral_preview.json', { 'coral_preview.json': preview }, [{ op: 'frame', frame: 61 }], (i) => ({
  kind: 'set_param',
  path: '/grow',
  param: 'kill',
  value: Number((0.09 + i * 0.0005).toFixed(4)),
}));

// A 1M-triangle result (a 708 x 708 grid: 999,698 triangles) from cooked to drawn: switching the view
// between two cached nodes, so the time is encoding, transfer, decoding, upload and the first frame.
const million = JSON.stringify({
  geode: 'network',
  version: 1,
  output: 'moved',
  nodes: {
    plane: { type: 'grid', params: { size: [10, 10], rows: 708, columns: 708 } },
    moved: { type: 'transform', inputs: ['plane'], params: { translate: [0, 0.5, 0] } },
  },
});
await withStudio('million.json', { 'million.json': million }, async (page) => {
  await timed(page, { op: 'view', node: '/plane' });
  await timed(page, { op: 'view', node: null });
  const t = [];
  for (let i = 0; i < 6; i++) {
    const r = await timed(page, { op: 'view', node: i % 2 ? null : '/plane' });
    t.push(r.cookedToDrawn);
  }
  const tris = await page.evaluate(() => window.__geode.drawn.triangles);
  console.log(`1M triangles (${tris}): cooked to drawn, ${fmt(t)}`);
});

// Cached playback: the chain over 48 frames at 24 fps, a first pass to fill the cache, then the
// frames per second of the next two passes (every frame shown, paced at the network's rate).
await withStudio('chain.json', {}, async (page) => {
  await timed(page, { kind: 'set_timeline', frames: [1, 48], fps: 24 });
  const played = async (frames) => {
    await page.evaluate(() => window.__geode.timeline.playLog.splice(0));
    await page.evaluate(() => window.__geode.timeline.toggle());
    await page.waitForFunction((n) => window.__geode.timeline.playLog.length >= n, frames, { timeout: 300_000 });
    await page.evaluate(() => window.__geode.timeline.toggle());
    return page.evaluate(() => window.__geode.timeline.playLog.slice());
  };
  await played(48);
  const pass = (await played(96)).slice(0, 96);
  const seconds = (pass[pass.length - 1].at - pass[0].at) / 1000;
  const hits = pass.every((e) => e.misses === 0);
  console.log(`chain playback (all cache hits: ${hits}): ${((pass.length - 1) / seconds).toFixed(1)} fps over ${pass.length} frames (network: 24 fps)`);
});
