"""The session summary for the therapist (views/summary.py) on the runs of the examples, in
English and Italian, as text and Markdown: the goals listed with their times, the child's
responses that changed the course, the end; never a code, a file, a block's path or a
condition's text. The summaries of the runtime cases are case files (harness/summary.py)."""

from __future__ import annotations

import inspect
import json
import re
from pathlib import Path

import pytest

from scriptc.analysis.analyze import analyze_file
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import Scenario, load_scenario
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.views.summary import condition_words, duration, summarize, words

ROOT = Path(__file__).parent.parent
EXAMPLES = ROOT / "examples"
ACTIVITIES = ("greeting", "joint_attention", "imitation", "turn_taking", "reward_dance",
              "approach")
FORMS = [("en", False), ("en", True), ("it", False), ("it", True)]
# What must never reach a therapist: a block's path, a file, a code, JSON or a condition.
LEAKS = re.compile(r"goal\d+/|/act\d|blk\d|\.script|\.json|\b[A-Z]\d{3}\b|[{}`]|\?THIS|#Human|"
                   r"OP[<>=]|Traceback")


def run_example(name: str, scenario: Scenario | None = None) -> list[dict]:
    """An example run as `scriptc run` runs it (the governor on), on the kinematic robot."""
    shown = f"examples/{name}.script"
    analysis = analyze_file(EXAMPLES / f"{name}.script", name=shown)
    assert analysis.script is not None
    trace = Trace()
    if scenario is None:
        scenario = load_scenario(str(EXAMPLES / f"{name}.world.json"))
    Session([IRProgram(analysis.script, shown)], robot="kinematic", trace=trace,
            scenario=scenario, profile=DEFAULT_PROFILE).run(3_600_000)
    return trace.events


@pytest.fixture(scope="module")
def runs() -> dict[str, list[dict]]:
    return {name: run_example(name) for name in ACTIVITIES}


@pytest.mark.parametrize(("lang", "markdown"), FORMS)
@pytest.mark.parametrize("name", ACTIVITIES)
def test_every_goal_reached_is_listed_at_its_time(runs, name: str, lang: str,
                                                  markdown: bool) -> None:
    events = runs[name]
    text = summarize(events, lang=lang, markdown=markdown)
    reached = [(e["goalid"], e["t"]) for e in events
               if e["event"] == "goal" and e["record"] == "reached"]
    assert reached
    template = "{goal}: reached at {time}" if lang == "en" else \
        "{goal}: obiettivo raggiunto a {time}"
    for goal, t in reached:
        goal_words = words(goal).replace("_", "\\_") if markdown else words(goal)
        assert template.format(goal=goal_words, time=duration(t, lang)) in text, (goal, text)
    assert not LEAKS.search(text), LEAKS.search(text)
    end = events[-1]
    overview = text.split("\n\n")[1]
    assert duration(end["time_ms"], lang) in overview


@pytest.mark.parametrize(("lang", "markdown"), FORMS)
def test_the_layout_of_each_form(runs, lang: str, markdown: bool) -> None:
    text = summarize(runs["greeting"], lang=lang, markdown=markdown)
    title = "Session summary" if lang == "en" else "Riepilogo della sessione"
    if markdown:
        assert text.startswith(f"# {title}\n\n")
        assert "\n## " in text
    else:
        assert text.startswith(f"{title}\n{'=' * len(title)}\n\n")
        assert "#" not in text
    assert text.endswith(".\n") and "\n\n\n" not in text


def test_greeting_tells_when_the_child_came_and_where_the_robot_went(runs) -> None:
    text = summarize(runs["greeting"])
    assert ("- At 3 s the child came within 1.5 m of the robot, so the robot went on to "
            "“child greeted”.") in text
    assert "- greeting: from 0 s to 6 s (6 s); it reached its end." in text
    assert "The session ended normally at 6 s" in text
    italian = summarize(runs["greeting"], lang="it")
    assert ("- A 3 s il bambino è arrivato a meno di 1,5 m dal robot, quindi il robot è "
            "passato a “child greeted”.") in italian
    assert "- child greeted: obiettivo raggiunto a 5 s" in italian
    assert "La sessione si è conclusa regolarmente a 6 s" in italian


def test_a_waiting_loop_is_told_once_when_its_answer_changes(runs) -> None:
    """Approach asks `positionrho < 1.0` nine times before the child is that close: one line,
    at the time it turned true."""
    text = summarize(runs["approach"])
    lines = [line for line in text.splitlines() if "within 1 m" in line]
    assert lines == [("- At 7.2 s the child came within 1 m of the robot, so the robot went on "
                      "to “child came closer”.")]
    assert "The robot ended 0.9 m from where it started." in text


def test_a_single_check_that_fails_is_told(runs) -> None:
    """Imitation checks once whether the child copied the move, and shows it again when not."""
    text = summarize(runs["imitation"])
    assert ("- At 5 s the child did not respond as the activity expected, so the robot went "
            "on to “demo2”.") in text
    assert ("- At 10 s the child moved and came within 2 m of the robot, so the robot went on "
            "to “movement copied”.") in text


def test_nobody_coming_is_the_time_to_wait_running_out() -> None:
    events = run_example("greeting", Scenario())
    text = summarize(events)
    assert "the time to wait ran out, so the robot went on to “session closed”." in text
    assert "child greeted: reached" not in text
    italian = summarize(events, lang="it", markdown=True)
    assert "è scaduto il tempo di attesa, quindi il robot è passato a “session closed”" in italian
    assert "Nessuna risposta del bambino" not in italian


