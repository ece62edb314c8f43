// The VS Code side of scriptc: starts `scriptc lsp` (the language server, over stdio) for
// robot activity scripts, and for their test files (`*.test.toml`, the language
// `scriptc-test`: the server reports their problems). Highlighting is the TextMate grammar in
// syntaxes/; everything else (diagnostics, formatting, hovers, navigation) comes from the
// server. The command "scriptc: Show the flow graph" shows `scriptc graph`'s drawing of the
// open script beside it (below).
"use strict";

const childProcess = require("child_process");
const crypto = require("crypto");
const fs = require("fs");
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

// -- the flow graph ----------------------------------------------------------------------------
//
// `scriptc graph - --stdin-filename FILE --format svg -o -` on the editor's text (unsaved
// changes included), shown in a webview beside the editor and drawn again as the text
// changes. Without Graphviz (scriptc says so with status 2 and `apt-get install graphviz`),
// the Mermaid text of `--format mermaid` is drawn by the copy of Mermaid in media/ (put there
// by scripts/vendor-mermaid.js when the extension is packaged): nothing is loaded from the
// network. A script with errors shows its diagnostics.

const GRAPH_COMMAND = "scriptc.showGraph";
const MERMAID = ["media", "mermaid.min.js"];
const REDRAW_DELAY_MS = 400;
const panels = new Map(); // document URI -> { panel, timer, version }

// Whether scriptc's stderr says that Graphviz's `dot` is missing (tests/test_views_graph.py
// holds the CLI's message to the words looked for here).
function dotMissing(status, stderr) {
  return status === 2 && /apt-get install graphviz/.test(stderr || "");
}

