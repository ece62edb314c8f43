"""The picture of the report in docs/views.md: the report of the approach example's run
(`scriptc run examples/approach.script --world examples/approach.world.json --report`), opened
in headless Chromium (Debian's, tests/chromium.py), the cursor put at 4.5 s, the whole page
taken as a PNG: docs/img/report-approach.png. Beside it, docs/img/report-approach.txt records
the digest of the page's template it was made from (`scriptc.views.report.template_digest`)
and the picture's size; tests/test_views_report.py fails when the template has changed since,
naming this command:

    python bench/report_screenshot.py
"""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from chromium import Chromium  # noqa: E402  (tests/ on the path first)

from scriptc.views.report import template_digest  # noqa: E402

PICTURE = ROOT / "docs" / "img" / "report-approach.png"
RECORD = PICTURE.with_suffix(".txt")
WIDTH = 1280
CURSOR_S = 4.5


def png_size(data: bytes) -> tuple[int, int]:
    """The width and height of a PNG (its IHDR chunk)."""
    if data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        raise ValueError("not a PNG")
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / "report.html"
        subprocess.run([sys.executable, "-m", "scriptc", "run", "approach.script", "--world",
                        "approach.world.json", "--report", str(page)], cwd=ROOT / "examples",
                       check=True, stdout=subprocess.DEVNULL)
        with Chromium(width=WIDTH, height=1500) as browser:  # every chart in view
            browser.open(page.as_uri())
            browser.wait_for("window.scriptcReport && window.scriptcReport.ready")
            x, y = browser.evaluate(
                "(() => { const u = scriptcReport.charts[1], r = u.over.getBoundingClientRect();"
                f" return [r.left + u.valToPos({CURSOR_S}, 'x'), r.top + r.height / 2]; }})()")
            browser.mouse_move(x, y)
            data = browser.screenshot()
            if browser.problems:
                raise SystemExit(f"the page has problems: {browser.problems}")
    width, height = png_size(data)
    PICTURE.parent.mkdir(parents=True, exist_ok=True)
    PICTURE.write_bytes(data)
    RECORD.write_text(f"template {template_digest()}\nsize {width}x{height}\n",
                      encoding="utf-8")
    print(f"wrote {os.path.relpath(PICTURE)} ({width}x{height}, {len(data) / 1024:.0f} KiB) "
          f"and {os.path.relpath(RECORD)}")


if __name__ == "__main__":
    main()
