"""Writing output files whole or not at all, and clearing what an interrupted write left."""

from __future__ import annotations

import os
import re
import secrets
import time
from pathlib import Path

#: marks a temporary file as ours: ``.NAME.phonglab-partial-XXXXXXXX.EXT``
TEMP_MARK = ".phonglab-partial-"
#: a temporary file older than this (seconds) belongs to a write that was killed
STALE_AFTER = 60.0
_OURS = re.compile(r"^\..*" + re.escape(TEMP_MARK) + r"[0-9a-f]{8}(\.[A-Za-z0-9]+)?$")
#: the naming before TEMP_MARK (``.NAME-XXXXXXXX.EXT``): cleared only when empty and a figure format
_OLD = re.compile(r"^\..+-[0-9a-f]{8}\.(png|svg|pdf)$")


def temp_name(path: Path) -> str:
    """A fresh temporary name beside ``path``: hidden, marked as ours, same extension."""
    return f".{path.stem}{TEMP_MARK}{secrets.token_hex(4)}{path.suffix}"


def is_temp_name(name: str) -> bool:
    """Whether ``name`` is one of :func:`temp_name`'s names."""
    return bool(_OURS.match(name))


def clean_stale_temporaries(folder, *, older_than: float = STALE_AFTER, now: float | None = None) -> list[str]:
    """Remove temporary files that a killed write left in ``folder``; return their names.

    Only files named by :func:`temp_name` (and empty ones of the older
    ``.NAME-XXXXXXXX.png`` naming) last modified more than ``older_than``
    seconds ago are removed: a write in progress elsewhere keeps its file.
    Errors (a missing folder, a file removed meanwhile) are ignored.
    """
    now = time.time() if now is None else now
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        ours = is_temp_name(entry.name)
        if not ours and not _OLD.match(entry.name):
            continue
        try:
            info = entry.stat(follow_symlinks=False)
            if not entry.is_file(follow_symlinks=False) or now - info.st_mtime < older_than:
                continue
            if not ours and info.st_size != 0:
                continue
            os.unlink(entry.path)
            removed.append(entry.name)
        except OSError:
            continue
    return removed


def write_atomically(path, write) -> None:
    """Call ``write(tmp_path)`` on a new hidden file beside ``path``, then rename it to ``path``.

    The temporary file is created with the usual permissions (0666 less the
    umask) and removed if anything fails, so ``path`` is either the complete
    new file or untouched. Temporaries a killed write left in the folder are
    cleared first (:func:`clean_stale_temporaries`).

    Raises
    ------
    OSError
        When the temporary file cannot be created, written or renamed.
    """
    path = Path(os.fspath(path))
    folder = path.resolve().parent
    clean_stale_temporaries(folder)
    while True:
        tmp = folder / temp_name(path)
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:  # pragma: no cover - a 32-bit name clash
            continue
    os.close(fd)
    try:
        write(str(tmp))
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