def test_operator_safety_problems_and_the_end_in_words() -> None:
    events = [
        {"t": 0, "event": "session_start", "scripts": ["a_b"], "robot": "mujoco", "until": None,
         "scenario": None, "profile": {"max_linear_speed": 0.5}},
        {"t": 0, "event": "script_load", "script": "a_b", "path": "x/a_b.script",
         "reason": "queue"},
        {"t": 500, "event": "operator", "command": "safety_lock", "held": True},
        {"t": 700, "event": "operator", "command": "drive", "v_x": 0.2, "v_y": 0.0,
         "v_theta": 0.0, "duration": 1500},
        {"t": 800, "event": "governor", "reasons": ["human-distance"]},
        {"t": 900, "event": "governor", "reasons": ["human-distance", "speed"]},
        {"t": 1000, "event": "error", "code": "function", "message": "`f` at goal0/act0/blk1",
         "fatal": False},
        {"t": 1200, "event": "goal", "script": "a_b", "goalid": "the_goal",
         "record": "interrupted"},
        {"t": 1200, "event": "session_end", "outcome": "interrupted", "time_ms": 1200,
         "pose": {"x": 0.3, "y": 0.4, "theta": 0.0}},
    ]
    text = summarize(events)
    assert "- At 0.5 s the operator held the safety lock." in text
    assert "- At 0.7 s the operator drove the robot by hand for 1.5 s." in text
    assert ("- 2 times, to keep the robot from coming too close to a person (first at 0.8 s)."
            in text)
    assert "- Once, to keep the robot within its speed limit (at 0.9 s)." in text
    assert ("- Once: a check of the activity could not be made (at 1 s); the session went on."
            in text)
    assert "- the goal: interrupted at 1.2 s, not reached" in text
    assert "- a b: from 0 s (1.2 s until the session ended); it was still running." in text
    assert ("The session was stopped early, at 1.2 s, by the person running it. The robot "
            "ended 0.5 m from where it started.") in text
    assert not LEAKS.search(text)
    italian = summarize(events, lang="it")
    assert "- 2 volte, per impedire al robot di avvicinarsi troppo a una persona" in italian
    assert "A 0,5 s l'operatore ha premuto il blocco di sicurezza." in italian


def test_names_are_escaped_in_markdown() -> None:
    events = [{"t": 0, "event": "script_load", "script": "a*b", "path": "p", "reason": "queue"},
              {"t": 10, "event": "goal", "script": "a*b", "goalid": "x_[y]", "record": "reached"}]
    text = summarize(events, markdown=True)
    assert "- a\\*b: from 0 s" in text and "- x \\[y\\]: reached at 0 s" in text
    assert "The record of the session is incomplete: it has no end." in text


def test_the_interface_the_report_verb_calls() -> None:
    parameters = inspect.signature(summarize).parameters
    assert list(parameters) == ["events", "lang", "markdown"]
    assert parameters["lang"].kind is inspect.Parameter.KEYWORD_ONLY
    assert parameters["lang"].default == "en" and parameters["markdown"].default is False
    with pytest.raises(ValueError, match="languages are en, it"):
        summarize([], lang="fr")


@pytest.mark.parametrize("events", [
    [], [{}], [{"t": "x", "event": 3}], [{"t": 0, "event": "jump", "condition": 4}],
    [{"t": 0, "event": "jump", "condition": "{CLASS #Human U ?k (B: near(x))} ! {TRUE}",
      "value": True, "target": 5, "bindings": []}],
    [{"t": 0, "event": "governor", "reasons": "speed"}, {"t": 1, "event": "operator"},
     {"t": 2, "event": "session_end", "pose": {"x": "a"}}, {"t": 3, "event": "error"}],
])
def test_a_strange_trace_never_raises(events) -> None:
    for lang, markdown in FORMS:
        assert summarize(events, lang=lang, markdown=markdown).endswith("\n")


def test_conditions_in_words() -> None:
    near = '{CLASS #Object T ?ball (?THIS>&category OP= "ball", B: near(0.6))} ! {TRUE}'
    assert condition_words(near, True) == "the “ball” came within 0.6 m of the robot"
    assert condition_words(near, False) == "the “ball” was not within 0.6 m of the robot"
    assert condition_words(near, True, "it") == ("l'oggetto “ball” è arrivato a meno di 0,6 m "
                                                 "dal robot")
    away = "{CLASS #Human U ?kid (?THIS>&positionrho OP> 2.0)} ! {TRUE}"
    assert condition_words(away, True, names={"?kid": "kid2"}) == (
        "the child (kid2) moved more than 2 m away")
    moved = ("{CLASS #Object T ?ball (?THIS>&category OP= \"ball\", B: near(0.6))} ! "
             "{E: gt(?ball>&positionchangetime, @pushed)}")
    assert condition_words(moved, True, "it") == ("l'oggetto “ball” si è mosso ed è arrivato a "
                                                  "meno di 0,6 m dal robot")


def test_times_in_words() -> None:
    assert [duration(ms) for ms in (0, 1500, 12_345, 60_000, 125_000, 3_720_000)] == [
        "0 s", "1.5 s", "12.3 s", "1 min", "2 min 5 s", "1 h 2 min"]
    assert duration(12_500, "it") == "12,5 s"
    assert words("child_greeted") == "child greeted"


def test_the_examples_trace_files_read_back_give_the_same_summary(runs, tmp_path) -> None:
    """What `scriptc report TRACE --summary` reads: the JSON lines of the trace."""
    events = runs["turn_taking"]
    path = tmp_path / "t.jsonl"
    path.write_text("".join(json.dumps(e) + "\n" for e in events), encoding="utf-8")
    again = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]
    assert summarize(again, lang="it") == summarize(events, lang="it")
