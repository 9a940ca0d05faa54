// Feeds files to the playground's WebAssembly module as the page's
// workers do (web/src/worker.js), for tests/playground.rs: node
// hostile.mjs MODULE FILE... prints, per file, one JSON line with the
// diagnostics of web_check and whether web_load kept a scene, which is
// then rendered at 8 × 8. Exits non-zero if the module aborts.

import { readFileSync } from "node:fs";
import { basename } from "node:path";

const [modulePath, ...files] = process.argv.slice(2);
const module = new WebAssembly.Module(readFileSync(modulePath));
const encoder = new TextEncoder();

for (const file of files) {
  // A fresh instance per file, as an aborted one cannot be used again.
  const wasm = new WebAssembly.Instance(module, {}).exports;
  const give = (name, bytes) => {
    const nameBytes = encoder.encode(name);
    const length = nameBytes.length + bytes.length;
    // web_input may grow the memory, which detaches the old buffer: ask
    // for the buffer after it.
    const at = wasm.web_input(length) >>> 0;
    const input = new Uint8Array(wasm.memory.buffer, at, length);
    input.set(nameBytes);
    input.set(bytes, nameBytes.length);
    return nameBytes.length;
  };
  const output = () =>
    new TextDecoder().decode(new Uint8Array(wasm.memory.buffer, wasm.web_output() >>> 0, wasm.web_output_len() >>> 0));
  const name = basename(file);
  const bytes = readFileSync(file);
  wasm.web_check(give(name, bytes));
  const { diagnostics } = JSON.parse(output());
  const rendered = wasm.web_load(give(name, bytes)) > 0;
  if (rendered && wasm.web_render(8, 0, 8) !== 8) throw new Error(`${name}: no rows rendered`);
  console.log(JSON.stringify({ name, diagnostics, rendered }));
}
