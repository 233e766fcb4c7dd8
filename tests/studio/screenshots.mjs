// The figures of docs/studio.md: the page in headless Chromium for two of its demos.
// Usage: node tests/studio/screenshots.mjs --url http://127.0.0.1:PORT/ --chromium /usr/bin/chromium --out docs/images
import { chromium } from 'playwright-core';
import path from 'node:path';

const arg = (name) => process.argv[process.argv.indexOf('--' + name) + 1];
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const browser = await chromium.launch({
  executablePath: arg('chromium'), headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage({ viewport: { width: 1300, height: 900 } });
await page.goto(arg('url'));
await page.waitForFunction(() => window.studio && window.studio.status);
async function set(selector, value) {
  await page.evaluate(([sel, v]) => {
    const el = document.querySelector(sel);
    if (el.type === 'checkbox') el.checked = v; else el.value = v;
    el.dispatchEvent(new Event('change'));
  }, [selector, value]);
}
async function until(predicate, seconds) {
  const end = Date.now() + seconds * 1000;
  while (Date.now() < end) {
    if (await page.evaluate(predicate)) return;
    await sleep(250);
  }
}

// Demo 2: Whitted against path tracing on the Cornell spheres, with the error chart.
await set('#scene', 'scenes/cornell_spheres');
await set('#width', '256'); await set('#height', '256'); await set('#spp', '256');
await set('#pane0 .lesson', '02_whitted');
await set('#pane1 .lesson', '04_rendering_equation');
await sleep(500);
await until(() => window.studio.status.panes.every((p) => p.state === 'done'), 240);
await page.click('#pane1 .image', { position: { x: 150, y: 330 } });
await sleep(1500);
await page.screenshot({ path: path.join(arg('out'), 'studio_whitted_vs_path.png'), fullPage: true });

// Demo 3: the furnace's series, bounce by bounce.
await set('#scene', 'scenes/furnace');
await set('#width', '64'); await set('#height', '64'); await set('#spp', '256');
await set('#pane0 .lesson', '04_rendering_equation');
await set('#pane1 .lesson', '04_rendering_equation');
await sleep(300);
await set('#pane0 .options input[data-flag="--bounces"]', '6');
await set('#pane1 .options input[data-flag="--bounces"]', '6');
await set('#albedo-on', true);
await set('#albedo', '0.8');
await sleep(500);
await until(() => window.studio.status.panes.every((p) => p.state === 'done' && p.layers && p.layers.length), 240);
await set('#pane1 .view', 'sum:1');
await page.evaluate(() => { const e = document.getElementById('exposure'); e.value = '-3'; e.dispatchEvent(new Event('input')); });
await page.click('#pane0 .image', { position: { x: 200, y: 200 } });
await sleep(1500);
await page.screenshot({ path: path.join(arg('out'), 'studio_furnace.png'), fullPage: true });
await browser.close();
