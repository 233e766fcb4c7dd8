// The studio's page in headless Chromium (run by tests/studio/run.sh): what a teacher does, and
// what must hold while they do it. Each check prints "ok: ..." or "FAIL: ..."; the exit status
// is the number of failures.
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

const arg = (name) => process.argv[process.argv.indexOf('--' + name) + 1];
const url = arg('url'), pid = arg('pid'), bin = arg('bin'), work = arg('work');
let failures = 0;
function check(ok, what) {
  console.log((ok ? 'ok: ' : 'FAIL: ') + what);
  if (!ok) failures += 1;
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const rss = () => Number(/VmRSS:\s+(\d+)/.exec(fs.readFileSync(`/proc/${pid}/status`, 'utf8'))[1]);

const browser = await chromium.launch({
  executablePath: arg('chromium'),
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const context = await browser.newContext({ viewport: { width: 1400, height: 1100 }, acceptDownloads: true });
const page = await context.newPage();
const outside = [];
page.on('request', (r) => { if (new URL(r.url()).hostname !== '127.0.0.1') outside.push(r.url()); });
page.on('pageerror', (e) => check(false, 'no script error in the page: ' + e.message));

const status = () => page.evaluate(() => window.studio.status);
async function waitFor(what, predicate, seconds = 60) {
  const end = Date.now() + seconds * 1000;
  while (Date.now() < end) {
    const s = await status();
    if (s && predicate(s)) return s;
    await sleep(100);
  }
  check(false, 'in time: ' + what);
  throw new Error('timed out: ' + what);
}
// Sets a control as a person would, and fires its change event.
async function set(selector, value) {
  await page.evaluate(([sel, v]) => {
    const el = document.querySelector(sel);
    if (el.type === 'checkbox') el.checked = v; else el.value = v;
    el.dispatchEvent(new Event('change'));
  }, [selector, value]);
}
// A digest of the pane's frame as drawn: the sum of its pixels' bytes.
const framePixels = (i) => page.evaluate((k) => {
  const img = document.querySelector(`#pane${k} .image`);
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const ctx = c.getContext('2d');
  ctx.drawImage(img, 0, 0);
  return Array.from(ctx.getImageData(0, 0, c.width, c.height).data);
}, i);

try {
  await page.goto(url);
  await page.waitForFunction(() => window.studio && window.studio.config && window.studio.status, null, { timeout: 30000 });
  const config = await page.evaluate(() => window.studio.config);
  check(config.loopback_only && config.bind === '127.0.0.1', 'the studio binds to 127.0.0.1 by default');
  check(config.scenes.some((s) => s.id === 'hard/cornell_tiny'), 'the scene list has scenes/ and scenes/hard/');

  // ---- the page's default scene has a shipped reference: its chart starts at once ----
  let s = await waitFor('the default panes measure against the shipped reference', (x) =>
    x.panes.every((p) => p.params && p.params.scene === 'scenes/cornell_spheres' && p.reference &&
      p.reference.includes('references/cornell_spheres/reference.exr') && (p.chart || []).length > 0), 30);
  check(s.reference === null, 'no background reference render for a scene with a shipped one');
  await set('#scene', 'scenes/whitted_1979');
  const size = await page.evaluate(() => [document.querySelector('#width').value, document.querySelector('#height').value]);
  check(size[0] === '341' && size[1] === '256', `choosing Whitted's scene takes its shipped reference's size (${size})`);
  s = await waitFor("Whitted's scene measured against its shipped reference", (x) =>
    x.panes.every((p) => p.params && p.params.scene === 'scenes/whitted_1979' && p.reference &&
      p.reference.includes('references/whitted_1979/reference.exr') && (p.chart || []).length > 0), 30);
  check(s.reference === null, "no background reference render for Whitted's scene either");

  // ---- a scene and two lessons: frames change as samples accumulate ----
  await set('#width', '48');
  await set('#height', '36');
  await set('#spp', '1000000');
  await set('#scene', 'scenes/cornell_box');
  await set('#pane0 .lesson', '04_rendering_equation');
  await set('#pane1 .lesson', '03_reflection_equation');
  s = await waitFor('both panes render the Cornell box at 48x36', (x) =>
    x.panes.every((p) => p.params && p.params.scene === 'scenes/cornell_box' && p.params['--width'] === '48' && p.spp >= 2) &&
    x.panes[0].lesson === '04_rendering_equation' && x.panes[1].lesson === '03_reflection_equation');
  await page.waitForFunction((g) => document.querySelector('#pane0 .image').dataset.generation === String(g), s.panes[0].generation);
  const firstSpp = Number(await page.evaluate(() => document.querySelector('#pane0 .image').dataset.spp));
  const first = await framePixels(0);
  await waitFor('more samples', (x) => x.panes[0].spp >= 4 * Math.max(1, firstSpp));
  await page.waitForFunction((n) => Number(document.querySelector('#pane0 .image').dataset.spp) >= n, 4 * Math.max(1, firstSpp));
  const later = await framePixels(0);
  const changed = first.reduce((n, v, k) => n + (v !== later[k] ? 1 : 0), 0);
  check(changed > 0.05 * first.length, `the frame's pixels change as samples accumulate (${changed} of ${first.length} bytes changed)`);
  s = await status();
  check(s.panes[0].spp > firstSpp && s.panes[0].passes >= 2, `the status shows growing spp (${firstSpp} -> ${s.panes[0].spp}, ${s.panes[0].passes} passes)`);
  const statusText = await page.textContent('#pane0 .status');
  check(/spp/.test(statusText) && /Mrays\/s/.test(statusText) && /elapsed/.test(statusText), 'the page shows passes, spp, rays/s and elapsed time: ' + statusText);
  const notes = await page.textContent('#pane0 .notes');
  check(/Russian roulette/.test(notes), "the page lists the lesson's notes");

  // ---- a control changed mid-render cancels the render in flight ----
  const old = s.panes[0].generation;
  const framesBefore = (await page.evaluate(() => window.studio.frames[0])).length;
  await set('#pane0 .options input[data-flag="--plain"]', true);
  s = await waitFor('the new render replaces the old', (x) => x.panes[0].generation > old && x.panes[0].spp >= 1);
  await sleep(1500);
  const frames = (await page.evaluate(() => window.studio.frames[0])).slice(framesBefore);
  const firstNew = frames.findIndex((f) => f.generation !== old);
  check(firstNew >= 0 && frames.slice(firstNew).every((f) => f.generation !== old),
    `after the change no frame of the old render arrives (${frames.length} frames since, the first new at ${firstNew})`);
  s = await status();
  check(s.live_renders <= 3, `one render per pane (and the reference at most): ${s.live_renders} running`);
  check(s.panes[0].command.includes('--plain'), 'the new render is the plain estimator: ' + s.panes[0].command);

  // ---- radiometry at a pixel, with units ----
  await page.click('#pane0 .image', { position: { x: 200, y: 150 } });
  await page.waitForFunction(() => window.studio.probe, null, { timeout: 20000 });
  const probeText = await page.textContent('#probe');
  check(['W/(sr m^2)', 'W/m^2', '1/sr'].every((u) => probeText.includes(u)) && /material/.test(probeText),
    'clicking a pixel shows its material, L, E and f with their units');

  // ---- the download equals the CLI's image, and the chart's last point the CLI's MSE ----
  await set('#spp', '24');
  s = await waitFor('pane 1 done at 24 spp', (x) => x.panes[0].state === 'done' && x.panes[0].spp === 24 && x.panes[0].params['--spp'] === '24', 120);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#pane0 .download-exr')]);
  const studioExr = fs.readFileSync(await download.path());
  const cli = s.panes[0].command.split(' ');
  check(path.basename(path.dirname(cli[0])) === 'bin', 'the command names the lesson in bin/: ' + cli[0]);
  cli[0] = path.basename(cli[0]);
  const reference = path.join(work, 'refs/cornell_box/reference.exr');
  execFileSync(path.join(bin, cli[0]), [...cli.slice(1), '--quiet', '--out', path.join(work, 'cli'),
    '--reference', reference, '--report', path.join(work, 'cli.json')]);
  const cliExr = fs.readFileSync(path.join(work, 'cli.exr'));
  check(studioExr.equals(cliExr), `the downloaded EXR equals the CLI's, bit for bit (${studioExr.length} bytes; ${cli.join(' ')})`);
  const report = JSON.parse(fs.readFileSync(path.join(work, 'cli.json'), 'utf8'));
  const chart = s.panes[0].chart;
  check(chart.length > 0 && s.panes[0].reference && s.panes[0].reference.includes('reference.exr'),
    `the chart measures against the cached reference (${s.panes[0].reference}, ${chart.length} points)`);
  const last = chart[chart.length - 1];
  check(last && last[0] === 24 && Math.abs(last[2] - report.mse) <= 1e-6 * report.mse,
    `the chart's last point is the CLI's MSE (${last && last[2]} against ${report.mse})`);
  await page.screenshot({ path: path.join(work, 'studio_screenshot.png'), fullPage: true });

  // ---- bad parameters: 400 and a message, never a crash ----
  const bad = [
    ['scene=../../etc/passwd&lesson=01_ray_casting', /not one of the studio's scenes/],
    ['scene=scenes/cornell_box&lesson=03_reflection_equation&--estimator=guess', /--estimator/],
    ['scene=scenes/cornell_box&lesson=01_ray_casting&--width=100000', /--max-size/],
    ['scene=scenes/cornell_box&lesson=01_ray_casting&--out=/tmp/x', /not allowed/],
    ['scene=scenes/cornell_box&lesson=%3Cscript%3E', /unknown/],
    ['pane=7&scene=scenes/cornell_box&lesson=01_ray_casting', /pane/],
  ];
  for (const [query, message] of bad) {
    const r = await page.request.post(url + 'api/start?' + query, { data: '', headers: { 'X-Studio': '1' } });
    const body = await r.json().catch(() => ({}));
    check(r.status() === 400 && message.test(body.error || ''), `400 for ${query}: ${body.error}`);
  }
  await set('#pane1 .lesson', '04_rendering_equation');
  await page.waitForSelector('#pane1 .options input[data-flag="--max-depth"]');
  await set('#pane1 .options input[data-flag="--max-depth"]', 'deep');
  await page.waitForFunction(() => !document.getElementById('message').hidden, null, { timeout: 10000 });
  check(/--max-depth/.test(await page.textContent('#message')), 'a bad value typed in the page is shown with the CLI\'s message: ' + await page.textContent('#message'));
  const foreign = await page.request.post(url + 'api/start?scene=scenes/cornell_box&lesson=01_ray_casting', { data: '' });
  check(foreign.status() === 400 && /X-Studio/.test((await foreign.json()).error), 'a POST without the page\'s header (another site\'s) is refused');
  const alive = await page.request.get(url + 'api/status');
  check(alive.ok(), 'the studio still answers after bad requests');
  await set('#pane1 .options input[data-flag="--max-depth"]', '');

  // ---- lesson 6 in a pane, with its per-technique view ----
  await set('#pane1 .lesson', '06_photon_mapping');
  await page.waitForSelector('#pane1 .options input[data-flag="--techniques"]');
  await set('#pane1 .options input[data-flag="--techniques"]', true);
  s = await waitFor('lesson 6 renders with its techniques as layers', (x) =>
    x.panes[1].lesson === '06_photon_mapping' && x.panes[1].spp >= 2 && (x.panes[1].layers || []).length === 3);
  const techniques = s.panes[1].layers.map((l) => l.name).join(',');
  check(techniques === 'connection,merging,light_tracing', `lesson 6's techniques are the pane's layers: ${techniques}`);
  const shares = s.panes[1].layers.reduce((a, l) => a + l.share, 0);
  check(Math.abs(shares - 1) < 1e-3, `lesson 6's techniques add up to its image: ${shares}`);
  await page.waitForFunction(() => [...document.querySelectorAll('#pane1 .view option')].some((o) => o.value === 'layer:1'));
  await set('#pane1 .view', 'layer:1');
  await page.waitForFunction(() => window.studio.frames[1].length > 0);
  check(await page.evaluate(() => document.querySelector('#pane1 .view option:checked').textContent) === 'merging',
    'the pane shows the merging image');
  await set('#pane1 .lesson', '04_rendering_equation');

  // ---- 40 reloads: renders do not pile up, memory stays flat ----
  await set('#spp', '1000000');
  await waitFor('long renders running again', (x) => x.panes.every((p) => p.params['--spp'] === '1000000' && p.state === 'rendering'));
  const reload = async () => {
    await page.reload();
    await page.waitForFunction(() => window.studio && window.studio.status, null, { timeout: 20000 });
  };
  // The first reloads grow the server's memory once and then no more (its two malloc arenas
  // reach their working size: 15.8 MB -> 18.0 MB over the first 20, +0.2 MB over the next 100),
  // so memory is measured after 20 reloads of warm-up; a leak would grow with every reload.
  await sleep(1000);
  const generations = (await status()).panes.map((p) => p.generation).join();
  for (let k = 0; k < 20; ++k) await reload();
  await sleep(1000);
  const before = rss();
  for (let k = 0; k < 20; ++k) await reload();
  await sleep(1000);
  s = await status();
  const after = rss();
  check(s.live_renders <= s.panes.length, `after 40 reloads ${s.live_renders} renders run (one per pane)`);
  check(s.panes.map((p) => p.generation).join() === generations, '40 reloads show the running renders, not new ones');
  check(after <= 1.1 * before, `memory flat over 20 reloads after 20 of warm-up: ${before} kB -> ${after} kB`);
  check(outside.length === 0, 'no request left 127.0.0.1' + (outside.length ? ': ' + outside.slice(0, 3).join(', ') : ''));
} catch (e) {
  check(false, 'the test ran to its end: ' + e.message);
} finally {
  await browser.close();
}
console.log(failures ? `${failures} failed` : 'all passed');
process.exit(failures ? 1 : 0);
