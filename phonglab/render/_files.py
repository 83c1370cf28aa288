"""Writing output files whole or not at all."""

from __future__ import annotations

import os
import secrets
from pathlib import Path


def write_atomically(path, write) -> None:
    """Call ``write(tmp_path)`` on a new hidden file beside ``path``, then rename it to ``path``.

    The temporary file is created with the usual permissions (0666 less the
    umask) and removed if anything fails, so ``path`` is either the complete
    new file or untouched.

    Raises
    ------
    OSError
        When the temporary file cannot be created, written or renamed.
    """
    path = Path(os.fspath(path))
    folder = path.resolve().parent
    while True:
        tmp = folder / f".{path.stem}-{secrets.token_hex(4)}{path.suffix}"
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
