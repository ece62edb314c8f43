"""The session summary for the therapist (`summarize`; `scriptc report TRACE --summary`,
docs/views.md "The session summary"): what happened in a run, in plain words, from its trace.

It tells the activities that ran and for how long, the goals (their ids turned into words:
`child_greeted` -> "child greeted") reached or not and when, each time the child's response
changed the course of an activity, the operator's interventions, the safety limits that stepped
in, the technical problems and how the session ended; in English or Italian (`lang`), as plain
text or Markdown. It never shows a diagnostic code, a file, a block's path or a condition's
text: what a jump's condition reads is said in words (`condition_words`).

**Which jumps changed the course (decided).** A jump whose condition reads the world (a person,
an object, an obstacle: `#Human`, `#Object`, `#Obstacle`) is the child's response. A waiting
loop asks the same jump again and again, and only its change says something: a jump is told
when its outcome differs from the previous time the same jump (script and block) was read; the
first time it is read, when it is true (the child was already there), or when it is read only
once (a single check of the response, true or false). A jump that reads only the activity's
clock (`elapsedtime`) is told when it turns true: the time to wait ran out. Where the robot
went is the goal the jump leads into when it leaves its goal (the goal's id in words), else the
label of the block the robot went on to.

Events are read as `runtime/trace.py` writes them, but a trace is a file from outside: a field
that is missing or of another type is read as absent, never an exception.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from scriptc.runtime.trace import Event

LANGUAGES = ("en", "it")

# The activity the runtime runs between the scripts (docs/runtime.md): not one of the session's.
_IDLE = "idle_activity"
# At most this many lines of one kind (responses, the operator) are listed; the rest counted.
MOST_LINES = 30

_WORDS: dict[str, dict[str, str]] = {
    "en": {
        "title": "Session summary",
        "overview": "The session lasted {duration} of simulated time: {activities}, {goals}.",
        "activity_count": "{n} activities", "activity_one": "one activity",
        "goal_count": "{n} goals reached", "goal_one": "one goal reached",
        "goal_none": "no goal reached",
        "activities": "Activities",
        "activity": "{name}: from {start} to {end} ({duration}); {how}.",
        "activity_open": "{name}: from {start} ({duration} until the session ended); it was "
                         "still running.",
        "by_rule": " A rule of the activities switched to it.",
        "unload_terminus": "it reached its end", "unload_past_end": "it reached its end",
        "unload_override": "it was replaced by another activity",
        "unload_idle_escape": "it gave way to the next activity",
        "unload_restart": "it was started again",
        "no_activity": "No activity ran.",
        "goals": "Goals",
        "goal_reached": "{goal}: reached at {time}",
        "goal_interrupted": "{goal}: interrupted at {time}, not reached",
        "goal_failed": "{goal}: not achieved (failed) at {time}",
        "in_activity": " ({activity})",
        "no_goal": "No goal was recorded.",
        "responses": "The child's responses",
        "response": "At {time} {what}, so {where}.",
        "timeout": "At {time} the time to wait ran out, so {where}.",
        "no_response": "Nothing the child did changed the course of the activities.",
        "went_goal": "the robot went on to “{goal}”",
        "went_label": "the robot went on to “{label}”",
        "went_step": "the robot went on to its next step",
        "went_end": "the activity ended",
        "child": "the child", "child_named": "the child ({name})",
        "object": "the “{category}”", "object_plain": "an object",
        "obstacle": "an obstacle",
        "within": "{subject} came within {d} m of the robot",
        "not_within": "{subject} was not within {d} m of the robot",
        "beyond": "{subject} moved more than {d} m away",
        "not_beyond": "{subject} stayed within {d} m",
        "moved": "{subject} moved", "not_moved": "{subject} did not move",
        "responded": "{subject} responded as the activity expected",
        "not_responded": "{subject} did not respond as the activity expected",
        "and": " and ",
        "operator": "The operator",
        "no_operator": "The operator did not intervene.",
        "lock_on": "At {time} the operator held the safety lock.",
        "lock_off": "At {time} the operator let go of the safety lock.",
        "drive": "At {time} the operator drove the robot by hand{duration}.",
        "drive_for": " for {duration}",
        "drive_stop": "At {time} the operator stopped the robot's wheels.",
        "pause": "At {time} the operator paused the activity.",
        "resume": "At {time} the operator resumed the activity.",
        "toggle": "At {time} the operator pressed the pause button.",
        "ignored": " Nothing happened: the safety lock was not held.",
        "more": "… and {n} more.",
        "safety": "Safety",
        "no_profile": "The session ran without the safety limits.",
        "no_clamp": "The safety limits never had to step in.",
        "clamps": "The safety limits stepped in:",
        "times_one": "once", "times": "{n} times",
        "clamp": "{times}, to {what} ({first}).",
        "first": "first at {time}", "only": "at {time}",
        "speed": "keep the robot within its speed limit",
        "angular-speed": "keep its turning within its limit",
        "human-distance": "keep the robot from coming too close to a person",
        "acceleration": "make it start and stop more gently",
        "angular-acceleration": "make it start and stop turning more gently",
        "led-flash": "keep its lights from flashing too fast",
        "problems": "Technical problems",
        "problem": "{times}: {what} ({first}); {after}.",
        "went_on": "the session went on", "stopped_here": "the session stopped there",
        "mutex-misuse": "a rule of the activity was used the wrong way",
        "unknown-rulecode": "the activity asked for a rule the robot does not have",
        "rule": "a rule of the activity did not work",
        "function": "a check of the activity could not be made",
        "override": "a switch to another activity could not be made",
        "script_vect": "an activity to run next could not be found",
        "update": "a change to what the robot knows was refused",
        "no-progress": "the activity went round in circles without time passing",
        "read": "the robot could not read the activity any further",
        "robot-unstable": "the robot's simulated physics failed",
        "problem_other": "a technical problem",
        "ending": "How it ended",
        "end_completed": "The session ended normally at {time}: every activity finished.",
        "end_until": "The session was stopped at its time limit, at {time}.",
        "end_stalled": "The session stopped at {time} because nothing more could happen: "
                       "the robot was waiting for something that could not come.",
        "end_error": "A problem stopped the session at {time}.",
        "end_interrupted": "The session was stopped early, at {time}, by the person running "
                           "it.",
        "end_missing": "The record of the session is incomplete: it has no end.",
        "rest_after": " The robot came to rest at {time}.",
        "moved_from_start": " The robot ended {d} m from where it started.",
        "at_start": " The robot ended where it started.",
    },
    "it": {
        "title": "Riepilogo della sessione",
        "overview": "La sessione è durata {duration} di tempo simulato: {activities}, {goals}.",
        "activity_count": "{n} attività", "activity_one": "un'attività",
        "goal_count": "{n} obiettivi raggiunti", "goal_one": "un obiettivo raggiunto",
        "goal_none": "nessun obiettivo raggiunto",
        "activities": "Attività",
        "activity": "{name}: da {start} a {end} ({duration}); {how}.",
        "activity_open": "{name}: da {start} ({duration} fino alla fine della sessione); era "
                         "ancora in corso.",
        "by_rule": " Una regola delle attività è passata a questa.",
        "unload_terminus": "è arrivata alla fine", "unload_past_end": "è arrivata alla fine",
        "unload_override": "è stata sostituita da un'altra attività",
        "unload_idle_escape": "ha lasciato il posto all'attività successiva",
        "unload_restart": "è stata ricominciata",
        "no_activity": "Nessuna attività è stata eseguita.",
        "goals": "Obiettivi",
        "goal_reached": "{goal}: obiettivo raggiunto a {time}",
        "goal_interrupted": "{goal}: interrotto a {time}, non raggiunto",
        "goal_failed": "{goal}: non raggiunto (fallito) a {time}",
        "in_activity": " ({activity})",
        "no_goal": "Nessun obiettivo è stato registrato.",
        "responses": "Le risposte del bambino",
        "response": "A {time} {what}, quindi {where}.",
        "timeout": "A {time} è scaduto il tempo di attesa, quindi {where}.",
        "no_response": "Nessuna risposta del bambino ha cambiato il corso delle attività.",
        "went_goal": "il robot è passato a “{goal}”",
        "went_label": "il robot è passato a “{label}”",
        "went_step": "il robot è passato al passo successivo",
        "went_end": "l'attività è finita",
        "child": "il bambino", "child_named": "il bambino ({name})",
        "object": "l'oggetto “{category}”", "object_plain": "un oggetto",
        "obstacle": "un ostacolo",
        "within": "{subject} è arrivato a meno di {d} m dal robot",
        "not_within": "{subject} non era a meno di {d} m dal robot",
        "beyond": "{subject} si è allontanato oltre {d} m",
        "not_beyond": "{subject} è rimasto entro {d} m",
        "moved": "{subject} si è mosso", "not_moved": "{subject} non si è mosso",
        "responded": "{subject} ha risposto come l'attività si aspettava",
        "not_responded": "{subject} non ha risposto come l'attività si aspettava",
        "and": " e ",
        "operator": "L'operatore",
        "no_operator": "L'operatore non è intervenuto.",
        "lock_on": "A {time} l'operatore ha premuto il blocco di sicurezza.",
        "lock_off": "A {time} l'operatore ha rilasciato il blocco di sicurezza.",
        "drive": "A {time} l'operatore ha guidato il robot a mano{duration}.",
        "drive_for": " per {duration}",
        "drive_stop": "A {time} l'operatore ha fermato le ruote del robot.",
        "pause": "A {time} l'operatore ha messo in pausa l'attività.",
        "resume": "A {time} l'operatore ha ripreso l'attività.",
        "toggle": "A {time} l'operatore ha premuto il pulsante di pausa.",
        "ignored": " Non è successo nulla: il blocco di sicurezza non era premuto.",
        "more": "… e altri {n}.",
        "safety": "Sicurezza",
        "no_profile": "La sessione si è svolta senza i limiti di sicurezza.",
        "no_clamp": "I limiti di sicurezza non sono mai dovuti intervenire.",
        "clamps": "I limiti di sicurezza sono intervenuti:",
        "times_one": "una volta", "times": "{n} volte",
        "clamp": "{times}, per {what} ({first}).",
        "first": "la prima a {time}", "only": "a {time}",
        "speed": "tenere il robot entro il limite di velocità",
        "angular-speed": "tenere la rotazione entro il suo limite",
        "human-distance": "impedire al robot di avvicinarsi troppo a una persona",
        "acceleration": "rendere più dolci partenze e frenate",
        "angular-acceleration": "rendere più dolci l'inizio e la fine delle rotazioni",
        "led-flash": "impedire alle luci di lampeggiare troppo in fretta",
        "problems": "Problemi tecnici",
        "problem": "{times}: {what} ({first}); {after}.",
        "went_on": "la sessione è proseguita", "stopped_here": "la sessione si è fermata lì",
        "mutex-misuse": "una regola dell'attività è stata usata nel modo sbagliato",
        "unknown-rulecode": "l'attività ha chiesto una regola che il robot non ha",
        "rule": "una regola dell'attività non ha funzionato",
        "function": "un controllo dell'attività non è stato possibile",
        "override": "il passaggio a un'altra attività non è stato possibile",
        "script_vect": "non è stata trovata un'attività da eseguire dopo",
        "update": "un aggiornamento di ciò che il robot sa è stato rifiutato",
        "no-progress": "l'attività girava a vuoto senza che il tempo passasse",
        "read": "il robot non ha potuto proseguire la lettura dell'attività",
        "robot-unstable": "la simulazione fisica del robot non ha funzionato",
        "problem_other": "un problema tecnico",
        "ending": "Com'è finita",
        "end_completed": "La sessione si è conclusa regolarmente a {time}: tutte le attività "
                         "sono terminate.",
        "end_until": "La sessione è stata fermata al limite di tempo previsto, a {time}.",
        "end_stalled": "La sessione si è fermata a {time} perché non poteva succedere più "
                       "nulla: il robot aspettava qualcosa che non poteva arrivare.",
        "end_error": "Un problema ha fermato la sessione a {time}.",
        "end_interrupted": "La sessione è stata interrotta in anticipo, a {time}, da chi la "
                           "conduceva.",
        "end_missing": "La registrazione della sessione è incompleta: manca la fine.",
        "rest_after": " Il robot si è fermato del tutto a {time}.",
        "moved_from_start": " Il robot ha finito a {d} m dal punto di partenza.",
        "at_start": " Il robot ha finito nel punto di partenza.",
    },
}

_CLASS_GROUP = re.compile(r"\{CLASS #(\w+) [A-Z]+ (\?\w+) \((.*?)\)\}")
_TEST_DISTANCE = re.compile(r"\?THIS>&positionrho OP([<>])=? ?(-?[0-9.]+)")
_TEST_NEAR = re.compile(r"\bnear\((-?[0-9.]+)\)")
_TEST_CATEGORY = re.compile(r'\?THIS>&category OP= ?"((?:[^"\\]|\\.)*)"')
_WORLD = ("Human", "Object", "Obstacle")
# The governor's reasons and the run-time codes the summary has words for.
_REASONS = ("speed", "angular-speed", "human-distance", "acceleration", "angular-acceleration",
            "led-flash")
_PROBLEMS = ("mutex-misuse", "unknown-rulecode", "rule", "function", "override", "script_vect",
             "update", "no-progress", "read", "robot-unstable")


def _int(value: object) -> int | None:
    return value if isinstance(value, int) and not isinstance(value, bool) else None


def _text(value: object) -> str:
    return value if isinstance(value, str) else ""


def _number(value: float, lang: str) -> str:
    """A number as the language writes it: `1.5`, `1,5`."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return text.replace(".", ",") if lang == "it" else text


