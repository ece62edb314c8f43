"""Pass 6, audio track paths: empty (A003), absolute (A001), or leaving the activity
repository once normalised (A002). The track `Silence` plays nothing and is always fine
(docs/runtime.md). Whether the file exists is not this pass's business: it needs the repository.
"""

from __future__ import annotations

import posixpath
import re

from scriptc.check.context import Context
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.ir.nodes import InstructionBlock

SILENCE = "Silence"
# `/x`, `\x` (and UNC `\\host`), `~` or `~user`, and Windows drives `C:` / `C:\x` / `C:/x`.
_ABSOLUTE = re.compile(r"[/\\~]|[A-Za-z]:")


def check_audio(ctx: Context) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    for block in ctx.blocks:
        if not isinstance(block, InstructionBlock):
            continue
        for ao in block.audios:
            path = ao.track_path.value.strip()
            if path == SILENCE:
                continue
            if not path:
                out.append(
                    diagnostic(
                        "A003",
                        "the audio command has no track path",
                        ao.span,
                        help="write the track's path before `wait_t` and `duration` "
                             '(`"songs/a.wav, 0, 1000"`), or `Silence` to play nothing',
                    )
                )
            elif _ABSOLUTE.match(path):
                out.append(
                    diagnostic(
                        "A001",
                        f"the audio path `{path}` is absolute",
                        ao.track_path.span,
                        notes=(("an absolute path names a file on one machine; the activity "
                                "breaks when it is copied to the robot or to another computer"),),
                        help="write the path relative to the activity repository, as the "
                             "thesis does: `plugins/audio_control/songs/...`",
                    )
                )
            elif ".." in path:
                normal = posixpath.normpath(path.replace("\\", "/"))
                if normal == ".." or normal.startswith("../"):
                    out.append(
                        diagnostic(
                            "A002",
                            f"the audio path `{path}` leaves the activity repository",
                            ao.track_path.span,
                            notes=(f"normalised, it is `{normal}`",),
                            help="keep the track inside the activity repository and write "
                                 "its path from there",
                        )
                    )
    return out
