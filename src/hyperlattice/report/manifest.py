"""The report directory's manifest: which files a report wrote, each with its SHA-256.

``_report.json`` in a report directory is the manifest. :func:`start` writes it before the first
output file; every writer of the report then records its file through :func:`writing` (the name
first, as pending, then the checksum once the file is complete), so an interrupted run leaves a
manifest that still describes the directory. A later run may write into a directory only when
:func:`problem` finds nothing wrong: the manifest is one a report wrote (format, version, a file
list), every file of the directory is listed, and every listed file still has its checksum. A
``_report.json`` a user made (even an empty one), a file the user added, or an output the user
edited is refused, so nothing of the user's is overwritten.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
from pathlib import Path
from typing import Iterator

from .. import _validate

__all__ = ["NAME", "FORMAT", "start", "writing", "problem"]

#: the manifest's file name in a report directory
NAME = "_report.json"
#: the manifest's format tag
FORMAT = "hyperlattice-report/2"
_TMP = NAME + ".tmp"
_SHA = re.compile(r"[0-9a-f]{64}\Z")


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _save(out: Path, data: dict) -> None:
    # atomic: a reader (or a run interrupted here) sees the old manifest or the new one, never half
    tmp = out / _TMP
    tmp.write_text(json.dumps(data, indent=1, sort_keys=True))
    os.replace(tmp, out / NAME)


def _load(out: Path) -> dict | None:
    try:
        data = json.loads((out / NAME).read_text(encoding="utf-8"))
    except (OSError, ValueError, UnicodeDecodeError):
        return None
    if not (isinstance(data, dict) and data.get("format") == FORMAT and isinstance(data.get("version"), str)
            and isinstance(data.get("files"), dict)):
        return None
    files = data["files"]
    if not all(isinstance(k, str) and "/" not in k and k not in (NAME, _TMP)
               and (v is None or (isinstance(v, str) and _SHA.match(v))) for k, v in files.items()):
        return None
    return data


def problem(out: Path) -> str | None:
    """Why the report directory ``out`` (holding :data:`NAME`) may not be written into, or None.

    Returns a clause for the refusal sentence: the manifest is not a report's, or a file is not
    listed in it, or a listed file no longer has its checksum. A file recorded as pending (the run
    that wrote it was interrupted while writing it) may hold anything.
    """
    out = _validate.directory("out", out, create=False)
    data = _load(out)
    if data is None:
        return f"its {NAME} is not a manifest a report wrote"
    files = data["files"]
    try:
        present = sorted(out.iterdir(), key=lambda f: f.name)
    except OSError as exc:
        return f"it cannot be read ({exc.strerror or exc})"
    for f in present:
        if f.name in (NAME, _TMP):
            continue
        if f.name not in files or f.is_dir() or f.is_symlink():
            return f"it holds {f.name + ('/' if f.is_dir() else '')!r}, which the report's manifest does not list"
        expected = files[f.name]
        if expected is not None and _sha256(f) != expected:
            return f"{f.name!r} was changed after the report wrote it (its SHA-256 differs from the manifest's)"
    return None


def start(out: Path, version: str) -> None:
    """Write the manifest of a run into ``out``, keeping the files an earlier run recorded (verified)."""
    out = _validate.directory("out", out, create=False)
    if not isinstance(version, str) or not version:
        raise ValueError(f"version must be the package version as a string, got {version!r}.")
    data = _load(out)
    files = {k: v for k, v in data["files"].items() if (out / k).is_file()} if data is not None else {}
    _save(out, {"format": FORMAT, "version": version, "files": files})


@contextlib.contextmanager
def writing(out: Path, name: str) -> Iterator[Path]:
    """Record ``out / name`` in the manifest around its writing; yields the path.

    Without a manifest in ``out`` (a writer used on its own, outside a report) nothing is recorded.
    """
    out = _validate.directory("out", out, create=False)
    if not isinstance(name, str) or not name or "/" in name or name in (NAME, _TMP):
        raise ValueError(f"name must be a file name in the report directory, got {name!r}.")
    data = _load(out) if (out / NAME).is_file() else None
    if data is not None:
        data["files"][name] = None          # pending: an interruption leaves it listed
        _save(out, data)
    yield out / name
    if data is not None:
        data = _load(out) or data
        data["files"][name] = _sha256(out / name)
        _save(out, data)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
