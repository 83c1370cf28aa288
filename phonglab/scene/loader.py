"""Read scene files (TOML) into checked scenes, with each problem's file and line.

A scene file is TOML read with :mod:`tomllib`; its table is checked once
(:func:`phonglab.scene.build.scene_parts`) into a :class:`~phonglab.scene.model.Scene`.
Every problem found is reported, not only the first: loading raises
:class:`~phonglab.scene.errors.SceneErrors` listing each one as
``FILE:LINE: field.path: what is allowed, got VALUE``
(the line from :class:`~phonglab.scene.toml_lines.KeyLines`). Lessons, which
wrap a scene in Markdown, are read by :mod:`phonglab.scene.lessons`.
"""

from __future__ import annotations

import os
import re
import stat
import tomllib
from pathlib import Path

from phonglab.scene.build import Problems, scene_parts
from phonglab.scene.checks import check_nesting
from phonglab.scene.errors import SceneError, SceneErrors
from phonglab.scene.model import Scene
from phonglab.scene.schema import MAX_SCENE_FILE_BYTES
from phonglab.scene.toml_lines import KeyLines


def scene_from_dict(data: dict, *, source=None, base_dir=None) -> Scene:
    """Check a scene given as a dictionary (parsed TOML) and build the Scene.

    Parameters
    ----------
    data : dict
        Keys as in a scene file.
    source : str, optional
        Stored in ``Scene.source``; not used in the messages.
    base_dir : path, optional
        Folder against which a relative ``geometry.path`` is resolved.

    Raises
    ------
    SceneError
        The only problem; or SceneErrors listing every problem.
    """
    problems = Problems()
    parts = scene_parts(data, problems, base_dir=base_dir)
    problems.raise_all()
    return Scene(source=source, **parts)


# ---------------------------------------------------------------------------
# files


def display(path) -> str:
    """The file name for messages: as the caller gave it."""
    return os.fspath(path)


def read_text(path, shown) -> str:
    """The file's UTF-8 text; a SceneErrors naming the file (``shown``) when it cannot be read.

    Only a regular file is read: a FIFO, a device or a socket is refused
    before it is opened (reading one could wait for ever), and the file is
    opened without blocking and checked again, in case it was swapped
    meanwhile. At most :data:`~phonglab.scene.schema.MAX_SCENE_FILE_BYTES`
    are read.
    """
    def refused(problem):
        return SceneErrors([SceneError(problem, file=shown)])

    try:
        info = os.stat(path)
        if stat.S_ISDIR(info.st_mode):
            raise refused("is a folder, not a scene or lesson file")
        if not stat.S_ISREG(info.st_mode):
            raise refused(f"is {_file_kind(info.st_mode)}, not a regular file")
        if info.st_size > MAX_SCENE_FILE_BYTES:
            raise refused(f"is too large: {info.st_size:,} bytes, at most {MAX_SCENE_FILE_BYTES:,} allowed")
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise refused("is not a regular file")
            data = f.read(MAX_SCENE_FILE_BYTES + 1)
        if len(data) > MAX_SCENE_FILE_BYTES:
            raise refused(f"is too large: more than {MAX_SCENE_FILE_BYTES:,} bytes allowed")
        # newlines as text mode reads them: \r\n and \r become \n
        return data.decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")
    except FileNotFoundError:
        raise refused("no such file") from None
    except UnicodeDecodeError as exc:
        raise refused(f"is not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except OSError as exc:
        raise refused(f"cannot be read: {exc.strerror or exc}") from None


def _file_kind(mode: int) -> str:
    """What a file that is not regular is, in words."""
    for test, words in ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
                        (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return words
    return "not a file"


def parse_toml(text: str, shown: str, first_line: int = 1) -> dict:
    """tomllib.loads, with a syntax error turned into a located SceneError.

    Text nested deeper than :data:`~phonglab.scene.schema.MAX_NESTING` is
    refused first: tomllib recurses once per level.
    """
    try:
        check_nesting(text, file=shown)
    except SceneError as exc:
        raise SceneErrors([exc]) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        match = re.search(r"\(at line (\d+), column (\d+)\)", message)
        line = None
        if match:
            line = int(match.group(1)) + first_line - 1
            message = message[: match.start()].rstrip() + f" (column {match.group(2)})"
        elif "end of document" in message:
            line = text.count("\n") + first_line
        raise SceneErrors([SceneError(f"is not valid TOML: {message}", file=shown, line=line)]) from None


def load_scene(path) -> Scene:
    """Load and check a TOML scene file.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    Scene
        With ``source`` set to ``path``.

    Raises
    ------
    SceneErrors
        Every problem in the file, each naming the file, line, field path,
        bad value and what is allowed.
    """
    shown = display(path)
    text = read_text(path, shown)
    data = parse_toml(text, shown)
    problems = Problems()
    parts = scene_parts(data, problems, base_dir=Path(path).resolve().parent)
    problems.raise_all(file=shown, lines=KeyLines(text))
    return Scene(source=os.fspath(path), **parts)


def lesson_files(folder) -> list[Path]:
    """The lesson files in ``folder``: ``*.md`` whose name starts with a digit, sorted."""
    found = [p for p in Path(folder).glob("*.md") if p.name[:1].isdigit()]
    return sorted(found, key=lambda p: (int(re.match(r"\d+", p.name).group()), p.name))
