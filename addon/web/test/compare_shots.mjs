// Screenshots of one served web export in three readings of the grid, for docs/ivg.md: the
// page as it is, without the vertices' _BAKEGI_READS_GRID (?reach=0) and the paper's reading
// (?visibility=0); the grid's light on white, 640x400.
//   node addon/web/test/compare_shots.mjs path/to/bakegi FOLDER OUT_PREFIX
// writes OUT_PREFIX_reach.png, OUT_PREFIX_no_reach.png and OUT_PREFIX_paper.png.
import { chromium } from "playwright-core";
import { launchOptions, startServer } from "./harness.mjs";
const [cli, folder, out] = process.argv.slice(2);
const { server, url } = await startServer(cli, folder);
const browser = await chromium.launch(launchOptions);
const page = await browser.newPage({ viewport: { width: 660, height: 420 } });
for (const [name, q] of [["reach", ""], ["no_reach", "&reach=0"], ["paper", "&visibility=0"]]) {
  await page.goto(`${url}?until=1&mode=light&size=640x400&panel=0${q}`);
  await page.waitForFunction(() => ["done", "failed"].includes(window.bakegiState?.phase), null, { timeout: 120000 });
  await page.locator("#view").screenshot({ path: `${out}_${name}.png` });
}
await browser.close();
server.kill();