function escapeHtml(text) {
  return String(text)
    .replace(/&/g, "&amp;")
    .replace(/</g, "&lt;")
    .replace(/>/g, "&gt;")
    .replace(/"/g, "&quot;");
}

// The SVG that Graphviz wrote, without what may not stand inside HTML (its XML declaration,
// its DOCTYPE and comments before the <svg> element).
function inlineSvg(svg) {
  const start = svg.indexOf("<svg");
  return start < 0 ? "" : svg.slice(start);
}

// The webview's page. `view` is one of
//   { kind: "svg", svg }                         Graphviz's drawing
//   { kind: "mermaid", mermaid, mermaidSrc }     Mermaid's text, drawn by the local bundle
//   { kind: "text", text }                       what scriptc said (errors), or a graph's text
// with `title` and `note` (a line above, e.g. why Mermaid draws it). `cspSource` is the
// webview's own source (webview.cspSource), `nonce` a fresh one: the Content-Security-Policy
// allows no network at all, scripts only with the nonce (Mermaid's bundle and its start).
function graphHtml(view, cspSource, nonce) {
  const scripts = view.kind === "mermaid" && view.mermaidSrc;
  const csp = [
    "default-src 'none'",
    `img-src ${cspSource} data:`,
    `style-src ${cspSource} 'unsafe-inline'`,
    scripts ? `script-src 'nonce-${nonce}'` : "script-src 'none'",
  ].join("; ");
  let body = "";
  if (view.note) {
    body += `<p class="note">${escapeHtml(view.note)}</p>\n`;
  }
  if (view.kind === "svg") {
    body += `<div class="graph">${inlineSvg(view.svg)}</div>\n`;
  } else if (scripts) {
    body +=
      `<div class="graph"><pre class="mermaid">${escapeHtml(view.mermaid)}</pre></div>\n` +
      `<script nonce="${nonce}" src="${escapeHtml(view.mermaidSrc)}"></script>\n` +
      `<script nonce="${nonce}">mermaid.initialize({ startOnLoad: true, securityLevel: "strict" });</script>\n`;
  } else {
    body += `<pre class="text">${escapeHtml(view.kind === "mermaid" ? view.mermaid : view.text)}</pre>\n`;
  }
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="${csp}">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<title>${escapeHtml(view.title || "Flow graph")}</title>
<style>
  body { padding: 8px 12px; }
  .note { font-style: italic; }
  .graph { background: #ffffff; color: #000000; padding: 12px; border-radius: 4px; overflow: auto; }
  .graph svg { max-width: 100%; height: auto; }
  .text { white-space: pre-wrap; font-family: var(--vscode-editor-font-family, monospace); }
</style>
</head>
<body>
${body}</body>
</html>
`;
}

// Run scriptc with `args`, `input` on its stdin: { status, stdout (text), stderr, error }.
function runScriptc(args, input, cwd) {
  const command = resolveCommand(vscode.workspace.getConfiguration("scriptc").get("path"));
  return new Promise((resolve) => {
    let child;
    try {
      child = childProcess.spawn(command, args, { cwd, stdio: ["pipe", "pipe", "pipe"] });
    } catch (error) {
      resolve({ status: null, stdout: "", stderr: "", error: `${command}: ${error.message || error}` });
      return;
    }
    const out = [];
    const err = [];
    child.stdout.on("data", (chunk) => out.push(chunk));
    child.stderr.on("data", (chunk) => err.push(chunk));
    child.on("error", (error) => {
      resolve({ status: null, stdout: "", stderr: "", error: `${command}: ${error.message || error}` });
    });
    child.on("close", (status) => {
      resolve({
        status,
        stdout: Buffer.concat(out).toString("utf8"),
        stderr: Buffer.concat(err).toString("utf8"),
        error: null,
      });
    });
    child.stdin.on("error", () => {}); // scriptc may stop reading (a usage error)
    child.stdin.end(input, "utf8");
  });
}

// What the webview shows for a document: the `view` of graphHtml. `run(args, input)` runs
// scriptc (runScriptc); `mermaidSrc` is the webview URI of the local Mermaid bundle, or null
// when the extension has none.
async function graphView(document, run, mermaidSrc) {
  const name = document.isUntitled ? "untitled.script" : document.fileName;
  const title = `Flow: ${path.basename(name)}`;
  const args = (format) => ["graph", "-", "--stdin-filename", name, "--format", format, "-o", "-"];
  const text = document.getText();
  const svg = await run(args("svg"), text);
  if (svg.error) {
    return {
      kind: "text", title,
      text: `${svg.error}\n\nInstall scriptc, or set scriptc.path (the extension's README says how).`,
    };
  }
  if (svg.status === 0) {
    return { kind: "svg", title, svg: svg.stdout };
  }
  if (!dotMissing(svg.status, svg.stderr)) {
    return { kind: "text", title, note: "The script has errors: no graph.", text: svg.stderr };
  }
  const mermaid = await run(args("mermaid"), text);
  if (mermaid.status !== 0) {
    return { kind: "text", title, text: mermaid.error || mermaid.stderr };
  }
  if (!mermaidSrc) {
    return {
      kind: "text", title, text: mermaid.stdout,
      note: "Graphviz is not installed, so the graph cannot be drawn here: install it " +
        "(apt-get install graphviz, brew install graphviz) and run the command again. " +
        "Below is the graph as Mermaid, which GitHub draws in a ```mermaid block.",
    };
  }
  return {
    kind: "mermaid", title, mermaid: mermaid.stdout, mermaidSrc,
    note: "Drawn with Mermaid, since Graphviz is not installed " +
      "(apt-get install graphviz, brew install graphviz: scriptc draws the SVG then).",
  };
}

function nonce() {
  return crypto.randomBytes(16).toString("base64");
}

async function drawGraph(context, document, entry) {
  const version = document.version;
  entry.version = version;
  const webview = entry.panel.webview;
  const local = vscode.Uri.joinPath(context.extensionUri, ...MERMAID);
  const mermaidSrc = fs.existsSync(local.fsPath) ? String(webview.asWebviewUri(local)) : null;
  const folder = vscode.workspace.getWorkspaceFolder && vscode.workspace.getWorkspaceFolder(document.uri);
  const cwd = folder ? folder.uri.fsPath : document.isUntitled ? undefined : path.dirname(document.fileName);
  const view = await graphView(document, (args, input) => runScriptc(args, input, cwd), mermaidSrc);
  if (entry.version !== version || !panels.has(document.uri.toString())) {
    return; // a newer drawing is under way, or the panel was closed
  }
  entry.panel.title = view.title;
  webview.html = graphHtml(view, webview.cspSource, nonce());
}

async function showGraph(context) {
  const editor = vscode.window.activeTextEditor;
  if (!editor || editor.document.languageId !== "scriptc") {
    vscode.window.showInformationMessage("scriptc: open a script (.script) to see its flow graph.");
    return;
  }
  const document = editor.document;
  const key = document.uri.toString();
  let entry = panels.get(key);
  if (entry) {
    entry.panel.reveal(vscode.ViewColumn.Beside, true);
  } else {
    const panel = vscode.window.createWebviewPanel(
      "scriptcGraph",
      `Flow: ${path.basename(document.fileName)}`,
      { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
      { enableScripts: true, localResourceRoots: [vscode.Uri.joinPath(context.extensionUri, "media")] }
    );
    entry = { panel, timer: null, version: -1 };
    panels.set(key, entry);
    const changes = vscode.workspace.onDidChangeTextDocument((event) => {
      if (event.document.uri.toString() !== key) return;
      clearTimeout(entry.timer);
      entry.timer = setTimeout(() => drawGraph(context, event.document, entry), REDRAW_DELAY_MS);
    });
    panel.onDidDispose(() => {
      clearTimeout(entry.timer);
      changes.dispose();
      panels.delete(key);
    });
  }
  await drawGraph(context, document, entry);
}

function activate(context) {
  context.subscriptions.push(
    vscode.commands.registerCommand("scriptc.restartServer", restart),
    vscode.commands.registerCommand(GRAPH_COMMAND, () => showGraph(context)),
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

module.exports = {
  activate, deactivate, resolveCommand, graphHtml, graphView, dotMissing, runScriptc, showGraph,
};
