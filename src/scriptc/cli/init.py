"""`scriptc init [DIR]`: scaffold an activity repository.

Writes a configuration (`scriptc.toml`), an example activity (`activities/hello.script`) and
its test (`activities/hello.test.toml`, run by `scriptc test`), a scenario for the simulator
(`scenarios/hello.json`), a folder for audio tracks, a GitHub Actions workflow (lint with
annotations and code scanning, then the tests: `.github/workflows/scriptc.yml`) and a
pre-commit configuration (`.pre-commit-config.yaml`). DIR (default: the working folder) is
created when missing. Existing files are never overwritten: each is named as skipped. The
repository it writes lints clean and its test passes (tests/test_init.py holds that).

The workflow installs the scriptc that runs `init`, as pip recorded where it came from
(`scriptc.project.provenance`): a commit of a repository, a version of a package index. A
scriptc that no other machine can install (a local checkout) gets an install step that fails
saying what to write, and `init` warns about it, rather than a line that installs something
else.

Exit status: 0 done (some files may have been skipped), 2 DIR is not a folder or a file
cannot be written.
"""

from __future__ import annotations

import os
from collections.abc import Callable

import click

from scriptc.cli.common import CliError, write
from scriptc.project.provenance import PLACEHOLDER, Provenance, provenance
from scriptc.robot.limits import toml_section
from scriptc.writing import WriteError, write_file

CONFIG = """\
# The configuration of this activity repository, read by every `scriptc` command run in it
# (scriptc's docs/configuration.md describes each key).

# Audio tracks (`AO("songs/hello.wav, 0, 1000")`) are written relative to this folder.
audio-root = "audio"

[lint]
select = ["ALL"]
ignore = []
# Codes not to report in some files (patterns as in .gitignore):
# per-file-ignores = { "drafts/**" = ["F001"] }
# Warnings that should fail the build:
# severity = { M004 = "error" }

# The robot the activities run on: the limits the safety checks and the governor keep.
# These are scriptc's safe defaults (a key left out keeps its default): write your robot's.
""" + toml_section() + """
# Functions of the rule grammar this repository adds (`B: waving()` in a condition), each
# with the Python object that implements it, imported only when a simulation runs:
# [[functions]]
# name = "waving"
# kind = "B"
# arity = 0
# doc = "True when the candidate Human waves at the robot."
# implementation = "activity_functions:waving"
"""

ACTIVITY = """\
% hello: the robot idles until a child comes within a metre, then greets them with a half
  turn and a green flash, and ends; after 30 s without a child it ends too.
  Lint it with `scriptc lint .`; compile it with `scriptc compile activities/hello.script`;
  `scriptc verify .` proves that it always ends, whatever the child does. %
[hello]
[goal:greet]
  [action]
    [b#idle#blk_inst: MV("0, 0, 0, 0, 500") LD() AO()]
    [b#look#blk_jump: CND({CLASS #Human T ?kid (B: near(1.0))} ! {TRUE}) TRJMP(greet) FLSJMP()]
    [b#wait#blk_jump: CND({CLASS #Activity T ?me (?THIS>&elapsedtime OP> 30000)} ! {TRUE})
                      TRJMP(done) FLSJMP(idle)]
    [b#greet#blk_inst: MV("0, 0, 1.5, 0, 2000")
                       LD("0, 1, 0, 1, 0, 500", "0, 0, 0, 0, 500, 500")
                       AO()]
    [b#done#blk_terminus]
"""

