"""``phonglab serve [LESSON]``: open the lesson app in a browser.

``LESSON`` is a lesson file (``lessons/03-specular.md``), a lesson number
(``3``), a folder of lessons, or a scene file (``.toml``); without it the
first lesson of ``lessons/`` opens. Every browser tab gets its own session.
The server listens on 127.0.0.1 (this machine only) unless ``--host`` says
otherwise; stop it with Ctrl-C.

Only the page this server serves may open a session (its own origin, or
one given with ``--allow-origin`` when a proxy serves it under another
address); at most ``--max-sessions`` tabs are open at once.

With ``--launcher`` each tab gets a phonglab process of its own behind the
same address (:mod:`phonglab.app.launcher`, wslink's launcher); the session
processes are this command with ``--one-session`` on a 127.0.0.1 port.
``--url-prefix`` names the path a proxy serves the app under (JupyterHub's
jupyter-server-proxy: :mod:`phonglab.app.jupyter_proxy`).

With ``--export-dir``, the hidden temporary files that an export killed
mid-write left there (by a server or an export stopped with ``kill -9``)
are removed when the server starts.

Exit status: 0 after a clean stop, 2 for a lesson that does not exist or an
address or port that cannot be used.
"""

from __future__ import annotations

import argparse
import errno
import ipaddress
import os
import socket
import sys
from pathlib import Path

from phonglab.bench.usage import bounded

#: where lessons live when no LESSON is given: ./lessons, else the source tree's
DEFAULT_FOLDER = "lessons"


def add_parser(subparsers):
    from phonglab.app.guard import DEFAULT_MAX_SESSIONS

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
    parser.add_argument("--allow-origin", action="append", default=[], type=_origin, metavar="ORIGIN",
                        help="also accept pages from ORIGIN (scheme://host[:port], e.g. https://phong.school.org "
                             "behind a proxy); repeatable. The page's own address is always accepted")
    parser.add_argument("--max-sessions", type=_max_sessions, default=DEFAULT_MAX_SESSIONS, metavar="N",
                        help=f"browser tabs served at once (default {DEFAULT_MAX_SESSIONS}); "
                             "one more is told the server is full")
    parser.add_argument("--allow-student-code", action="store_true",
                        help="show the 'Your code' panel: students paste their shade() and it RUNS ON THIS SERVER, "
                             "graded like `phonglab grade` in a bubblewrap sandbox (own user, PID, network and mount "
                             "namespaces, a read-only view of only Python and NumPy, a seccomp filter, CPU, memory "
                             "and time limits), a few at once. Refuses to start when bwrap or libseccomp is missing")
    parser.add_argument("--launcher", action="store_true",
                        help="one phonglab process per browser tab, behind this one address (wslink's launcher): "
                             "a class uses every core. --max-sessions processes at most, on 127.0.0.1 ports from "
                             "--session-ports; a tab's process ends when the tab closes or after --idle-timeout")
    parser.add_argument("--session-ports", type=_port, default=None, metavar="FIRST",
                        help="with --launcher: the first of --max-sessions ports the session processes use on "
                             "127.0.0.1 (default 9100)")
    parser.add_argument("--idle-timeout", type=_idle, default=None, metavar="SECONDS",
                        help="with --launcher: end a tab's session after this many seconds without a message "
                             "(default 1800)")
    parser.add_argument("--url-prefix", type=_prefix, default="/", metavar="PATH",
                        help="the path a proxy serves the app under (e.g. /user/ana/phonglab/ behind JupyterHub's "
                             "jupyter-server-proxy): the page's WebSocket address starts with it (default /)")
    parser.add_argument("--one-session", action="store_true", help=argparse.SUPPRESS)
    return parser


_max_sessions = bounded(int, 1, None, "a whole number of at least 1")
_port = bounded(int, 0, 65535, "a whole number from 0 to 65535")
_idle = bounded(float, 10, 86400, "a number of seconds from 10 to 86400")


