"""The one runner of case files: every check of every case (tests/harness/ says what a case is,
which aspects apply to it and what each writes), and the rules that keep the cases whole."""

from __future__ import annotations

import json

import harness
import pytest
from harness.diagnostics import parsed

CHECKS = harness.checks()


@pytest.mark.parametrize("check", CHECKS, ids=[c.id for c in CHECKS])
def test_case(check: harness.Check) -> None:
    check.run()


def test_every_file_has_a_case() -> None:
    """Each file under tests/cases/ is an input, an expected output or a declared support file:
    an expected file whose input is gone (or misnamed) is found, not kept forever."""
    stray = harness.unaccounted(CHECKS)
    assert not stray, (f"files no case reads or expects (remove them, or see tests/harness/): "
                       f"{stray}")


def test_every_code_has_a_case() -> None:
    """Each code of the registry is reported by a case: a lint code in an expected diagnostics
    file, a verification's (family Y) in an expected `.verify` file, a run-time code (family
    X) in an `error` event of an expected trace."""
    from scriptc.diagnostics.codes import all_codes

    seen = set()
    for path in [*harness.files("", "*.diagnostics"), *harness.files("", "*.lint"),
                 *harness.files("verify", "*.verify")]:
        seen.update(code for _span, _severity, code, _message in
                    parsed(path.read_text(encoding="utf-8")))
    names = set()
    for path in harness.files("runtime", "*.trace.jsonl"):
        for line in path.read_text(encoding="utf-8").splitlines():
            event = json.loads(line)
            if event.get("event") == "error":
                names.add(event.get("code"))
    missing = [c.code for c in all_codes() if not c.retired
               and (c.name not in names if c.at_run_time else c.code not in seen)]
    assert not missing, f"codes without a case file: {missing}"


def test_messages_are_written_as_the_house_style_says() -> None:
    """rustc's style (CONTRIBUTING.md): a message starts lowercase (but for an acronym) and has
    no final period; every message of every case is held to it."""
    from test_codes import lowercase_start

    wrong = sorted({(code, message) for path in harness.files("", "*.diagnostics")
                    for _span, _severity, code, message in parsed(path.read_text(encoding="utf-8"))
                    if not lowercase_start(message) or message.endswith(".")})
    assert not wrong, wrong


def test_every_ide_feature_has_cases() -> None:
    from harness import ide

    features = {p.stem.split("_")[0] for p in ide.CASE_FILES}
    assert features == set(ide.FEATURES), set(ide.FEATURES) - features


def test_bytecode_refuses_what_no_vm_could_run() -> None:
    """The runtime cases left out of the VM's runs are refused by code generation, with the
    reason."""
    from harness.runtime import NOT_IN_BYTECODE, RUNTIME

    from scriptc.analysis.analyze import analyze_file
    from scriptc.emit.codegen import CodegenError
    from scriptc.ops.build import emit

    for name in NOT_IN_BYTECODE:
        path = RUNTIME / f"{name}.script"
        analysis = analyze_file(path, name=harness.relative(path))
        with pytest.raises(CodegenError, match="no block carries"):
            emit(analysis.script, "bytecode", analysis.source)
