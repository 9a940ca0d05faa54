// The playground's Web Worker: the WebAssembly module (crates/web) off the
// page's thread. The page runs two: one that checks each version of the
// text as it is typed ("check"), and one that renders the last valid
// version ("render"), which the page ends (Worker.terminate) when the text
// changes again, so a long render never delays the next.
//
// Messages in: {type: "init", module} first (a compiled
// WebAssembly.Module), then {type: "texture", name, bytes} (a file a scene
// may name), {type: "check", seq, name, text} and {type: "render", seq,
// name, text, coarse, size}. Messages out: {type: "checked", seq, result,
// ms} (result is web_check's JSON), {type: "frame", seq, size, start, end,
// rgb} per band of rows (a coarse frame first when asked) and {type:
// "rendered", seq, size, ms} when the last band is done; {type: "failed",
// seq, message} when the module aborted.

let wasm = null;
// The last check asked for, and whether one is waiting to run: a check
// that is outrun by a newer text is skipped.
let pendingCheck = null;
let checkScheduled = false;
const encoder = new TextEncoder();

// Put `name` then `bytes` in the module's input buffer; the name's length.
function give(name, bytes) {
  const nameBytes = encoder.encode(name);
  const length = nameBytes.length + bytes.length;
  const at = wasm.web_input(length) >>> 0;
  const input = new Uint8Array(wasm.memory.buffer, at, length);
  input.set(nameBytes);
  input.set(bytes, nameBytes.length);
  return nameBytes.length;
}

// A copy of what the module's last call left in its output buffer.
function output() {
  const at = wasm.web_output() >>> 0;
  const length = wasm.web_output_len() >>> 0;
  return new Uint8Array(wasm.memory.buffer, at, length).slice();
}

function check() {
  checkScheduled = false;
  const { seq, name, text } = pendingCheck;
  const started = performance.now();
  try {
    wasm.web_check(give(name, encoder.encode(text)));
    const result = new TextDecoder().decode(output());
    postMessage({ type: "checked", seq, result, ms: performance.now() - started });
  } catch (error) {
    // The module aborted (it is built with panic = "abort"): this
    // instance is spent, and the page starts another worker.
    postMessage({ type: "failed", seq, message: String(error) });
  }
}

// Rows per band: about 32,768 pixels, so a band takes a few milliseconds
// on the sample and the page fills in as it goes.
function bandRows(size) {
  return Math.max(1, Math.floor(32768 / size));
}

function renderFrame(seq, size) {
  const rows = bandRows(size);
  for (let start = 0; start < size; start += rows) {
    const end = Math.min(size, start + rows);
    if (wasm.web_render(size, start, end) !== end - start) {
      throw new Error(`the module rendered no rows ${start}..${end} at ${size}`);
    }
    const rgb = output();
    postMessage({ type: "frame", seq, size, start, end, rgb }, [rgb.buffer]);
  }
}

function render({ seq, name, text, coarse, size }) {
  const started = performance.now();
  if (wasm.web_load(give(name, encoder.encode(text))) === 0) {
    throw new Error("the scene did not load");
  }
  if (coarse > 0) {
    renderFrame(seq, coarse);
  }
  renderFrame(seq, size);
  postMessage({ type: "rendered", seq, size, ms: performance.now() - started });
}

onmessage = (event) => {
  const message = event.data;
  switch (message.type) {
    case "init":
      wasm = new WebAssembly.Instance(message.module, {}).exports;
      break;
    case "texture":
      wasm.web_texture(give(message.name, message.bytes));
      break;
    case "check":
      pendingCheck = message;
      if (!checkScheduled) {
        checkScheduled = true;
        setTimeout(check, 0);
      }
      break;
    case "render":
      try {
        render(message);
      } catch (error) {
        postMessage({ type: "failed", seq: message.seq, message: String(error) });
      }
      break;
  }
};
