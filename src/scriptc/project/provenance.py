"""Where the running scriptc was installed from, and the pip requirement that installs the same
scriptc somewhere else (a CI runner, a colleague's machine).

pip records how it installed a distribution in the distribution's `direct_url.json` (PEP 610):

- from a version control system: the repository's URL and the commit (`vcs_info`), so
  `scriptc @ git+URL@COMMIT` installs exactly this scriptc anywhere that can reach the URL;
- from an archive at a URL (`archive_info`): `scriptc @ URL`, when the URL is not a local file;
- from a local folder (`dir_info`, editable or not) or a local archive: nothing another machine
  can install, so there is no requirement, and the reason says what to write instead;
- no `direct_url.json` at all: installed from a package index, so `scriptc==VERSION`.

`scriptc init` writes the requirement into the CI workflow it scaffolds (docs/cli.md), and says
plainly when there is none instead of writing one that cannot work.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

if TYPE_CHECKING:  # importlib.metadata is imported when the installation is read
    from importlib.metadata import Distribution

__all__ = ["PLACEHOLDER", "Provenance", "extra_install_command", "provenance"]

DISTRIBUTION = "scriptc"

# What a user writes when scriptc cannot tell (the docs use the same placeholder): the host,
# owner and commit are theirs to fill in.
PLACEHOLDER = "scriptc @ git+https://<your-host>/<you>/scriptc@<commit>"


@dataclass(frozen=True)
class Provenance:
    """How the running scriptc was installed: `requirement(extras)` reproduces it, or is None
    when nothing can (then `reason` says why, in a sentence)."""

    kind: str  # "vcs", "url", "index" or "local"
    base: str | None  # the requirement without extras, or None
    reason: str = ""

    def requirement(self, extras: Sequence[str] = ()) -> str | None:
        """The pip requirement, with `extras` (`scriptc[plot] @ git+...`), or None."""
        if self.base is None:
            return None
        name = DISTRIBUTION + (f"[{','.join(extras)}]" if extras else "")
        return name + self.base[len(DISTRIBUTION):]


# A requirement of one extra as the metadata writes it: `matplotlib>=3.7; extra == "plot"`.
_EXTRA_REQUIREMENT = re.compile(
    r"""^(?P<requirement>[^;]+);\s*extra\s*==\s*(?P<q>["'])(?P<extra>[^"']+)(?P=q)\s*$""")


def _installed(distribution: Distribution | None) -> Distribution | None:
    """The given distribution, else the installed scriptc's, else None."""
    if distribution is not None:
        return distribution
    from importlib import metadata

    try:
        return metadata.distribution(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return None


def extra_install_command(extra: str, fallback: Sequence[str],
                          distribution: Distribution | None = None) -> str:
    """The command that installs what an extra of scriptc needs (`plot`: matplotlib) into the
    environment scriptc runs in: `/path/to/python -m pip install 'matplotlib>=3.7'`. The
    requirements are the extra's own, as the installed scriptc declares them; `fallback` when
    scriptc is not installed as a package."""
    import shlex
    import sys

    found = _installed(distribution)
    wanted = []
    for text in (found.requires or []) if found is not None else []:
        m = _EXTRA_REQUIREMENT.match(text)
        if m is not None and m.group("extra") == extra:
            wanted.append(m.group("requirement").strip())
    return " ".join([shlex.quote(sys.executable), "-m", "pip", "install",
                     *(shlex.quote(r) for r in (wanted or fallback))])


def provenance(distribution: Distribution | None = None) -> Provenance:
    """The provenance of `distribution` (an `importlib.metadata.Distribution`; default: the
    installed scriptc). Never raises: a missing or unreadable record means "cannot tell"."""
    distribution = _installed(distribution)
    if distribution is None:
        return Provenance("local", None, "scriptc is not installed as a package (it runs from "
                                         "its source folder)")
    version = distribution.version
    try:
        raw = distribution.read_text("direct_url.json")
    except OSError:
        raw = None
    if raw is None:
        return Provenance("index", f"{DISTRIBUTION}=={version}")
    try:
        record = json.loads(raw)
        url = record["url"]
        if not isinstance(url, str) or not isinstance(record, dict):
            raise TypeError
    except (ValueError, TypeError, KeyError):
        return Provenance("local", None, "scriptc's installation record (direct_url.json) "
                                         "cannot be read")
    fragments = []
    subdirectory = record.get("subdirectory")
    if isinstance(subdirectory, str) and subdirectory:
        fragments.append(f"subdirectory={subdirectory}")
    local = urlsplit(url).scheme in ("", "file")
    vcs = record.get("vcs_info")
    if isinstance(vcs, dict) and isinstance(vcs.get("vcs"), str) \
            and isinstance(vcs.get("commit_id"), str) and not local:
        return Provenance("vcs", f"{DISTRIBUTION} @ {vcs['vcs']}+{url}@{vcs['commit_id']}"
                                 + _fragment(fragments))
    archive = record.get("archive_info")
    if isinstance(archive, dict) and not local:
        # The archive's digest, so pip refuses another file at the same URL: `hashes` (PEP 610
        # as amended) or the older `hash` ("sha256=...").
        hashes = archive.get("hashes")
        if isinstance(hashes, dict) and isinstance(hashes.get("sha256"), str):
            fragments.append(f"sha256={hashes['sha256']}")
        elif isinstance(archive.get("hash"), str) and "=" in archive["hash"]:
            fragments.append(archive["hash"])
        return Provenance("url", f"{DISTRIBUTION} @ {url}" + _fragment(fragments))
    where = urlsplit(url).path or url
    editable = isinstance(record.get("dir_info"), dict) and record["dir_info"].get("editable")
    what = "an editable install of the checkout" if editable else "an install from the files"
    return Provenance("local", None, f"scriptc {version} is {what} at {where}, which no other "
                                     "machine can install")


def _fragment(parts: list[str]) -> str:
    return "#" + "&".join(parts) if parts else ""