def _prefix(text: str) -> str:
    from phonglab.app.server import normal_prefix

    try:
        return normal_prefix(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _origin(text: str) -> str:
    import argparse

    from phonglab.app.guard import normal_origin

    try:
        return normal_origin(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


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
    try:  # a name or address that does not resolve: say so before building anything
        socket.getaddrinfo(host, args.port, type=socket.SOCK_STREAM)
    except (socket.gaierror, UnicodeError) as exc:
        raise UsageError(f"cannot listen on {host}:{args.port}: {getattr(exc, 'strerror', None) or exc}") from None
    if not _is_loopback(host):
        print(f"phonglab serve: warning: listening on {host}: other machines can reach this server",
              file=sys.stderr)
    if args.allow_student_code:
        _check_student_code()
    _remove_stale_gradings()

    if args.export_dir is not None and not args.one_session:
        # (behind the launcher the front cleaned the folder once: a session process starting
        # while another tab's export is being written must not take that file for a leftover)
        _clean_export_dir(args.export_dir)

    def ready(port):
        shown = f"[{host}]" if ":" in host else host
        print(f"phonglab: serving {target} at http://{shown}:{port}/  (Ctrl-C stops)", flush=True)

    from phonglab.app import serve

    if (args.session_ports is not None or args.idle_timeout is not None) and not args.launcher:
        raise UsageError("--session-ports and --idle-timeout go with --launcher")
    try:
        if args.launcher:
            _serve_launcher(target, args, ready)
        else:
            secret = None
            if args.one_session:  # a session process behind the launcher: its secret comes in the environment
                from phonglab.app.launcher import SECRET_ENV

                secret = os.environ.get(SECRET_ENV) or None
                if secret is None:
                    raise UsageError(f"--one-session needs the secret in {SECRET_ENV}")
            serve(target, host=host, port=args.port, export_dir=args.export_dir, on_ready=ready,
                  allow_origins=args.allow_origin, max_sessions=1 if args.one_session else args.max_sessions,
                  allow_student_code=args.allow_student_code, secret=secret, one_session=args.one_session,
                  url_prefix=args.url_prefix)
    except socket.gaierror as exc:  # a host name or address that does not resolve
        raise UsageError(f"cannot listen on {host}:{args.port}: {exc.strerror or exc}") from None
    except OSError as exc:
        if exc.errno in (errno.EADDRINUSE, errno.EACCES, errno.EADDRNOTAVAIL):
            raise UsageError(f"cannot listen on {host}:{args.port}: {exc.strerror}") from None
        raise
    return 0


def _serve_launcher(target, args, ready) -> None:
    """``--launcher``: the page and wslink's launcher here, one session process per tab."""
    import asyncio
    import logging

    from phonglab.app import launcher, make_app

    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    first = launcher.FIRST_PORT if args.session_ports is None else args.session_ports
    if first + args.max_sessions - 1 > 65535:
        from phonglab.cli import UsageError

        raise UsageError(f"--session-ports: {args.max_sessions} ports from {first} pass 65535")
    front = launcher.Launcher(
        make_app(target), max_sessions=args.max_sessions, first_port=first, allow_origins=args.allow_origin,
        idle=launcher.IDLE_SECONDS if args.idle_timeout is None else args.idle_timeout, url_prefix=args.url_prefix,
        command=launcher.session_command(target, allow_student_code=args.allow_student_code,
                                         export_dir=args.export_dir))
    asyncio.run(front.run(args.host, args.port, on_ready=ready))


def _clean_export_dir(folder) -> list[str]:
    """Remove what exports killed mid-write left in ``folder`` (before any tab can export); say so on stderr."""
    from phonglab.render._files import clean_stale_temporaries

    removed = clean_stale_temporaries(folder)
    if removed:
        print(f"phonglab serve: removed {len(removed)} temporary file(s) an interrupted export left in {folder}: "
              + ", ".join(removed[:5]) + (", …" if len(removed) > 5 else ""), file=sys.stderr)
    return removed


def _check_student_code() -> None:
    """Refuse ``--allow-student-code`` (one line: what to install) unless the grader's sandbox works here."""
    from phonglab.app.student_code import grading_slots
    from phonglab.cli import UsageError
    from phonglab.teaching.isolation import SandboxUnavailable, check

    try:
        check()
    except SandboxUnavailable as exc:
        raise UsageError(f"--allow-student-code: {exc}") from None
    print(f"phonglab serve: --allow-student-code: students' code runs on this server in a bubblewrap sandbox, "
          f"{grading_slots()} at a time", file=sys.stderr)


def _remove_stale_gradings() -> list[str]:
    """Remove students' folders that gradings killed under earlier versions left in the temporary folder."""
    from phonglab.teaching.isolation import remove_stale_folders

    removed = remove_stale_folders()
    if removed:
        print(f"phonglab serve: removed {len(removed)} folder(s) of students' code left by killed gradings",
              file=sys.stderr)
    return removed


def _is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False
