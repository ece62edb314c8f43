#!/usr/bin/env node
// Puts Mermaid's browser bundle (dist/mermaid.min.js, one self-contained file) and its licence
// into media/, where the flow graph's webview loads it from when Graphviz is missing
// (extension.js, "scriptc: Show the flow graph"): the extension never loads Mermaid from the
// network. The package is fetched with npm's own client (`npm pack`) at the pinned version and
// checked against its pinned integrity; nothing else of Mermaid (its hundred dependencies,
// bundled into that file already) is installed. Nothing is fetched when media/ holds the
// pinned file already.
//
//   node scripts/vendor-mermaid.js      (run by `vscode:prepublish`, so by `vsce package`)
"use strict";

const crypto = require("node:crypto");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { execFileSync } = require("node:child_process");

const VERSION = "11.12.0";
// `npm view mermaid@11.12.0 dist.integrity`, and the sha256 of its dist/mermaid.min.js.
const INTEGRITY =
  "sha512-ZudVx73BwrMJfCFmSSJT84y6u5brEoV8DOItdHomNLz32uBjNrelm7mg95X7g+C6UoQH/W6mBLGDEDv73JdxBg==";
const BUNDLE_SHA256 = "07e37dfa97b337ccc85365d57eddf99b9706f09db3b59b260d0333b23b343c4b";
const MEDIA = path.join(__dirname, "..", "media");
const FILES = { "package/dist/mermaid.min.js": "mermaid.min.js", "package/LICENSE": "mermaid.LICENSE" };

function sha256(file) {
  return crypto.createHash("sha256").update(fs.readFileSync(file)).digest("hex");
}

function vendored() {
  const bundle = path.join(MEDIA, "mermaid.min.js");
  return fs.existsSync(bundle) && fs.existsSync(path.join(MEDIA, "mermaid.LICENSE")) &&
    sha256(bundle) === BUNDLE_SHA256;
}

function main() {
  if (vendored()) {
    console.log(`media/mermaid.min.js: Mermaid ${VERSION}, already there`);
    return;
  }
  const work = fs.mkdtempSync(path.join(os.tmpdir(), "scriptc-mermaid-"));
  try {
    const npm = process.platform === "win32" ? "npm.cmd" : "npm";
    execFileSync(npm, ["pack", `mermaid@${VERSION}`, "--pack-destination", work, "--silent",
                       "--prefer-offline"], { stdio: ["ignore", "ignore", "inherit"],
                                              shell: process.platform === "win32" });
    const tarball = path.join(work, `mermaid-${VERSION}.tgz`);
    const integrity = "sha512-" + crypto.createHash("sha512").update(fs.readFileSync(tarball)).digest("base64");
    if (integrity !== INTEGRITY) {
      throw new Error(`mermaid-${VERSION}.tgz: integrity ${integrity}, expected ${INTEGRITY}`);
    }
    execFileSync("tar", ["-xzf", tarball, "-C", work, ...Object.keys(FILES)], { stdio: "inherit" });
    if (sha256(path.join(work, "package/dist/mermaid.min.js")) !== BUNDLE_SHA256) {
      throw new Error(`mermaid-${VERSION}.tgz: dist/mermaid.min.js is not the pinned file`);
    }
    fs.mkdirSync(MEDIA, { recursive: true });
    for (const [from, to] of Object.entries(FILES)) {
      fs.copyFileSync(path.join(work, from), path.join(MEDIA, to));
    }
    console.log(`media/mermaid.min.js: Mermaid ${VERSION} (${INTEGRITY.slice(0, 19)}...)`);
  } finally {
    fs.rmSync(work, { recursive: true, force: true });
  }
}

try {
  main();
} catch (error) {
  console.error(`vendor-mermaid: ${error.message || error}`);
  process.exit(1);
}
