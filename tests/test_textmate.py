"""The editor side in lsp/vscode: the extension's manifest agrees with scriptc, and
`lsp/vscode/scripts/check.sh` builds the .vsix with @vscode/vsce and passes the TextMate
grammar tests (`lsp/vscode/tests/*.test.script`, vscode-tmgrammar-test).

check.sh installs the npm tools with `npm ci` when `node_modules` does not match the lock
file (about 25 s with a warm npm cache, the npm registry otherwise); with them installed the
check takes about 10 s. Node.js >= 20 and npm are part of the project's machine (see
docs/editors.md); a machine without them fails here rather than skipping.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from scriptc.project.files import SCRIPT_SUFFIX
from scriptc.testing import SUFFIX as TEST_SUFFIX

VSCODE = Path(__file__).parent.parent / "lsp" / "vscode"


def test_manifest_declares_the_language_the_grammar_and_the_server_setting() -> None:
    manifest = json.loads((VSCODE / "package.json").read_text(encoding="utf-8"))
    languages = {language["id"]: language for language in manifest["contributes"]["languages"]}
    grammars = {grammar["language"]: grammar for grammar in manifest["contributes"]["grammars"]}
    assert set(languages) == set(grammars) == {"scriptc", "scriptc-test"}
    language, grammar = languages["scriptc"], grammars["scriptc"]
    assert SCRIPT_SUFFIX in language["extensions"]
    assert grammar["scopeName"] == "source.scriptc" and (VSCODE / grammar["path"]).is_file()
    assert (VSCODE / language["configuration"]).is_file()
    # Test files are a language of their own, so that the client sends them to the server
    # (docs/editors.md): TOML, highlighted by the editor's TOML grammar when there is one.
    tests, test_grammar = languages["scriptc-test"], grammars["scriptc-test"]
    assert tests["filenamePatterns"] == [f"*{TEST_SUFFIX}"]
    assert (VSCODE / tests["configuration"]).is_file()
    assert json.loads((VSCODE / test_grammar["path"]).read_text(encoding="utf-8"))[
        "patterns"] == [{"include": "source.toml"}]
    assert set(manifest["activationEvents"]) == {"onLanguage:scriptc", "onLanguage:scriptc-test"}
    settings = manifest["contributes"]["configuration"]["properties"]
    assert settings["scriptc.path"]["default"] == "scriptc"
    assert settings["scriptc.args"]["default"] == ["lsp"]
    assert (VSCODE / manifest["main"]).is_file()
    assert (VSCODE / "package-lock.json").is_file()


def test_language_configuration_knows_brackets_and_percent_comments() -> None:
    config = json.loads((VSCODE / "language-configuration.json").read_text(encoding="utf-8"))
    assert config["comments"]["blockComment"] == ["%", "%"]
    assert config["brackets"] == [["[", "]"], ["(", ")"], ["{", "}"]]


@pytest.mark.packaging
def test_vsix_builds_and_grammar_tests_pass() -> None:
    assert shutil.which("node") and shutil.which("npm"), (
        "Node.js and npm are needed (docs/editors.md)")
    done = subprocess.run(["bash", str(VSCODE / "scripts" / "check.sh")], capture_output=True,
                          text=True, timeout=300, stdin=subprocess.DEVNULL, check=False)
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-4000:]
    assert "== ok" in done.stdout
    for name in ("items", "blocks", "conditions", "comments", "strings"):
        assert f"tests/{name}.test.script run successfuly" in done.stdout
    assert (VSCODE / "scriptc.vsix").is_file()
