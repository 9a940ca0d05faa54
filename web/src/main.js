// The playground's page: an editor of scene text with the diagnostics of
// `raytracer check` as you type, and the image `raytracer render` makes of
// it, re-rendered as the scene changes. Everything runs in the browser:
// the WebAssembly module (crates/web) checks in one Web Worker and renders
// in another (worker.js), so typing never waits for either. The bundle
// (web/build.mjs) carries the module, the worker's script, the sample
// and the built-in suite's scenes, and their texture; nothing is fetched.

import { EditorView, basicSetup } from "codemirror";
import { EditorState } from "@codemirror/state";
import { HighlightStyle, StreamLanguage, syntaxHighlighting } from "@codemirror/language";
import { lintGutter, setDiagnostics } from "@codemirror/lint";
import { tags } from "@lezer/highlight";
import assets from "assets:data";

// The largest side the page renders (crates/web's MAX_SIZE): a camera
// above it is shown at this size, the same view with fewer pixels.
const MAX_SIZE = 2048;
// A camera above COARSE_ABOVE pixels is first rendered at COARSE pixels,
// shown scaled up, then at its own size.
const COARSE_ABOVE = 200;
const COARSE = 100;

const $ = (id) => document.getElementById(id);
const status = $("status");
const canvas = $("image");
const context = canvas.getContext("2d");

