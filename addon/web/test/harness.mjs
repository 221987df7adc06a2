// What the page's browser scripts share (run.mjs, first_image.mjs): their --key value
// arguments, `bakegi serve` started on a free loopback port, and Chromium's launch options.
import { spawn } from "node:child_process";

// --key value pairs (a key followed by another key or nothing is true).
export function parseArgs(words) {
  return Object.fromEntries(
    words.reduce((pairs, word, i, all) => {
      if (word.startsWith("--")) pairs.push([word.slice(2), all[i + 1]?.startsWith("--") || all[i + 1] === undefined ? true : all[i + 1]]);
      return pairs;
    }, []));
}

// `cli serve folder` on port 0; resolves with the server process and its URL.
export function startServer(cli, folder, extra = []) {
  return new Promise((resolve, reject) => {
    const server = spawn(cli, ["serve", folder, "--port", "0", ...extra], { stdio: ["ignore", "pipe", "inherit"] });
    let text = "";
    server.stdout.on("data", (chunk) => {
      text += chunk;
      const match = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (match) resolve({ server, url: match[0] });
    });
    server.on("exit", (code) => reject(new Error(`bakegi serve exited (${code}): ${text}`)));
  });
}

export const launchOptions = {
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  // Software WebGL2 (SwiftShader): what a machine without a GPU has.
  args: ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--no-sandbox"],
};
