"""No input makes any verb raise: every outcome is an exit code of 0, 1 or 2 with messages,
never a traceback (hypothesis, through click's runner and the real verbs)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scripts
from test_properties import JUNK

from scriptc.cli.main import cli

# Property tests over generated input: the slow tier (CONTRIBUTING.md).
pytestmark = pytest.mark.slow

FAST = settings(max_examples=60, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=10),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(
        st.sampled_from(["activityname", "goal0", "act0", "blk0", "type", "move", "toparse",
                         "truejump", "alfarulemessages", "x"]), inner, max_size=5),
    max_leaves=20,
)
BYTES = st.one_of(st.binary(max_size=200), JUNK.map(lambda t: t.encode("utf-8", "surrogatepass")))


def _run(args: list[str], tmp: Path, data: bytes, name: str) -> None:
    path = tmp / name
    path.write_bytes(data)
    result = CliRunner().invoke(cli, [*args, str(path)], catch_exceptions=True)
    assert result.exit_code in (0, 1, 2), (args, result.output, result.exception)
    assert "Traceback" not in result.output
    assert (not isinstance(result.exception, Exception)
            or isinstance(result.exception, SystemExit)), result.exception


@FAST
@given(data=BYTES)
def test_lint_and_compile_never_raise(tmp_path_factory, data: bytes) -> None:
    tmp = tmp_path_factory.mktemp("verbs")
    _run(["lint"], tmp, data, "x.script")
    _run(["lint", "--format", "sarif"], tmp, data, "x.script")
    _run(["compile", "-o", str(tmp / "out.json")], tmp, data, "x.script")


@FAST
@given(data=st.one_of(BYTES, JSON_VALUES.map(lambda v: json.dumps(v).encode())))
def test_check_and_decompile_never_raise(tmp_path_factory, data: bytes) -> None:
    tmp = tmp_path_factory.mktemp("verbs")
    _run(["check", "--format", "json"], tmp, data, "x.json")
    _run(["decompile", "-o", str(tmp / "out.script")], tmp, data, "x.json")


@FAST
@given(text=scripts())
def test_compile_of_generated_scripts(tmp_path_factory, text: str) -> None:
    tmp = tmp_path_factory.mktemp("gen")
    _run(["compile", "-o", str(tmp / "out.json")], tmp, text.encode(), "g.script")
