// Bundles the playground (`make web`, scripts/web.sh): node build.mjs
// WASM OUT. Writes OUT/index.html, OUT/style.css and OUT/playground.js,
// one script that carries the WebAssembly module, the worker's script
// (started from a blob: URL, since a page opened from file:// may not
// start a worker from a file), the sample and the built-in suite's
// scenes, and their texture, so the page fetches nothing.

import { readFileSync, copyFileSync } from "node:fs";
import { basename, dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { build } from "esbuild";

const [wasmPath, out] = process.argv.slice(2);
const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, "..");

const worker = await build({
  entryPoints: [join(here, "src/worker.js")],
  bundle: true,
  minify: true,
  format: "iife",
  write: false,
});

// The sample first, then the suite's scenes in its order.
const suite = JSON.parse(readFileSync(join(root, "suite/suite.json"), "utf8"));
const scenes = [
  { name: "sample.txt", title: "sample (scenes/sample.txt)", path: "scenes/sample.txt" },
  ...suite.scenes.map((s) => ({ name: basename(s.scene), title: `suite: ${s.scene}`, path: `suite/${s.scene}` })),
].map(({ name, title, path }) => ({ name, title, text: readFileSync(join(root, path), "utf8") }));

const data = {
  wasm: readFileSync(wasmPath).toString("base64"),
  worker: worker.outputFiles[0].text,
  scenes,
  textures: [{ name: "wood_tex.ppm", base64: readFileSync(join(root, "scenes/wood_tex.ppm")).toString("base64") }],
};

// `import assets from "assets:data"` in main.js is `data`.
const assets = {
  name: "assets",
  setup(b) {
    b.onResolve({ filter: /^assets:/ }, (args) => ({ path: args.path, namespace: "assets" }));
    b.onLoad({ filter: /.*/, namespace: "assets" }, () => ({
      contents: `export default ${JSON.stringify(data)};`,
      loader: "js",
    }));
  },
};

await build({
  entryPoints: [join(here, "src/main.js")],
  bundle: true,
  minify: true,
  format: "iife",
  outfile: join(out, "playground.js"),
  plugins: [assets],
  legalComments: "linked",
});
copyFileSync(join(here, "index.html"), join(out, "index.html"));
copyFileSync(join(here, "style.css"), join(out, "style.css"));