# The example's test (docs/testing.md): what hello.script is for, in the scenario's world.
TEST = """\
# A test of hello.script (scriptc's docs/testing.md): in the scenario a child comes within a
# metre at 0.5 s; the robot must greet them at once with a green flash and a half turn, and
# end. `scriptc test` runs every *.test.toml of the repository, in simulated time.
description = "hello: a child who comes within a metre is greeted with a green flash and a half turn"
scripts = ["hello.script"]
world = "../scenarios/hello.json"
until = 60000

[[expect]]
name = "greets the child as soon as they are near"
event = "block"
where = { label = "greet" }
within = [500, 500]
count = "1"

[[expect]]
name = "a green flash"
at = 750
led = [0.0, 1.0, 0.0]

[[expect]]
name = "a half turn"
at = "end"
pose = { x = 0.0, y = 0.0, theta = 3.0 }

[[expect]]
name = "then it ends"
outcome = "completed"
time = { max = 5000 }
"""  # noqa: E501 - the lines of the file `init` writes, as written

SCENARIO = """\
{
  "description": "A child walks up to the robot: half a second in, they are 0.8 m away, straight ahead.",
  "updates": [
    {
      "at": 500,
      "objectid": "Human/kid1",
      "attributename": "poses",
      "policy": "R",
      "jsonmsg": {"positionrho": 0.8, "positiontheta": 0.0, "positionchangetime": 500}
    }
  ]
}
"""  # noqa: E501 - the lines of the file `init` writes, as written

AUDIO = """\
# Audio tracks

The activities' audio tracks go here (`audio-root` in scriptc.toml): a script plays
`audio/songs/hello.wav` as `AO("songs/hello.wav, 0, 1000")`.
"""

WORKFLOW = """\
# Lint and test the activities on every push and pull request. Lint errors fail the job; every
# diagnostic shows as an annotation on the changed lines (--format github) and as a
# code-scanning alert (--format sarif, uploaded below); the second lint reads the first one's
# cache, so it costs almost nothing. Then the tests (*.test.toml) run in simulated time: a
# failing test fails the job, each failed expectation an annotation on its test file. Then
# `scriptc verify` explores every world: a property violated fails the job, on its line.
name: scriptc

on:
  push:
  pull_request:

permissions:
  contents: read
  security-events: write  # to upload SARIF to code scanning

jobs:
  scriptc:
    runs-on: ubuntu-latest
    steps:
      - uses: actions/checkout@v4
      - uses: actions/setup-python@v5
        with:
          python-version: "3.11"
      - name: Install scriptc
        id: install
<install>
      - name: Lint (annotations)
        run: scriptc lint . --format github
      # The next steps run even when the first lint found errors, but not without scriptc.
      - name: Lint (SARIF for code scanning)
        if: always() && steps.install.outcome == 'success'
        # Exit status 1 (errors found) still leaves a SARIF file to upload; 2 does not.
        run: scriptc lint . --format sarif --quiet > scriptc.sarif || test $? -eq 1
      - name: Upload to code scanning
        if: always() && steps.install.outcome == 'success'
        uses: github/codeql-action/upload-sarif@v3
        with:
          sarif_file: scriptc.sarif
          category: scriptc
      - name: Test
        if: always() && steps.install.outcome == 'success'
        run: scriptc test . --format github
      # Every world explored: each activity ends, reaches its goals, keeps within the robot's
      # profile; a violation is an annotation, and the world that shows it is kept.
      - name: Verify
        if: always() && steps.install.outcome == 'success'
        run: scriptc verify . --format github
      - name: Keep the counterexamples
        if: failure() && steps.install.outcome == 'success'
        uses: actions/upload-artifact@v4
        with:
          name: scriptc-verify
          path: scriptc-verify/
          if-no-files-found: ignore
"""

PRE_COMMIT = """\
# pre-commit (https://pre-commit.com): run `pre-commit install` once, then every commit
# lints and formats the scripts it changes. These hooks run the installed `scriptc`.
repos:
  - repo: local
    hooks:
      - id: scriptc-fmt
        name: scriptc fmt
        entry: scriptc fmt
        language: system
        files: \\.script$
      - id: scriptc-lint
        name: scriptc lint
        entry: scriptc lint --force-exclude
        language: system
        files: \\.script$
        require_serial: true  # scriptc lints in parallel itself
"""

