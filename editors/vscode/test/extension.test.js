// extension.js under node's test runner, with stand-ins for the `vscode`
// module and the language client (VS Code itself is not run here): what
// it asks VS Code and the client to do on activation, for `.txt`
// documents, when the server cannot start, and when `raytracer.path`
// changes.

"use strict";

const test = require("node:test");
const assert = require("node:assert");
const Module = require("node:module");

/** Everything the stand-ins were asked to do, in order. */
const calls = [];
const settings = { path: "raytracer", detectTxt: true };
let failStart = false;
let listeners = {};

const vscode = {
  workspace: {
    textDocuments: [],
    getConfiguration: () => ({ get: (key, fallback) => settings[key] ?? fallback }),
    onDidOpenTextDocument: (listener) => ((listeners.open = listener), { dispose() {} }),
    onDidChangeConfiguration: (listener) => ((listeners.config = listener), { dispose() {} }),
  },
  languages: {
    setTextDocumentLanguage: (document, language) =>
      calls.push(["setLanguage", document.uri.path, language]),
  },
  window: {
    showErrorMessage: (message) => calls.push(["error", message]),
  },
};

class LanguageClient {
  constructor(id, name, server, client) {
    calls.push(["client", server.command, server.args, client.documentSelector.map((s) => s.language)]);
  }
  async start() {
    if (failStart) {
      throw new Error("spawn nowhere ENOENT");
    }
    calls.push(["start"]);
  }
  async stop() {
    calls.push(["stop"]);
  }
}

const load = Module._load;
Module._load = function (request, ...rest) {
  if (request === "vscode") return vscode;
  if (request === "vscode-languageclient/node") return { LanguageClient };
  return load.call(this, request, ...rest);
};
const extension = require("../extension");

function document(path, languageId, text) {
  return { uri: { path }, languageId, getText: () => text };
}

test("activation starts `raytracer lsp` for scene documents and detects open .txt scenes", async () => {
  calls.length = 0;
  vscode.workspace.textDocuments = [
    document("/s/sample.txt", "plaintext", "# header\ncamera 400\n"),
    document("/s/notes.txt", "plaintext", "Some notes\n"),
    document("/s/sample.md", "markdown", "camera 400\n"),
  ];
  await extension.activate({ subscriptions: [] });
  assert.deepStrictEqual(calls, [
    ["setLanguage", "/s/sample.txt", "raytracer"],
    ["client", "raytracer", ["lsp"], ["raytracer", "raytracer"]],
    ["start"],
  ]);

  calls.length = 0;
  listeners.open(document("/s/other.TXT", "plaintext", "sphere center 0 0 -5\n"));
  settings.detectTxt = false;
  listeners.open(document("/s/off.txt", "plaintext", "sphere center 0 0 -5\n"));
  settings.detectTxt = true;
  assert.deepStrictEqual(calls, [["setLanguage", "/s/other.TXT", "raytracer"]]);
});

test("a new raytracer.path restarts the server; one that cannot start is reported", async () => {
  calls.length = 0;
  settings.path = "/nowhere/raytracer";
  failStart = true;
  await listeners.config({ affectsConfiguration: (key) => key === "raytracer.path" });
  assert.strictEqual(calls.length, 3, JSON.stringify(calls));
  assert.deepStrictEqual(calls[0], ["stop"]);
  assert.deepStrictEqual(calls[1], ["client", "/nowhere/raytracer", ["lsp"], ["raytracer", "raytracer"]]);
  assert.match(calls[2][1], /^could not start `\/nowhere\/raytracer lsp`: spawn nowhere ENOENT; set `raytracer.path`/);

  calls.length = 0;
  await listeners.config({ affectsConfiguration: () => false });
  await extension.deactivate();
  assert.deepStrictEqual(calls, []);
});
