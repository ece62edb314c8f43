// The client without VS Code: `vscode` and `vscode-languageclient/node` are replaced by
// stand-ins that record what extension.js asks of them. Run by scripts/check.sh
// (`node --test tests/`).
"use strict";

const assert = require("node:assert");
const Module = require("node:module");
const path = require("node:path");
const test = require("node:test");

const settings = { path: "scriptc", args: ["lsp"] };
const started = [];
const commands = {};
const fakeVscode = {
  workspace: {
    workspaceFolders: [{ uri: { fsPath: "/work/project" } }],
    getConfiguration: () => ({ get: (key) => settings[key] }),
    createFileSystemWatcher: (glob) => ({ glob }),
    onDidChangeConfiguration: () => ({ dispose() {} }),
  },
  window: { showErrorMessage: async () => undefined },
  commands: {
    registerCommand: (name, fn) => {
      commands[name] = fn;
      return { dispose() {} };
    },
    executeCommand: () => undefined,
  },
};
class FakeClient {
  constructor(id, name, serverOptions, clientOptions) {
    Object.assign(this, { id, name, serverOptions, clientOptions });
  }
  async start() {
    started.push(this);
  }
  async stop() {}
}
const fakeClientLib = { LanguageClient: FakeClient, TransportKind: { stdio: 0 } };

const resolve = Module._resolveFilename;
Module._resolveFilename = function (request, ...rest) {
  if (request === "vscode" || request === "vscode-languageclient/node") return request;
  return resolve.call(this, request, ...rest);
};
require.cache.vscode = { id: "vscode", filename: "vscode", loaded: true, exports: fakeVscode };
require.cache["vscode-languageclient/node"] = {
  id: "vscode-languageclient/node", filename: "vscode-languageclient/node", loaded: true, exports: fakeClientLib,
};

const extension = require(path.join(__dirname, "..", "extension.js"));

test("scriptc.path: a command name, a path relative to the workspace, ${workspaceFolder}", () => {
  assert.strictEqual(extension.resolveCommand("scriptc"), "scriptc");
  assert.strictEqual(extension.resolveCommand(".venv/bin/scriptc"), path.join("/work/project", ".venv/bin/scriptc"));
  assert.strictEqual(extension.resolveCommand("${workspaceFolder}/bin/scriptc"), "/work/project/bin/scriptc");
  assert.strictEqual(extension.resolveCommand("/usr/bin/scriptc"), "/usr/bin/scriptc");
  assert.strictEqual(extension.resolveCommand(""), "scriptc");
});

test("activate starts `scriptc lsp` over stdio for scriptc documents and test files", async () => {
  const context = { subscriptions: [] };
  await extension.activate(context);
  assert.strictEqual(started.length, 1);
  const client = started[0];
  assert.deepStrictEqual(client.serverOptions.run, { command: "scriptc", args: ["lsp"], transport: 0 });
  assert.deepStrictEqual(client.clientOptions.documentSelector.map((s) => s.language), ["scriptc", "scriptc", "scriptc-test"]);
  assert.ok(typeof commands["scriptc.restartServer"] === "function");
  settings.path = ".venv/bin/scriptc";
  await commands["scriptc.restartServer"]();
  assert.strictEqual(started.length, 2);
  assert.strictEqual(started[1].serverOptions.run.command, path.join("/work/project", ".venv/bin/scriptc"));
  await extension.deactivate();
});
