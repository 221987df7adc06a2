// How long the page takes to its first lit image (issue 16's 300 ms target), measured in
// Debian's Chromium against `bakegi serve` on loopback, in two situations:
//  - cold: a freshly launched browser opens the page (its GPU process starts with the page's
//    WebGL context: with software WebGL that alone is most of the time);
//  - warm: the browser has already shown a WebGL page in another tab (what a user with a
//    browser open sees when they follow a link); the page is opened in a new tab.
//   node test/first_image.mjs --cli build/bakegi --folder F [--loads 5] [--until 1] [--json out.json]
// (--until: the part of the stream each load asks for; the first image needs only its start).
// Prints, per situation, the median and range of the first image's time and where it went
// (the page's own timeline: script start, WebGL context, manifest, scene built, first image).
import { writeFileSync } from "node:fs";
import { chromium } from "playwright-core";
import { launchOptions, parseArgs, startServer } from "./harness.mjs";

const args = parseArgs(process.argv.slice(2));
const loads = Number(args.loads ?? 5);
const { server, url } = await startServer(args.cli, args.folder);

async function timedLoad(browser) {
  const page = await browser.newPage({ viewport: { width: 660, height: 420 } });
  await page.goto(`${url}?until=${args.until ?? 1}&size=640x400${args.extra ?? ''}`);
  await page.waitForFunction(() => ["done", "paused", "failed"].includes(window.bakegiState?.phase), null, { timeout: 120000 });
  const state = await page.evaluate(() => window.bakegiState);
  const arrival = await page.evaluate(() => {
    const [navigation] = performance.getEntriesByType("navigation");
    const script = performance.getEntriesByType("resource").find((r) => r.name.endsWith("viewer.js"));
    return { html_ms: navigation.responseEnd, script_request_ms: script?.requestStart, script_arrived_ms: script?.responseEnd };
  });
  await page.close();
  if (state.error) throw new Error(state.error);
  const t = state.timeline;
  return { first_image_ms: state.firstImageMs, script_ms: t.script, context_ms: t.context,
    manifest_ms: t.manifest, built_ms: t.built, done_ms: state.doneMs, ...arrival };
}

const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];
function summary(name, runs) {
  const row = (key) => `${key} ${median(runs.map((r) => r[key])).toFixed(0)}`;
  const firsts = runs.map((r) => r.first_image_ms);
  console.log(`${name}: first lit image median ${median(firsts).toFixed(0)} ms (${Math.min(...firsts).toFixed(0)}-${Math.max(...firsts).toFixed(0)}); ` +
    ["html_ms", "script_request_ms", "script_arrived_ms", "script_ms", "context_ms", "manifest_ms", "built_ms"].map(row).join(", "));
  return { runs, median_first_image_ms: median(firsts) };
}

const results = {};
try {
  const cold = [];
  for (let i = 0; i < loads; ++i) {
    const browser = await chromium.launch(launchOptions);
    try { cold.push(await timedLoad(browser)); } finally { await browser.close(); }
  }
  results.cold = summary("cold browser", cold);
  const browser = await chromium.launch(launchOptions);
  try {
    await timedLoad(browser);  // the browser's GPU process and caches are up after this
    const warm = [];
    for (let i = 0; i < loads; ++i) warm.push(await timedLoad(browser));
    results.warm = summary("warm browser, new tab", warm);
  } finally { await browser.close(); }
} finally {
  server.kill();
}
if (args.json) writeFileSync(args.json, JSON.stringify(results, null, 1));
