#!/usr/bin/env bash
# Build the VS Code extension into a .vsix and test its TextMate grammar.
#
#   bash lsp/vscode/scripts/check.sh        (from anywhere; needs Node.js >= 20 and npm)
#
# Installs the npm tools from package-lock.json (`npm ci`) unless node_modules already holds
# exactly that lock file, runs the grammar tests (tests/*.test.script, vscode-tmgrammar-test)
# and the client's tests (tests/*.test.js, node's test runner),
# packages the extension with @vscode/vsce into scriptc.vsix and checks what the package holds
# (python3 reads the zip).
# tests/test_textmate.py runs this script; CI runs it through that test.
set -euo pipefail
cd "$(dirname "$0")/.."

export npm_config_audit=false npm_config_fund=false npm_config_update_notifier=false

if ! cmp -s package-lock.json node_modules/.package-lock.json 2>/dev/null \
   && ! node -e '
     const a = require("./package-lock.json").packages, b = require("./node_modules/.package-lock.json").packages;
     for (const k of Object.keys(a)) { if (k && !a[k].optional && (!b[k] || b[k].version !== a[k].version)) process.exit(1); }
   ' 2>/dev/null; then
  echo "== npm ci"
  npm ci --prefer-offline --no-audit --no-fund --loglevel=error
fi

echo "== JSON files parse"
for f in package.json language-configuration.json test-language-configuration.json \
         syntaxes/scriptc.tmLanguage.json syntaxes/scriptc-test.tmLanguage.json; do
  node -e 'JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"))' "$f"
done
node --check extension.js

echo "== TextMate grammar tests"
npx --no-install vscode-tmgrammar-test -g syntaxes/scriptc.tmLanguage.json 'tests/*.test.script'

echo "== client (node --test, VS Code stood in for)"
log="$(mktemp)"
node --test tests/ >"$log" 2>&1 || { cat "$log"; rm -f "$log"; exit 1; }
grep -E '^# (pass|fail)' "$log"; rm -f "$log"

echo "== vsix"
rm -f scriptc.vsix
npx --no-install vsce package --allow-missing-repository --out scriptc.vsix </dev/null
# The package must hold the manifest, the client, the grammars, the language configurations,
# the client library (a runtime dependency) and Mermaid's bundle, and nothing of the tests or
# the dev tools.
python3 - <<'PY'
import os, sys, zipfile
names = zipfile.ZipFile("scriptc.vsix").namelist()
need = ["extension/package.json", "extension/extension.js", "extension/LICENSE.txt",
        "extension/syntaxes/scriptc.tmLanguage.json", "extension/language-configuration.json",
        "extension/syntaxes/scriptc-test.tmLanguage.json",
        "extension/test-language-configuration.json",
        "extension/node_modules/vscode-languageclient/node.js",
        # Mermaid, for the flow graph without Graphviz (scripts/vendor-mermaid.js, run by
        # vsce's vscode:prepublish): shipped, never loaded from the network
        "extension/media/mermaid.min.js", "extension/media/mermaid.LICENSE"]
missing = [n for n in need if n not in names]
unwanted = [n for n in names if n.startswith(("extension/tests/", "extension/scripts/"))
            or "/node_modules/vscode-tmgrammar-test/" in n or "/node_modules/@vscode/vsce" in n]
if missing or unwanted:
    sys.exit(f"scriptc.vsix: missing {missing}, unwanted {unwanted[:5]}")
print(f"scriptc.vsix: {len(names)} files, {os.path.getsize('scriptc.vsix')} bytes")
PY
echo "== ok"
