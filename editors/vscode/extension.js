// The VS Code extension for the raytracer's scene files: it starts
// `raytracer lsp` through vscode-languageclient for every scene document
// (diagnostics, quick fixes, formatting, hover, completion and semantic
// tokens come from the server), and opens a `.txt` file as a scene when its
// first word outside comments is a section keyword. The TextMate grammar in
// syntaxes/ colours a scene before the server answers and where it cannot
// start.

"use strict";

const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");
const { startsLikeScene } = require("./detect");

/** @type {LanguageClient | undefined} */
let client;

function settings() {
  return vscode.workspace.getConfiguration("raytracer");
}

/** A plain-text `.txt` document that reads as a scene becomes one. */
function detect(document) {
  if (
    document.languageId === "plaintext" &&
    document.uri.path.toLowerCase().endsWith(".txt") &&
    settings().get("detectTxt", true) &&
    startsLikeScene(document.getText())
  ) {
    vscode.languages.setTextDocumentLanguage(document, "raytracer");
  }
}

async function startClient() {
  const command = settings().get("path", "raytracer") || "raytracer";
  client = new LanguageClient(
    "raytracer",
    "raytracer lsp",
    { command, args: ["lsp"] },
    {
      documentSelector: [
        { scheme: "file", language: "raytracer" },
        { scheme: "untitled", language: "raytracer" },
      ],
    }
  );
  try {
    await client.start();
  } catch (error) {
    client = undefined;
    vscode.window.showErrorMessage(
      `could not start \`${command} lsp\`: ${error.message}; set \`raytracer.path\` to the raytracer binary`
    );
  }
}

async function stopClient() {
  const running = client;
  client = undefined;
  if (running) {
    await running.stop();
  }
}

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  context.subscriptions.push(
    vscode.workspace.onDidOpenTextDocument(detect),
    vscode.workspace.onDidChangeConfiguration(async (event) => {
      if (event.affectsConfiguration("raytracer.path")) {
        await stopClient();
        await startClient();
      }
    })
  );
  vscode.workspace.textDocuments.forEach(detect);
  await startClient();
}

function deactivate() {
  return stopClient();
}

module.exports = { activate, deactivate };
