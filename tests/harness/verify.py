"""The `verify` aspect of case files: what `scriptc verify` says of a script.

Under tests/cases/verify/, `NAME.script` is a case (it has its lint `.diagnostics` too, as
every script of the cases); beside it:

- `NAME.verify`: the line of each property (as `scriptc verify` prints them), an empty line,
  then the diagnostics of the verification in the form of every diagnostics file
  (harness/diagnostics.py): each Y code whole, with the `scriptc run` command that replays the
  run that shows it, the scenario files named as `scriptc verify` names them in
  `scriptc-verify/`;
- `NAME.verify.json`: the result as `scriptc verify --json` prints it, without the seconds.

Each case is verified twice: the two results must be identical (the exploration and the worlds
it writes depend on nothing but the script).
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path

from harness import CASES, Check, expect, files, relative
from harness.diagnostics import rendered

FOLDER = "scriptc-verify"


def _outputs(path: Path) -> tuple[Path, Path]:
    return path.with_suffix(".verify"), path.with_name(path.stem + ".verify.json")


def outputs(path: Path) -> tuple[str, str]:
    """The two expected texts of the case `path` (see the module's docstring)."""
    from scriptc.ops.verify import VerifyOptions, replay_command, verify_file
    from scriptc.verify.report import as_data, diagnostics, property_lines

    with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(CASES):
        name = relative(path)
        result = verify_file(name, VerifyOptions(counterexamples=os.path.join(tmp, FOLDER)))
        assert result.verification is not None, result.problem
        verification = result.verification
        written = {k: os.path.join(FOLDER, os.path.basename(v))
                   for k, v in result.written.items()}
        until = {w.name: w.until for f in verification.findings
                 if (w := f.witness) is not None}
        replays = {k: replay_command(name, v, until.get(k) if k == "no-stall" else None)
                   for k, v in written.items()}
        found = diagnostics(verification, replays)
        assert result.analysis is not None
        text = property_lines(verification) + "\n" + rendered(result.analysis.source, found,
                                                               lambda _text: found)
        data = as_data(name, verification, written, result.assumptions)
        data.pop("seconds")
        return text, json.dumps(data, indent=1, ensure_ascii=False) + "\n"


def _case(path: Path) -> None:
    first, second = outputs(path), outputs(path)
    assert first == second, "two verifications of the script differ"
    text_file, json_file = _outputs(path)
    expect(text_file, first[0])
    expect(json_file, first[1])


def checks() -> list[Check]:
    return [Check("verify", p, _outputs(p), lambda p=p: _case(p))
            for p in files("verify", "*.script")]
