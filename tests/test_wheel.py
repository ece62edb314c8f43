"""The wheel carries grammar/, schemas/ and the explanations, and works from any directory.

The wheel is built with `pip wheel .` (hatchling, the project's build backend, from the test
environment: no network), installed with `pip install --target` into a fresh folder, and run
from an unrelated working directory with the test environment's dependencies.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from scriptc.views.report import ASSETS

ROOT = Path(__file__).parent.parent


@pytest.mark.packaging
def test_wheel_ships_data_and_runs_anywhere(tmp_path: Path) -> None:
    wheels = tmp_path / "wheels"
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
         "--wheel-dir", str(wheels), str(ROOT)],
        check=True, capture_output=True,
    )
    (wheel,) = wheels.glob("scriptc-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    for required in ("scriptc/grammar/script.lark", "scriptc/grammar/condition.lark",
                     "scriptc/schemas/thesis-script.schema.json",
                     "scriptc/diagnostics/explanations/L003.md",
                     "scriptc/runtime/robots/teo.xml",
                     *(f"scriptc/views/assets/{name}" for name in ASSETS)):
        assert required in names, f"{required} is not in the wheel"

    target = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target",
                    str(target), str(wheel)], check=True, capture_output=True)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    script = elsewhere / "hello.script"
    script.write_text((ROOT / "examples" / "test_act.script").read_text(encoding="utf-8"),
                      encoding="utf-8")
    # Only the installed wheel and the dependencies: not the source tree.
    env = dict(os.environ,
               PYTHONPATH=os.pathsep.join([str(target), sysconfig.get_paths()["purelib"]]))
    probe = subprocess.run(
        [sys.executable, "-I", "-c",
         ("import sys; sys.path[:0] = sys.argv[1].split(__import__('os').pathsep);"
          "import scriptc, scriptc.resources as r; "
          "print(scriptc.__file__); print(r.data_dir('grammar'))"),
         env["PYTHONPATH"]],
        cwd=elsewhere, capture_output=True, text=True, check=True,
    )
    assert str(target) in probe.stdout and str(ROOT / "src") not in probe.stdout
    run = subprocess.run(
        [sys.executable, "-I", "-c",
         ("import sys; sys.path[:0] = sys.argv[1].split(__import__('os').pathsep);"
          "from scriptc.cli.main import main; "
          "sys.argv = ['scriptc', 'compile', 'hello.script', '-o', 'out.json']; main()"),
         env["PYTHONPATH"]],
        cwd=elsewhere, capture_output=True, text=True, check=False,
    )
    assert run.returncode == 0, run.stderr
    expected = (ROOT / "tests/data/script_gen_test_act.json").read_text(encoding="utf-8")
    assert (elsewhere / "out.json").read_text(encoding="utf-8") == expected
