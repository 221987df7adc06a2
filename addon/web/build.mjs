// Builds the page into the add-on (addon/bakegi/web/): viewer.js, one classic script with
// three.js inside (so that index.html also works opened from a folder, where browsers refuse
// modules), and index.html. `npm ci && npm run build`; tools/setup.sh runs it.
import { build } from "esbuild";
import { copyFileSync, mkdirSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const out = join(here, "..", "bakegi", "web");
mkdirSync(out, { recursive: true });
await build({
  entryPoints: [join(here, "src", "viewer.js")],
  bundle: true,
  format: "iife",
  minify: true,
  target: "es2020",
  outfile: join(out, "viewer.js"),
  logLevel: "warning",
});
copyFileSync(join(here, "src", "index.html"), join(out, "index.html"));
console.log(`built ${out}/viewer.js and index.html`);