def duration(ms: int, lang: str = "en") -> str:
    """A time in words: `12.5 s`, `2 min 5 s`, `1 h 2 min` (`12,5 s` in Italian)."""
    if ms < 60_000:
        return f"{_number(round(ms / 1000, 1), lang)} s"
    seconds = round(ms / 1000)
    if seconds < 3600:
        minutes, rest = divmod(seconds, 60)
        return f"{minutes} min" + (f" {rest} s" if rest else "")
    hours, rest = divmod(seconds // 60, 60)
    return f"{hours} h" + (f" {rest} min" if rest else "")


def words(identifier: str) -> str:
    """An id as words: `child_greeted` -> `child greeted`, `firstRound` stays."""
    return " ".join(identifier.replace("_", " ").replace("-", " ").split())


def _goal_index(path: str) -> int | None:
    head = path.partition("/")[0]
    return int(head[4:]) if head.startswith("goal") and head[4:].isdigit() else None


@dataclass
class _Subject:
    """What one CLASS assignment of a condition looks for: its class, the facts it tests."""

    cls: str
    alias: str
    category: str = ""
    within: float | None = None
    beyond: float | None = None
    moved: bool = False
    other: bool = False


def _subjects(condition: str) -> list[_Subject]:
    found: list[_Subject] = []
    for match in _CLASS_GROUP.finditer(condition):
        cls, alias, tests = match.groups()
        if cls not in _WORLD:
            continue
        subject = _Subject(cls, alias)
        category = _TEST_CATEGORY.search(tests)
        if category is not None:
            subject.category = category.group(1)
        for test in _TEST_DISTANCE.finditer(tests):
            if test.group(1) == "<":
                subject.within = float(test.group(2))
            else:
                subject.beyond = float(test.group(2))
        near = _TEST_NEAR.search(tests)
        if near is not None:
            subject.within = float(near.group(1))
        rest = _TEST_CATEGORY.sub("", _TEST_NEAR.sub("", _TEST_DISTANCE.sub("", tests)))
        subject.other = "?THIS" in rest or "(" in rest
        found.append(subject)
    evaluation = condition.rpartition(" ! ")[2]
    for subject in found:
        if f"{subject.alias}>&positionchangetime" in condition:
            subject.moved = True
        elif subject.alias + ">&" in evaluation:
            subject.other = True
    return found


def reads_the_world(condition: str) -> bool:
    """Whether a jump's condition looks at a person, an object or an obstacle."""
    return any(f"#{cls} " in condition for cls in _WORLD)


def _clock_only(condition: str) -> bool:
    return "elapsedtime" in condition and not reads_the_world(condition)


def _subject_words(subject: _Subject, words_: dict[str, str], name: str) -> str:
    if subject.cls == "Human":
        return words_["child_named"].format(name=name) if name else words_["child"]
    if subject.cls == "Object":
        return (words_["object"].format(category=subject.category) if subject.category
                else words_["object_plain"])
    return words_["obstacle"]


def _join(parts: list[str], lang: str) -> str:
    out = parts[0]
    for part in parts[1:]:
        glue = _WORDS[lang]["and"]
        if lang == "it" and part.startswith("è"):
            glue = " ed "
        out += glue + part
    return out


def condition_words(condition: str, value: bool, lang: str = "en",
                    names: dict[str, str] | None = None) -> str:
    """What a jump's condition found in the world, in words: what was true (`value` true), or
    what was not. `names`: the entity each alias was bound to, shown for a person when several
    children are in the session (`?kid` -> `kid1`)."""
    w = _WORDS[lang]
    subjects = _subjects(condition)
    if not subjects:
        key = "responded" if value else "not_responded"
        return w[key].format(subject=w["child"])

    def subject_of(s: _Subject) -> str:
        return _subject_words(s, w, (names or {}).get(s.alias, ""))

    if not value:
        # What failed is not known from the trace, unless there was one thing to fail.
        testing = [s for s in subjects if s.within is not None or s.beyond is not None
                   or s.moved or s.other]
        if len(testing) == 1 and sum(x is not None and x is not False for x in (
                testing[0].within, testing[0].beyond, testing[0].moved or None,
                testing[0].other or None)) == 1:
            s = testing[0]
            if s.within is not None:
                return w["not_within"].format(subject=subject_of(s), d=_number(s.within, lang))
            if s.beyond is not None:
                return w["not_beyond"].format(subject=subject_of(s), d=_number(s.beyond, lang))
            if s.moved:
                return w["not_moved"].format(subject=subject_of(s))
        person = next((s for s in subjects if s.cls == "Human"), subjects[0])
        return w["not_responded"].format(subject=subject_of(person))
    sentences = []
    for s in subjects:
        subject = subject_of(s)
        facts = []
        if s.moved:
            facts.append(w["moved"])
        if s.within is not None:
            facts.append(w["within"].replace("{d}", _number(s.within, lang)))
        if s.beyond is not None:
            facts.append(w["beyond"].replace("{d}", _number(s.beyond, lang)))
        if s.other and not facts and s.cls == "Human":
            facts.append(w["responded"])
        if not facts:
            continue
        # the subject once, then each fact without it: "the ball moved and came within ..."
        rest = [f.replace("{subject} ", "", 1) for f in facts]
        sentences.append(f"{subject} {_join(rest, lang)}")
    if not sentences:
        person = next((s for s in subjects if s.cls == "Human"), subjects[0])
        return w["responded"].format(subject=subject_of(person))
    return _join(sentences, lang)


def _escape(text: str, markdown: bool) -> str:
    return re.sub(r"([\\`*_\[\]<>#|])", r"\\\1", text) if markdown else text


class _Writer:
    def __init__(self, markdown: bool) -> None:
        self.markdown = markdown
        self.lines: list[str] = []

    def title(self, text: str) -> None:
        if self.markdown:
            self.lines += [f"# {text}", ""]
        else:
            self.lines += [text, "=" * len(text), ""]

    def heading(self, text: str) -> None:
        if self.markdown:
            self.lines += [f"## {text}", ""]
        else:
            self.lines += [text, "-" * len(text), ""]

    def paragraph(self, text: str) -> None:
        self.lines += [text, ""]

    def items(self, texts: list[str], more: str | None = None) -> None:
        self.lines += [f"- {text}" for text in texts]
        if more:
            self.lines.append(f"- {more}")
        self.lines.append("")

    def text(self) -> str:
        return "\n".join(self.lines).rstrip("\n") + "\n"


@dataclass
class _Load:
    script: str
    start: int
    reason: str
    end: int | None = None
    how: str = ""


def summarize(events: list[dict], *, lang: str = "en",  # type: ignore[type-arg]  # trace events
              markdown: bool = False) -> str:
    """The summary of a run for the therapist, in plain words, from its trace's events: in
    English (`lang="en"`) or Italian (`"it"`), as plain text or Markdown. ValueError for a
    language it does not speak."""
    if lang not in _WORDS:
        raise ValueError(f"no summary in `{lang}`: the languages are {', '.join(LANGUAGES)}")
    w = _WORDS[lang]
    md = markdown
    good: list[Event] = [e for e in events if isinstance(e, dict) and _int(e.get("t")) is not None
                         and isinstance(e.get("event"), str)]

    def when(t: int) -> str:
        return duration(t, lang)

    def name(text: str) -> str:
        return _escape(words(text), md)

    end_event = next((e for e in reversed(good) if e["event"] == "session_end"), None)
    end_t = (_int(end_event.get("time_ms")) if end_event is not None else None)
    if end_t is None:
        end_t = max((e["t"] for e in good), default=0)

    # -- the activities and the goals ----------------------------------------------------------
    loads: list[_Load] = []
    open_loads: dict[str, _Load] = {}
    goal_ids: dict[tuple[str, int], str] = {}
    where: dict[str, int] = {}
    goals: list[tuple[int, str, str, str]] = []  # (t, script, goal id, record)
    for e in good:
        kind, script = e["event"], _text(e.get("script"))
        goal = _goal_index(_text(e.get("path"))) if kind != "script_load" else None
        if goal is not None and script:
            where[script] = goal
        if kind == "script_load" and script:
            load = _Load(script, e["t"], _text(e.get("reason")))
            open_loads[script] = load
            loads.append(load)
        elif kind == "script_unload" and script in open_loads:
            load = open_loads.pop(script)
            load.end, load.how = e["t"], _text(e.get("reason"))
        elif kind == "goal" and _text(e.get("goalid")):
            goals.append((e["t"], script, _text(e.get("goalid")), _text(e.get("record"))))
            if "by" not in e and script in where:
                goal_ids.setdefault((script, where[script]), _text(e.get("goalid")))
    shown_loads = [load for load in loads if load.script != _IDLE]
    scripts = {load.script for load in shown_loads}
    reached = [g for g in goals if g[3] == "reached"]

    out = _Writer(md)
    out.title(w["title"])
    count = len(shown_loads)
    activities = (w["activity_one"] if count == 1
                  else w["activity_count"].format(n=count))
    goal_count = len(reached)
    goals_text = (w["goal_none"] if goal_count == 0 else w["goal_one"] if goal_count == 1
                  else w["goal_count"].format(n=goal_count))
    out.paragraph(w["overview"].format(duration=when(end_t), activities=activities,
                                       goals=goals_text))

    out.heading(w["activities"])
    lines = []
    for load in shown_loads:
        if load.end is None:
            line = w["activity_open"].format(name=name(load.script), start=when(load.start),
                                             duration=when(max(0, end_t - load.start)))
        else:
            how = w.get(f"unload_{load.how}", w["unload_terminus"])
            line = w["activity"].format(name=name(load.script), start=when(load.start),
                                        end=when(load.end),
                                        duration=when(load.end - load.start), how=how)
        if load.reason == "override":
            line += w["by_rule"]
        lines.append(line)
    if lines:
        out.items(lines)
    else:
        out.paragraph(w["no_activity"])

    out.heading(w["goals"])
    lines = []
    for t, script, goalid, record in goals:
        if script == _IDLE:
            continue
        key = {"reached": "goal_reached", "interrupted": "goal_interrupted"}.get(
            record, "goal_failed")
        line = w[key].format(goal=name(goalid), time=when(t))
        if len(scripts) > 1:
            line += w["in_activity"].format(activity=name(script))
        lines.append(line)
    if lines:
        out.items(lines)
    else:
        out.paragraph(w["no_goal"])

    # -- the child's responses -----------------------------------------------------------------
    out.heading(w["responses"])
    jumps = [e for e in good if e["event"] == "jump" and isinstance(e.get("condition"), str)
             and isinstance(e.get("value"), bool)]
    reads: dict[tuple[str, str], int] = {}
    for e in jumps:
        jump = (_text(e.get("script")), _text(e.get("path")))
        reads[jump] = reads.get(jump, 0) + 1
    humans = {_text(e.get("objectid")) for e in good if e["event"] == "update"
              and _text(e.get("objectid")).startswith("Human/")}
    last: dict[tuple[str, str], bool] = {}
    lines = []
    for i, e in enumerate(good):
        condition, value = e.get("condition"), e.get("value")
        if e["event"] != "jump" or not isinstance(condition, str) or not isinstance(value, bool):
            continue
        jump = (_text(e.get("script")), _text(e.get("path")))
        before = last.get(jump)
        last[jump] = value
        if reads_the_world(condition):
            told = value != before if before is not None else (value or reads[jump] == 1)
        elif _clock_only(condition):
            told = value and before is not True
        else:
            told = False
        if not told:
            continue
        target = e.get("target")
        where_to = _where(good, i, jump[0], jump[1], target, goal_ids, w, md)
        if reads_the_world(condition):
            bound = e.get("bindings")
            bindings: dict[str, object] = bound if isinstance(bound, dict) else {}
            names = ({alias: _escape(_text(v).partition("/")[2], md)
                      for alias, v in bindings.items()} if len(humans) > 1 else {})
            lines.append(w["response"].format(time=when(e["t"]), where=where_to,
                                              what=condition_words(condition, value, lang,
                                                                   names)))
        else:
            lines.append(w["timeout"].format(time=when(e["t"]), where=where_to))
    if lines:
        out.items(lines[:MOST_LINES], w["more"].format(n=len(lines) - MOST_LINES)
                  if len(lines) > MOST_LINES else None)
    else:
        out.paragraph(w["no_response"])

    # -- the operator --------------------------------------------------------------------------
    out.heading(w["operator"])
    lines = [_operator(e, w, lang) for e in good if e["event"] == "operator"]
    if lines:
        out.items(lines[:MOST_LINES], w["more"].format(n=len(lines) - MOST_LINES)
                  if len(lines) > MOST_LINES else None)
    else:
        out.paragraph(w["no_operator"])

    # -- safety --------------------------------------------------------------------------------
    out.heading(w["safety"])
    start = next((e for e in good if e["event"] == "session_start"), None)
    clamps: dict[str, list[int]] = {}
    for e in good:
        if e["event"] == "governor" and isinstance(e.get("reasons"), list):
            for reason in e["reasons"]:
                clamps.setdefault(_text(reason), []).append(e["t"])
    if clamps:
        out.paragraph(w["clamps"])
        out.items([_capital(w["clamp"].format(times=_times(len(ts), w), what=w[reason],
                                              first=_first(ts, w, lang)))
                   for reason, ts in clamps.items() if reason in _REASONS])
    elif start is not None and not isinstance(start.get("profile"), dict):
        out.paragraph(w["no_profile"])
    else:
        out.paragraph(w["no_clamp"])

    # -- problems ------------------------------------------------------------------------------
    problems: dict[tuple[str, bool], list[int]] = {}
    for e in good:
        if e["event"] == "error":
            problems.setdefault((_text(e.get("code")), e.get("fatal") is True), []).append(e["t"])
    if problems:
        out.heading(w["problems"])
        out.items([_capital(w["problem"].format(
            times=_times(len(ts), w), first=_first(ts, w, lang),
            what=w[code] if code in _PROBLEMS else w["problem_other"],
            after=w["stopped_here"] if fatal else w["went_on"]))
            for (code, fatal), ts in problems.items()])

    # -- the end -------------------------------------------------------------------------------
    out.heading(w["ending"])
    if end_event is None:
        out.paragraph(w["end_missing"])
    else:
        outcome = _text(end_event.get("outcome"))
        text = w.get(f"end_{outcome}", w["end_completed"]).format(time=when(end_t))
        rest = _int(end_event.get("at_rest_ms"))
        if rest is not None and rest > end_t:
            text += w["rest_after"].format(time=when(rest))
        pose = end_event.get("pose")
        if isinstance(pose, dict) and all(isinstance(pose.get(k), (int, float))
                                          for k in ("x", "y")):
            moved = math.hypot(pose["x"], pose["y"])
            text += (w["moved_from_start"].format(d=_number(moved, lang)) if moved >= 0.005
                     else w["at_start"])
        out.paragraph(text)
    return out.text()


def _times(n: int, w: dict[str, str]) -> str:
    return w["times_one"] if n == 1 else w["times"].format(n=n)


def _first(times: list[int], w: dict[str, str], lang: str) -> str:
    return w["only" if len(times) == 1 else "first"].format(time=duration(times[0], lang))


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _where(events: Sequence[Event], i: int, script: str, path: str, target: object,
           goal_ids: dict[tuple[str, int], str], w: dict[str, str], md: bool) -> str:
    """Where a jump (the `i`th event) took the robot, in words."""
    if not isinstance(target, str):
        return w["went_end"]
    to_goal, from_goal = _goal_index(target), _goal_index(path)
    if to_goal is not None and to_goal != from_goal and (script, to_goal) in goal_ids:
        return w["went_goal"].format(goal=_escape(words(goal_ids[script, to_goal]), md))
    for e in events[i + 1:]:
        if e["event"] == "block" and _text(e.get("script")) == script:
            label = _text(e.get("label"))
            if label and _text(e.get("path")) == target:
                return w["went_label"].format(label=_escape(words(label), md))
            break
        if e["event"] == "jump" and _text(e.get("script")) == script:
            continue
    return w["went_step"]


def _operator(e: Event, w: dict[str, str], lang: str) -> str:
    time = duration(e["t"], lang)
    command = e.get("command")
    if command == "safety_lock":
        line = w["lock_on" if e.get("held") is True else "lock_off"].format(time=time)
    elif command == "drive":
        speeds = [e.get(k) for k in ("v_x", "v_y", "v_theta")]
        span = _int(e.get("duration"))
        if e.get("ignored") is not True and all(v == 0 for v in speeds):
            line = w["drive_stop"].format(time=time)
        else:
            line = w["drive"].format(time=time, duration=w["drive_for"].format(
                duration=duration(span, lang)) if span else "")
    else:
        on = e.get("on")
        line = w["pause" if on is True else "resume" if on is False else "toggle"].format(
            time=time)
    if e.get("ignored") is True:
        line += w["ignored"]
    return line
