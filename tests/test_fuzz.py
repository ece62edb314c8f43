"""The fuzz campaign's short run in the suite: every entry point over mutated real examples,
with its laws (tests/fuzzing.py says which). Hypothesis draws the mutations, so a failure
shrinks to a small input and replays; bench/fuzz.py runs the long campaign.

The large payloads are scaled down here (a 50 KB line, not 1 MB; 10,000 nested brackets
stay) to keep the suite's share to a few seconds; the campaign runs them at full size. The
classes the campaign found each have a regression case of their own beside the code they
broke (listed in REGRESSIONS, so that each is known to exist)."""

from __future__ import annotations

import fuzzing
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

SCALE = 0.05
EXAMPLES_PER_ENTRY = 30


@st.composite
def mutated(draw, kind: str) -> tuple[str, bytes]:
    name, seed = draw(st.sampled_from(fuzzing.SEEDS[kind]))
    return name, fuzzing.mutate(seed, lambda lo, hi: draw(st.integers(lo, hi)), SCALE)


@pytest.mark.slow
@pytest.mark.parametrize("entry", sorted(fuzzing.ENTRIES))
def test_every_entry_point_holds_its_laws_on_mutated_examples(entry: str) -> None:
    @settings(max_examples=EXAMPLES_PER_ENTRY, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(mutated(fuzzing.ENTRIES[entry].kind))
    def holds(case: tuple[str, bytes]) -> None:
        name, data = case
        fuzzing.drive(entry, name, data)

    holds()


@pytest.mark.parametrize("entry", sorted(fuzzing.ENTRIES))
def test_the_unmutated_examples_hold_the_laws(entry: str) -> None:
    """The seeds themselves: the laws are not vacuous (the examples compile, run, format)."""
    for name, data in fuzzing.SEEDS[fuzzing.ENTRIES[entry].kind]:
        fuzzing.drive(entry, name, data)


def test_the_seeds_pass_so_the_laws_are_exercised() -> None:
    from scriptc.analysis.analyze import analyze_bytes

    assert all(analyze_bytes(n, d, "script").ok for n, d in fuzzing.SEEDS["script"])
    assert all(analyze_bytes(n, d, "json").ok for n, d in fuzzing.SEEDS["json"])
    assert len(fuzzing.SEEDS["scenario"]) >= 3 and len(fuzzing.SEEDS["config"]) >= 1


def test_every_mutation_changes_or_keeps_bytes_deterministically() -> None:
    """Each mutation is a function of the bytes and the picks: the same picks, the same
    input, so a failure of the campaign replays from its seed."""
    import random

    data = fuzzing.SEEDS["script"][0][1]
    for name, mutation in fuzzing.MUTATIONS.items():
        a = mutation(data, random.Random(7).randint, SCALE)
        b = mutation(data, random.Random(7).randint, SCALE)
        assert a == b, name
        assert isinstance(a, bytes)
    long = fuzzing.MUTATIONS["long-line"](b"[a]", lambda lo, hi: lo, 1.0)
    assert len(long) > 1_000_000
    nested = fuzzing.MUTATIONS["nested"](b"", lambda lo, hi: hi, 1.0)
    assert nested.count(b")") == 10_000


def test_a_broken_law_and_a_crash_are_classified() -> None:
    assert fuzzing.classify("fmt", fuzzing.LawBroken("fmt: formatting is idempotent", "x")) \
        == "fmt: formatting is idempotent"
    try:
        from scriptc.numbers import whole_number

        whole_number("x")
    except ValueError as exc:
        assert (fuzzing.classify("lint", exc)
                == "lint: crash ValueError at scriptc/numbers.py:whole_number")


# Each class the campaign found (issue 12 and since), and the test that keeps it fixed.
REGRESSIONS = {
    "render: a long line between two annotated lines":
        "test_render.py::test_text_snapshot[gap_long_line]",
    "numbers: huge and non-finite JSON numbers": "test_json_pos.py::test_errors",
    "numbers: scenarios": "test_runtime.py::test_numbers_and_depths_a_scenario_refuses",
    "numbers: script numbers": "cases/checks/huge_numbers.script",
    "numbers: configuration": "cases/config/non_finite_numbers.toml",
    "names: configuration and run time":
        "test_language.py::test_a_function_name_the_configuration_accepts_runs",
    "names: check and decompile": "cases/json/read/reserved_activity_name.json",
    "slow: a million open brackets":
        "test_bad_input.py::test_the_scanner_keeps_no_more_diagnostics_than_are_shown",
    "config: nested too deep": "cases/config/too_deep.toml",
    "check: 5,000-digit goal, action and block numbers": "cases/json/shape/huge_indexes.json",
    "compile: hang, a megabyte of blanks in an audio path":
        "test_bad_input.py::test_a_megabyte_of_blanks_in_an_audio_path_is_linear",
    "fmt: hang, a megabyte of blanks before a syntax error":
        "test_bad_input.py::test_a_megabyte_of_blanks_before_a_syntax_error_is_linear",
    "editor: hang, completion in a megabyte word":
        "test_bad_input.py::test_completion_in_a_megabyte_word_is_linear",
    "fmt: crash, a time of a million leading zeros": "cases/checks/leading_zeros.script",
    "run: an override's goal of thousands of digits": "cases/runtime/override_huge_numbers.script",
}


def test_every_class_has_its_regression_case() -> None:
    from pathlib import Path

    here = Path(__file__).parent
    for cls, where in REGRESSIONS.items():
        path, _, name = where.partition("::")
        assert (here / path).exists(), cls
        if name:
            assert f"def {name.split('[')[0]}(" in (here / path).read_text(encoding="utf-8"), cls
