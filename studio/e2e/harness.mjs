// Test harness: starts a real `geode serve` on a copy of an example network, drives Debian's Chromium with playwright-core, and the editor and panel gestures the browser tests share.

import { spawn } from 'node:child_process';
import { cpSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
export const repo = resolve(here, '../..');
export const geodeBin = process.env.GEODE_BIN ?? join(repo, 'target/debug/geode');
export const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';

/**
 * Copies `examples/` to a fresh folder (so saves never touch the repository), adds `files`
 * (name to text), and serves `name` from it.
 */
export async function serve(name, extraArgs = [], files = {}) {
  const dir = mkdtempSync(join(tmpdir(), 'geode-studio-'));
  cpSync(join(repo, 'examples'), dir, { recursive: true });
  for (const [file, text] of Object.entries(files)) writeFileSync(join(dir, file), text);
  const network = join(dir, name);
  const proc = spawn(geodeBin, ['serve', network, '--port', '0', ...extraArgs], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  proc.stderr.on('data', (d) => (stderr += d));
  const url = await new Promise((resolveUrl, reject) => {
    let out = '';
    proc.stdout.on('data', (d) => {
      out += d;
      const m = /geode studio: (\S+)/.exec(out);
      if (m) resolveUrl(m[1]);
    });
    proc.on('exit', (code) => reject(new Error(`geode serve exited (${code}): ${stderr}`)));
    setTimeout(() => reject(new Error(`geode serve printed no URL: ${stderr}`)), 60_000);
  });
  return {
    url,
    dir,
    network,
    proc,
    stderr: () => stderr,
    async stop() {
      proc.kill('SIGTERM');
      await new Promise((r) => (proc.exitCode !== null ? r() : proc.on('exit', r)));
      rmSync(dir, { recursive: true, force: true });
    },
  };
}

export async function browser() {
  // playwright gives the browser a fresh, empty profile of its own.
  const b = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  return {
    b,
    async close() {
      await b.close();
    },
  };
}

/** Opens the studio and waits until it drew its first result. */
export async function open(b, url, { width = 1400, height = 900 } = {}) {
  const page = await b.newPage({ viewport: { width, height } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.__geode?.store.catalogue.size > 0 && window.__geode.store.state);
  return { page, errors };
}

/** Waits for a cook newer than `after` (a generation) to be drawn or to fail; returns the cook message. */
export async function nextCook(page, after, timeout = 60_000) {
  await page.waitForFunction(
    (g) => {
      const c = window.__geode.store.cooked;
      if (!c || c.generation <= g) return false;
      return !c.hasGeometry || window.__geode.drawn?.generation === c.generation;
    },
    after,
    { timeout },
  );
  return page.evaluate(() => window.__geode.store.cooked);
}

/** A network document's text from its nodes and output node. */
export const network = (nodes, output) => JSON.stringify({ geode: 'network', version: 1, output, nodes });

/** An example network's text. */
export const example = (name) => readFileSync(join(repo, 'examples', name), 'utf8');

export const generation = (page) => page.evaluate(() => window.__geode.store.cooked?.generation ?? 0);
export const drawn = (page) => page.evaluate(() => window.__geode.drawn);

/** The box of an element the editor may be redrawing: asked again until it is there. */
export async function boxOf(locator) {
  for (let i = 0; i < 50; i++) {
    const b = await locator.boundingBox().catch(() => null);
    if (b) return b;
    await new Promise((r) => setTimeout(r, 50));
  }
  throw new Error(`no box for ${locator}`);
}

/** Clicks a node of the editor by name (framing all first, as a user would press H, when it is off screen). */
export async function clickNode(page, name) {
  const node = page.locator(`g.node[data-node="${name}"] rect.body`);
  let box = await boxOf(node);
  const editor = await boxOf(page.locator('#editor svg'));
  const inside = (b) => b.x >= editor.x && b.y >= editor.y && b.x + b.width <= editor.x + editor.width && b.y + b.height <= editor.y + editor.height;
  if (!inside(box)) {
    await page.mouse.move(editor.x + 5, editor.y + 5);
    await page.locator('#editor svg').focus();
    await page.keyboard.press('h');
    box = await boxOf(node);
  }
  // Right of the labels and left of the template and display flags, at any zoom.
  await page.mouse.click(box.x + box.width * 0.7, box.y + box.height * 0.8);
}

/** Types into a parameter's first (or `index`th) text field and commits it with Enter. */
export async function setParam(page, param, text, index = 0) {
  const field = page.locator(`.param[data-param="${param}"] input[type=text]`).nth(index);
  await field.fill(text);
  await field.press('Enter');
}