function base64Bytes(base64) {
  const binary = atob(base64);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

// The module, compiled once and handed to every worker.
const module = new WebAssembly.Module(base64Bytes(assets.wasm));
const workerUrl = URL.createObjectURL(new Blob([assets.worker], { type: "text/javascript" }));

// The language's keywords, from the module itself.
const keywords = (() => {
  const wasm = new WebAssembly.Instance(module, {}).exports;
  wasm.web_language();
  const bytes = new Uint8Array(wasm.memory.buffer, wasm.web_output() >>> 0, wasm.web_output_len() >>> 0);
  return JSON.parse(new TextDecoder().decode(bytes));
})();

// Highlighting by line structure (grammar/scene.ebnf): the first word of a
// line is a section keyword or an attribute, `texture`'s value is a path,
// and `#` starts a comment.
function sceneLanguage() {
  const sections = new Set(keywords.sections);
  const attributes = new Set(keywords.attributes);
  const number = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;
  return StreamLanguage.define({
    name: "raytracer-scene",
    startState: () => ({ first: true, path: false }),
    token(stream, state) {
      if (stream.sol()) {
        state.first = true;
        state.path = false;
      }
      if (stream.eatSpace()) return null;
      if (stream.peek() === "#") {
        stream.skipToEnd();
        return "comment";
      }
      if (stream.peek() === '"') {
        stream.next();
        while (!stream.eol()) {
          const c = stream.next();
          if (c === "\\") stream.next();
          else if (c === '"') break;
        }
        state.first = state.path = false;
        return "string";
      }
      stream.eatWhile(/[^\s#"]/);
      const word = stream.current();
      const first = state.first;
      const path = state.path;
      state.first = state.path = false;
      if (path) return "string";
      if (number.test(word)) return "number";
      if (first && sections.has(word)) return "section";
      if (first && attributes.has(word)) {
        state.path = word === "texture";
        return "attribute";
      }
      return first ? "invalid" : null;
    },
    languageData: { commentTokens: { line: "#" } },
    tokenTable: { section: tags.keyword, attribute: tags.propertyName },
  });
}

const highlight = HighlightStyle.define([
  { tag: tags.keyword, color: "#7a3e9d", fontWeight: "bold" },
  { tag: tags.propertyName, color: "#1d5fa8" },
  { tag: tags.number, color: "#2a7a2a" },
  { tag: tags.string, color: "#a0522d" },
  { tag: tags.comment, color: "#777", fontStyle: "italic" },
  { tag: tags.invalid, color: "#c0392b" },
]);

// --- Scenes and textures --------------------------------------------------

const scenes = assets.scenes;
const textures = new Map(assets.textures.map((t) => [t.name, base64Bytes(t.base64)]));
let sceneName = scenes[0].name;

const isImage = (name) => /\.(ppm|png|jpe?g)$/i.test(name);

// --- Workers ---------------------------------------------------------------

function startWorker(onmessage) {
  const worker = new Worker(workerUrl);
  worker.onmessage = (event) => onmessage(event.data);
  worker.postMessage({ type: "init", module });
  for (const [name, bytes] of textures) worker.postMessage({ type: "texture", name, bytes });
  return worker;
}

// Each version of the text has a number; changedAt[n] is when it was typed.
let seq = 0;
const changedAt = new Map();
let checker = startWorker(onChecked);
let renderer = null;
let rendering = null; // {seq, size, text} of the render under way
let rendered = null; // {text, textures} of the image shown
let textureVersion = 0;
let firstDiagnostics = null;

// A new version of the text: check it, and stop the render of the old one.
function requestCheck() {
  if (renderer && rendering) {
    renderer.terminate();
    renderer = null;
    rendering = null;
    clearTimeout(flushTimer);
    flushTimer = null;
    bands = [];
  }
  seq += 1;
  status.dataset.seq = String(seq);
  changedAt.set(seq, performance.now());
  checker.postMessage({ type: "check", seq, name: sceneName, text: view.state.doc.toString() });
}

// --- Diagnostics -------------------------------------------------------------

// A function from a byte offset of `text`'s UTF-8 to its UTF-16 index.
function byteToIndex(text) {
  const utf8 = new TextEncoder().encode(text);
  if (utf8.length === text.length) return (offset) => offset;
  const index = new Uint32Array(utf8.length + 1);
  let byte = 0;
  for (let i = 0; i < text.length; ) {
    const point = text.codePointAt(i);
    const bytes = point < 0x80 ? 1 : point < 0x800 ? 2 : point < 0x10000 ? 3 : 4;
    const units = point < 0x10000 ? 1 : 2;
    for (let k = 0; k < bytes; k++) index[byte + k] = i;
    byte += bytes;
    i += units;
  }
  index[utf8.length] = text.length;
  return (offset) => index[Math.min(offset, utf8.length)];
}

// Apply `fix` (of the diagnostics of `checked`) if the text is still the
// one checked.
function applyFix(fix, checked) {
  if (view.state.doc.toString() !== checked.text) return;
  const at = byteToIndex(checked.text);
  view.dispatch({
    changes: fix.edits.map((e) => ({
      from: at(e.byte_offset),
      to: at(e.byte_offset + e.byte_length),
      insert: e.content,
    })),
  });
  view.focus();
}

function showDiagnostics(checked) {
  const { result, text } = checked;
  const at = byteToIndex(text);
  const inline = [];
  const list = $("problems");
  list.replaceChildren();
  for (const d of result.diagnostics) {
    const label = d.labels[0];
    const from = label ? at(label.byte_offset) : 0;
    const to = label ? at(label.byte_offset + label.byte_length) : 0;
    const message = `${d.message} [${d.code}]` + (d.help ? `\nhelp: ${d.help}` : "");
    inline.push({
      from,
      to: Math.max(from, to),
      severity: d.severity === "error" ? "error" : d.severity === "warning" ? "warning" : "info",
      message,
      actions: d.fix ? [{ name: d.fix.message, apply: () => applyFix(d.fix, checked) }] : [],
    });
    const item = document.createElement("li");
    item.className = `problem ${d.severity}`;
    item.dataset.code = d.code;
    item.dataset.line = label ? label.line : "";
    const where = document.createElement("span");
    where.className = "where";
    where.textContent = label ? `${label.line}:${label.column}` : "";
    const code = document.createElement("code");
    code.textContent = d.code;
    const words = document.createElement("span");
    words.className = "message";
    words.textContent = d.message;
    item.append(where, " ", code, " ", words);
    if (d.help) {
      const help = document.createElement("div");
      help.className = "help";
      help.textContent = `help: ${d.help}`;
      item.append(help);
    }
    if (d.fix) {
      const button = document.createElement("button");
      button.className = "fix";
      button.textContent = `Fix: ${d.fix.message}`;
      button.onclick = (event) => {
        event.stopPropagation();
        applyFix(d.fix, checked);
      };
      item.append(button);
    }
    item.onclick = () => {
      if (view.state.doc.toString() !== text) return;
      view.dispatch({ selection: { anchor: from, head: Math.max(from, to) }, scrollIntoView: true });
      view.focus();
    };
    list.append(item);
  }
  $("problem-count").textContent =
    result.diagnostics.length === 0 ? "No problems" : `${result.errors} errors, ${result.warnings} warnings`;
  view.dispatch(setDiagnostics(view.state, inline));
}

function onChecked(message) {
  if (message.type === "failed") {
    // The module aborted on this text: a bug to report, not to hang on.
    checker.terminate();
    checker = startWorker(onChecked);
    setStatus("error", `The checker stopped on this text (${message.message}); please report it.`);
    return;
  }
  if (message.seq !== seq) return; // outrun by a newer text
  const now = performance.now();
  const text = view.state.doc.toString();
  const checked = { seq: message.seq, text, result: JSON.parse(message.result) };
  showDiagnostics(checked);
  if (firstDiagnostics === null) {
    firstDiagnostics = now;
    status.dataset.firstDiagnosticsMs = now.toFixed(1);
  }
  status.dataset.latencyMs = (now - changedAt.get(message.seq)).toFixed(1);
  status.dataset.checkMs = message.ms.toFixed(1);
  changedAt.clear();
  status.dataset.checkedSeq = String(message.seq);
  const resolution = checked.result.resolution;
  if (resolution == null) {
    canvas.classList.add("stale");
    setStatus("errors", "The image is of the last scene without errors.");
    return;
  }
  if (rendered && rendered.text === text && rendered.textures === textureVersion) {
    canvas.classList.remove("stale");
    return;
  }
  startRender(text, resolution);
}

// --- Rendering -----------------------------------------------------------------

function setStatus(state, text) {
  status.dataset.state = state;
  status.textContent = text;
}

function startRender(text, resolution) {
  if (!renderer) renderer = startWorker(onRendered);
  const size = Math.min(resolution, MAX_SIZE);
  const coarse = size > COARSE_ABOVE ? COARSE : 0;
  rendering = { seq, size, text, textures: textureVersion };
  // The canvas is drawn over from here: it shows no finished image.
  rendered = null;
  delete status.dataset.coarse;
  $("download-png").disabled = true;
  if (canvas.width !== size) {
    canvas.width = canvas.height = size;
  }
  const note = resolution > MAX_SIZE ? ` (the camera's ${resolution} × ${resolution} is shown at ${size} × ${size}: use \`raytracer render\` for every pixel)` : "";
  setStatus("rendering", `Rendering ${size} × ${size}…${note}`);
  renderer.postMessage({ type: "render", seq, name: sceneName, text, coarse, size });
}

// A band of RGB rows as image data.
function rgba(rgb, width, rows) {
  const data = new ImageData(width, rows);
  for (let p = 0, q = 0; p < rgb.length; p += 3, q += 4) {
    data.data[q] = rgb[p];
    data.data[q + 1] = rgb[p + 1];
    data.data[q + 2] = rgb[p + 2];
    data.data[q + 3] = 255;
  }
  return data;
}

// The coarse image lies under the canvas (index.html), scaled up by CSS,
// and shows through wherever the full image has no band yet.
const coarseCanvas = $("coarse");
// Bands received and not yet drawn: drawing is batched, at most every
// FLUSH_MS, as each drawing of a large canvas costs the page's thread
// far more than the band's pixels.
const FLUSH_MS = 100;
let bands = [];
let flushTimer = null;

function flush() {
  flushTimer = null;
  for (const { data, start } of bands) context.putImageData(data, 0, start);
  bands = [];
}

function onFrame(message) {
  const rows = message.end - message.start;
  const data = rgba(message.rgb, message.size, rows);
  if (message.size !== rendering.size) {
    if (coarseCanvas.width !== message.size) coarseCanvas.width = coarseCanvas.height = message.size;
    coarseCanvas.getContext("2d").putImageData(data, 0, message.start);
    if (message.end === message.size) {
      // The old image goes, and the coarse one shows until the bands
      // cover it.
      context.clearRect(0, 0, canvas.width, canvas.height);
      coarseCanvas.hidden = false;
      canvas.classList.remove("stale");
      status.dataset.coarse = String(message.size);
    }
    return;
  }
  bands.push({ data, start: message.start });
  flushTimer ??= setTimeout(flush, FLUSH_MS);
}

function onRendered(message) {
  if (!rendering || message.seq !== rendering.seq) return;
  if (message.type === "failed") {
    renderer.terminate();
    renderer = null;
    rendering = null;
    setStatus("error", `The renderer stopped (${message.message}); please report it.`);
    return;
  }
  if (message.type === "frame") {
    onFrame(message);
    return;
  }
  // "rendered": the last bands drawn, the coarse image hidden, and the
  // status no longer says one shows (a test waiting for the next
  // render's coarse frame must not find this one's).
  clearTimeout(flushTimer);
  flush();
  coarseCanvas.hidden = true;
  delete status.dataset.coarse;
  canvas.classList.remove("stale");
  rendered = { text: rendering.text, textures: rendering.textures };
  status.dataset.renderMs = message.ms.toFixed(1);
  status.dataset.renderedSize = String(message.size);
  setStatus("rendered", `Rendered ${message.size} × ${message.size} in ${Math.round(message.ms)} ms; diagnostics in ${status.dataset.latencyMs} ms.`);
  rendering = null;
  $("download-png").disabled = false;
}

// --- Files -----------------------------------------------------------------------

function showTextures() {
  const list = $("textures");
  list.replaceChildren();
  for (const [name, bytes] of textures) {
    const item = document.createElement("li");
    item.textContent = `${name} (${bytes.length} bytes)`;
    list.append(item);
  }
}

function addTexture(name, bytes) {
  textures.set(name, bytes);
  textureVersion += 1;
  checker.postMessage({ type: "texture", name, bytes });
  // The renderer holds the old files: the next render starts a fresh one.
  if (renderer) renderer.terminate();
  renderer = null;
  rendering = null;
  clearTimeout(flushTimer);
  flushTimer = null;
  bands = [];
  showTextures();
  requestCheck();
}

function openScene(name, text) {
  sceneName = name;
  $("scene-name").textContent = name;
  view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: text } });
}

