// The VS Code side of scriptc: starts `scriptc lsp` (the language server, over stdio) for
// robot activity scripts, and for their test files (`*.test.toml`, the language
// `scriptc-test`: the server reports their problems). Highlighting is the TextMate grammar in
// syntaxes/; everything else (diagnostics, formatting, hovers, navigation) comes from the
// server.
"use strict";

const path = require("path");
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client = null;

// `scriptc.path` may name a command on PATH (`scriptc`), an absolute path, or a path relative
// to the first workspace folder (`.venv/bin/scriptc`); `${workspaceFolder}` is expanded.
function resolveCommand(setting) {
  const folders = vscode.workspace.workspaceFolders || [];
  const root = folders.length ? folders[0].uri.fsPath : "";
  let command = (setting || "scriptc").replace(/\$\{workspaceFolder\}/g, root);
  if (root && !path.isAbsolute(command) && /[\\/]/.test(command)) {
    command = path.join(root, command);
  }
  return command;
}

function createClient() {
  const config = vscode.workspace.getConfiguration("scriptc");
  const command = resolveCommand(config.get("path"));
  const args = config.get("args") || ["lsp"];
  const run = { command, args, transport: TransportKind.stdio };
  const serverOptions = { run, debug: run };
  const clientOptions = {
    documentSelector: [
      { scheme: "file", language: "scriptc" },
      { scheme: "untitled", language: "scriptc" },
      // A test file's paths are relative to it: only a file on disk can be checked.
      { scheme: "file", language: "scriptc-test" },
    ],
    synchronize: {
      fileEvents: vscode.workspace.createFileSystemWatcher("**/{*.script,scriptc.toml,pyproject.toml}"),
    },
    outputChannelName: "scriptc",
  };
  return new LanguageClient("scriptc", "scriptc", serverOptions, clientOptions);
}

async function start() {
  client = createClient();
  try {
    await client.start();
  } catch (error) {
    const command = resolveCommand(vscode.workspace.getConfiguration("scriptc").get("path"));
    const choice = await vscode.window.showErrorMessage(
      `scriptc: could not start the language server with \`${command} lsp\` (${error.message || error}). ` +
        "Install scriptc from its source repository (docs/cli.md, \"Installing scriptc\") or set `scriptc.path`.",
      "Open Settings"
    );
    if (choice === "Open Settings") {
      vscode.commands.executeCommand("workbench.action.openSettings", "scriptc.path");
    }
  }
}

async function stop() {
  if (client) {
    const running = client;
    client = null;
    try {
      await running.stop();
    } catch (_error) {
      // a server that never started has nothing to stop
    }
  }
}

async function restart() {
  await stop();
  await start();
}

function activate(context) {
  context.subscriptions.push(
    vscode.commands.registerCommand("scriptc.restartServer", restart),
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (event.affectsConfiguration("scriptc.path") || event.affectsConfiguration("scriptc.args")) {
        restart();
      }
    })
  );
  return start();
}

function deactivate() {
  return stop();
}

module.exports = { activate, deactivate, resolveCommand };
