"""``phonglab serve [LESSON]``: open the lesson app in a browser.

``LESSON`` is a lesson file (``lessons/03-specular.md``), a lesson number
(``3``), a folder of lessons, or a scene file (``.toml``); without it the
first lesson of ``lessons/`` opens. Every browser tab gets its own session.
The server listens on 127.0.0.1 (this machine only) unless ``--host`` says
otherwise; stop it with Ctrl-C.

Exit status: 0 after a clean stop, 2 for a lesson that does not exist or a
port that cannot be used.
"""

from __future__ import annotations

import errno
import ipaddress
import sys
from pathlib import Path

#: where lessons live when no LESSON is given: ./lessons, else the source tree's
DEFAULT_FOLDER = "lessons"


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "serve",
        help="open the lesson app in a browser",
        description="Serve the lesson app; open the printed address in a browser. Each tab is its own session.",
    )
    parser.add_argument("lesson", nargs="?", metavar="LESSON",
                        help="a lesson file, a lesson number, a lessons folder or a scene file (default: lessons/)")
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    parser.add_argument("--port", type=_port, default=8080, help="port to listen on (default 8080; 0 picks a free one)")
    parser.add_argument("--export-dir", default=None, metavar="DIR",
                        help="also keep a server copy of each figure exported from the page there "
                             "(default: none; exports download to the browser)")
    return parser


def _port(text: str) -> int:
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number from 0 to 65535, got {text!r}") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"must be a whole number from 0 to 65535, got {value}")
    return value


def default_folder() -> Path:
    """``./lessons`` if it exists, else the ``lessons/`` folder next to the package."""
    here = Path.cwd() / DEFAULT_FOLDER
    if here.is_dir():
        return here
    return Path(__file__).resolve().parents[2] / DEFAULT_FOLDER


def resolve_target(lesson: str | None) -> Path:
    """The file or folder to serve for the LESSON argument.

    Raises
    ------
    phonglab.cli.UsageError
        When nothing matches.
    """
    from phonglab.cli import UsageError
    from phonglab.scene import lesson_files

    if lesson is None:
        folder = default_folder()
        if not folder.is_dir():
            raise UsageError(f"no lessons folder at {folder}; give a LESSON file or folder")
        return folder
    path = Path(lesson)
    if path.exists():
        if path.is_file() and path.suffix.lower() not in (".md", ".markdown", ".toml"):
            raise UsageError(f"LESSON must be a lesson (.md), a scene (.toml) or a folder, got {lesson!r}")
        return path
    if lesson.isdigit():
        folder = default_folder()
        for candidate in lesson_files(folder) if folder.is_dir() else []:
            digits = candidate.name.split("-")[0]
            if digits.isdigit() and int(digits) == int(lesson):
                return candidate
        raise UsageError(f"no lesson number {lesson} in {folder}")
    raise UsageError(f"no such lesson file or folder: {lesson!r}")


def run(args) -> int:
    from phonglab.cli import UsageError

    target = resolve_target(args.lesson)
    host = args.host
    if not _is_loopback(host):
        print(f"phonglab serve: warning: listening on {host}: other machines can reach this server",
              file=sys.stderr)

    def ready(port):
        shown = f"[{host}]" if ":" in host else host
        print(f"phonglab: serving {target} at http://{shown}:{port}/  (Ctrl-C stops)", flush=True)

    from phonglab.app import serve

    try:
        serve(target, host=host, port=args.port, export_dir=args.export_dir, on_ready=ready)
    except OSError as exc:
        if exc.errno in (errno.EADDRINUSE, errno.EACCES, errno.EADDRNOTAVAIL):
            raise UsageError(f"cannot listen on {host}:{args.port}: {exc.strerror}") from None
        raise
    return 0


def _is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False