# The install step when scriptc cannot tell where it came from: it fails, saying what to do,
# rather than install something else (a package of that name on an index need not be ours).
UNKNOWN_INSTALL = f"""\
        # `scriptc init` ran from a scriptc that no other machine can install (a local checkout).
        # Replace the command below with the install of your scriptc, for example
        #   python -m pip install "{PLACEHOLDER}"
        # (scriptc's docs/cli.md, "Installing scriptc in CI").
        run: |
          echo "::error::Edit the step 'Install scriptc' of .github/workflows/scriptc.yml: it does not say where to install scriptc from."
          exit 1"""  # noqa: E501 - the lines of the file `init` writes, as written


def workflow(origin: Provenance) -> str:
    """The CI workflow, installing the scriptc that `origin` describes."""
    requirement = origin.requirement()
    if requirement is None:
        step = UNKNOWN_INSTALL
    else:
        step = f'        run: python -m pip install "{requirement}"'
    return WORKFLOW.replace("<install>", step)


WORKFLOW_PATH = ".github/workflows/scriptc.yml"

# (path inside DIR, content or a function of the running scriptc's provenance), in the order
# they are written and reported.
FILES: tuple[tuple[str, str | Callable[[Provenance], str]], ...] = (
    ("scriptc.toml", CONFIG),
    ("activities/hello.script", ACTIVITY),
    ("activities/hello.test.toml", TEST),
    ("scenarios/hello.json", SCENARIO),
    ("audio/README.md", AUDIO),
    (WORKFLOW_PATH, workflow),
    (".pre-commit-config.yaml", PRE_COMMIT),
)


def scaffold(folder: str, origin: Provenance | None = None) -> tuple[list[str], list[str]]:
    """Write the files of a new activity repository into `folder` (made when missing), never
    over an existing file: the paths written and the paths skipped. `origin` is where the
    scriptc the workflow installs comes from (default: the running one's). Raises OSError (a
    folder that cannot be made) or WriteError (a file that cannot be written)."""
    origin = origin if origin is not None else provenance()
    os.makedirs(folder, exist_ok=True)
    written, skipped = [], []
    for name, content in FILES:
        text = content if isinstance(content, str) else content(origin)
        path = os.path.join(folder, *name.split("/"))
        if os.path.lexists(path):
            skipped.append(name)
            continue
        os.makedirs(os.path.dirname(path), exist_ok=True)
        # Created whole or not at all, and never over a file another process made meanwhile.
        try:
            write_file(path, text, exclusive=True)
        except FileExistsError:
            skipped.append(name)
            continue
        written.append(name)
    return written, skipped


@click.command("init")
@click.argument("folder", default=".", metavar="[DIR]")
def command(folder: str) -> None:
    """Scaffold an activity repository in DIR (default: here): configuration, an example
    activity with its test and scenario, a CI workflow and pre-commit hooks. Existing files
    are kept."""
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise CliError(f"`{folder}` is not a folder")
    origin = provenance()
    try:
        written, skipped = scaffold(folder, origin)
    except WriteError as exc:
        raise CliError(str(exc)) from None
    except OSError as exc:
        raise CliError(f"cannot write in `{folder}`: {exc.strerror or exc}") from None
    lines = [f"created {name}" for name in written]
    lines += [f"skipped {name} (it exists)" for name in skipped]
    if written:
        where = "" if os.path.abspath(folder) == os.getcwd() else f"cd {folder} && "
        lines.append(f"next: {where}scriptc lint . && scriptc test && scriptc verify .")
    write("".join(line + "\n" for line in lines))
    if WORKFLOW_PATH in written and origin.requirement() is None:
        write(f"warning: {WORKFLOW_PATH} cannot install scriptc: {origin.reason}. Edit its step "
              f"`Install scriptc` to install your scriptc, for example\n"
              f"  python -m pip install \"{PLACEHOLDER}\"\n"
              "(docs/cli.md, \"Installing scriptc in CI\"); until then the workflow fails "
              "there, saying so.\n", err=True)