// Textures (by extension) are kept; any other file is opened as the scene.
async function openFiles(files) {
  for (const file of files) {
    const bytes = new Uint8Array(await file.arrayBuffer());
    if (isImage(file.name)) addTexture(file.name, bytes);
    else openScene(file.name, new TextDecoder().decode(bytes));
  }
}

// --- Share links and downloads -------------------------------------------------------

// The scene in a URL fragment: `#scene=` and the deflated UTF-8 text in
// URL-safe base64, with the name after `&name=`.
async function shareFragment(name, text) {
  const stream = new Blob([text]).stream().pipeThrough(new CompressionStream("deflate-raw"));
  const bytes = new Uint8Array(await new Response(stream).arrayBuffer());
  let binary = "";
  for (const b of bytes) binary += String.fromCharCode(b);
  const base64 = btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
  return `#scene=${base64}&name=${encodeURIComponent(name)}`;
}

async function sharedScene(fragment) {
  const params = new URLSearchParams(fragment.replace(/^#/, ""));
  const encoded = params.get("scene");
  if (!encoded) return null;
  const bytes = base64Bytes(encoded.replace(/-/g, "+").replace(/_/g, "/"));
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate-raw"));
  const text = await new Response(stream).text();
  return { name: params.get("name") || "scene.txt", text };
}

function download(blob, name) {
  const link = document.createElement("a");
  link.href = URL.createObjectURL(blob);
  link.download = name;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(link.href), 60_000);
}

const stem = () => sceneName.replace(/\.[^.]*$/, "") || "scene";

// --- The page ---------------------------------------------------------------------

const view = new EditorView({
  parent: $("editor"),
  state: EditorState.create({
    doc: "",
    extensions: [
      basicSetup,
      sceneLanguage(),
      syntaxHighlighting(highlight),
      lintGutter(),
      EditorView.updateListener.of((update) => {
        if (update.docChanged) requestCheck();
      }),
    ],
  }),
});

const picker = $("scene-picker");
for (const [i, scene] of scenes.entries()) {
  const option = document.createElement("option");
  option.value = String(i);
  option.textContent = scene.title;
  picker.append(option);
}
picker.onchange = () => {
  const scene = scenes[Number(picker.value)];
  openScene(scene.name, scene.text);
};

$("files").onchange = (event) => openFiles(event.target.files);
document.addEventListener("dragover", (event) => {
  event.preventDefault();
  document.body.classList.add("dragging");
});
document.addEventListener("dragleave", () => document.body.classList.remove("dragging"));
document.addEventListener("drop", (event) => {
  event.preventDefault();
  document.body.classList.remove("dragging");
  openFiles(event.dataTransfer.files);
});

$("share").onclick = async () => {
  const fragment = await shareFragment(sceneName, view.state.doc.toString());
  history.replaceState(null, "", fragment);
  const link = $("share-link");
  link.value = location.href;
  link.hidden = false;
  link.select();
  navigator.clipboard?.writeText(location.href).catch(() => {});
};
$("download-scene").onclick = () =>
  download(new Blob([view.state.doc.toString()], { type: "text/plain" }), sceneName);
$("download-png").onclick = () => canvas.toBlob((blob) => download(blob, `${stem()}.png`), "image/png");

showTextures();
sharedScene(location.hash)
  .catch(() => null)
  .then((shared) => {
    const scene = shared || scenes[0];
    openScene(scene.name, scene.text);
    document.body.dataset.ready = "true";
  });
