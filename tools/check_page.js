// Opens a page written by `treeskel ... --html` in headless Chromium (playwright-core from npm, with
// Debian's chromium) the way a user's browser would, and prints what a test needs as JSON: how long
// it took to draw, console errors, every request the page made, what it shows, and screenshots.
// Usage: node tools/check_page.js PAGE.html OUT_DIR [--toggles]
//   OUT_DIR/all.png (everything drawn), and with --toggles cloud.png, skeleton.png, mesh.png (one
//   layer each, switched with the page's own checkboxes) and status.png / height.png (the cloud's two
//   colourings). For each, `drawn` says what share of the view is not background and the box of
//   those pixels (fractions of the width and height, from the top left).
//        node tools/check_page.js --image PICTURE.png   the same figures for a PNG (a preview).
'use strict';
const path = require('path');
const fs = require('fs');
const { chromium } = require('playwright-core');

// What share of an image is not the background (its top-left pixel), and the box of those pixels.
// Runs in the page.
function drawnShare(pixels) {
  const { data, width, height } = pixels;
  const [r0, g0, b0] = [data[0], data[1], data[2]];
  let count = 0, x0 = width, y0 = height, x1 = -1, y1 = -1, checksum = 0;
  for (let i = 0; i < data.length; ++i) checksum = (checksum * 31 + data[i]) >>> 0;
  for (let y = 0; y < height; ++y)
    for (let x = 0; x < width; ++x) {
      const i = 4 * (y * width + x);
      if (Math.abs(data[i] - r0) + Math.abs(data[i + 1] - g0) + Math.abs(data[i + 2] - b0) > 30) {
        ++count;
        x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
      }
    }
  return { checksum, share: count / (width * height), box: count ? [x0 / width, y0 / height, (x1 + 1) / width, (y1 + 1) / height] : null };
}

async function canvasFigures(page) {
  return page.evaluate((fn) => {
    const share = new Function('return ' + fn)();
    const c = document.getElementById('view');
    const t = document.createElement('canvas');
    t.width = c.width;
    t.height = c.height;
    const ctx = t.getContext('2d');
    ctx.drawImage(c, 0, 0);
    return share(ctx.getImageData(0, 0, t.width, t.height));
  }, drawnShare.toString());
}

async function imageFigures(browser, file) {
  const page = await browser.newPage();
  const data = 'data:image/png;base64,' + fs.readFileSync(file).toString('base64');
  const out = await page.evaluate(async ([src, fn]) => {
    const share = new Function('return ' + fn)();
    const img = new Image();
    img.src = src;
    await img.decode();
    const t = document.createElement('canvas');
    t.width = img.naturalWidth;
    t.height = img.naturalHeight;
    const ctx = t.getContext('2d');
    ctx.drawImage(img, 0, 0);
    return { width: t.width, height: t.height, ...share(ctx.getImageData(0, 0, t.width, t.height)) };
  }, [data, drawnShare.toString()]);
  await page.close();
  return out;
}

async function main() {
  const [page_file, out_dir, ...flags] = process.argv.slice(2);
  if (page_file === '--image') {
    const browser = await chromium.launch({ executablePath: process.env.TREESKEL_CHROMIUM || '/usr/bin/chromium', args: ['--no-sandbox'] });
    try {
      console.log(JSON.stringify(await imageFigures(browser, out_dir)));
    } finally {
      await browser.close();
    }
    return;
  }
  if (!page_file || !out_dir) {
    console.error('usage: node check_page.js PAGE.html OUT_DIR [--toggles]');
    process.exit(2);
  }
  fs.mkdirSync(out_dir, { recursive: true });
  const executablePath = process.env.TREESKEL_CHROMIUM || '/usr/bin/chromium';
  const browser = await chromium.launch({
    executablePath,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const result = { errors: [], requests: [], ready: false, drawn: {} };
  try {
    const context = await browser.newContext({ viewport: { width: 1200, height: 800 } });
    const page = await context.newPage();
    const url = 'file://' + path.resolve(page_file);
    page.on('console', (m) => { if (m.type() === 'error') result.errors.push(m.text()); });
    page.on('pageerror', (e) => result.errors.push(String(e)));
    page.on('request', (r) => { if (r.url() !== url) result.requests.push(r.url()); });
    const start = Date.now();
    await page.goto(url);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
    result.seconds_to_draw = (Date.now() - start) / 1000;
    result.ready = true;
    result.counts = await page.evaluate(() => window.treeskel.counts);
    result.timing = await page.evaluate(() => window.treeskel.timing);
    result.navigation = await page.evaluate(() => performance.getEntriesByType('navigation')[0].toJSON());
    result.report_rows = await page.$$eval('#report tr', (rows) => rows.map((r) => [r.cells[0].textContent, r.cells[1].textContent]));
    result.warnings = await page.$$eval('#warnings li', (items) => items.map((i) => i.textContent));
    const canvas = page.locator('#view');
    await canvas.screenshot({ path: path.join(out_dir, 'all.png') });
    result.drawn.all = await canvasFigures(page);
    if (flags.includes('--toggles')) {
      const layers = ['cloud', 'skeleton', 'mesh'];
      for (const only of layers) {
        for (const layer of layers) {
          const box = page.locator('#show-' + layer);
          if (!(await box.isDisabled()) && (await box.isChecked()) !== (layer === only)) await box.click();
        }
        await canvas.screenshot({ path: path.join(out_dir, only + '.png') });
        result.drawn[only] = await canvasFigures(page);
      }
      for (const layer of layers) {
        const box = page.locator('#show-' + layer);
        if (!(await box.isDisabled()) && (await box.isChecked()) !== (layer === 'cloud')) await box.click();
      }
      for (const mode of ['status', 'height']) {
        await page.selectOption('#cloud-colour', mode);
        await canvas.screenshot({ path: path.join(out_dir, mode + '.png') });
        result.drawn[mode] = await canvasFigures(page);

      }
    }
  } finally {
    await browser.close();
  }
  console.log(JSON.stringify(result));
}

main().catch((e) => {
  console.error(String(e && e.stack ? e.stack : e));
  process.exit(1);
});
