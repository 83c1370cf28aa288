"""The ``phonglab`` command line: serve, export, check, plan, bench, grade, new.

Each subcommand lives in its own module of this package and exposes two
functions::

    def add_parser(subparsers) -> argparse.ArgumentParser: ...
    def run(args) -> int: ...          # the process exit status

Modules are imported only when their subcommand runs, so ``phonglab check``
does not pay for importing VTK or trame.

Exit status: 0 success, 1 the files or scene had problems (``check``), 2 bad
usage or bad input (argparse's own convention), as every subcommand documents.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from phonglab.bench.usage import UsageError  # raised by the subcommands and the benchmarks

#: subcommand name -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "serve": ("phonglab.cli.serve", "open the lesson app in a browser"),
    "export": ("phonglab.cli.export", "render a scene or lesson to PNG/SVG/PDF"),
    "check": ("phonglab.cli.check", "validate scene and lesson files"),
    "plan": ("phonglab.cli.plan", "show which effects a scene computes and skips"),
    "bench": ("phonglab.cli.bench", "measure speed and accuracy (ratios, same run)"),
    "grade": ("phonglab.cli.grade", "grade a student's shade() for one point against the core"),
    "new": ("phonglab.cli.new", "write a minimal lesson to start from (phonglab new lesson FILE)"),
}


def _load(name: str):
    return importlib.import_module(COMMANDS[name][0])


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="phonglab",
        description="phonglab: learn the Phong illumination model by moving sliders.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (_, help_text) in COMMANDS.items():
        if name == only:
            _load(name).add_parser(sub)
        else:  # a placeholder lists the command in `phonglab --help` without importing it
            sub.add_parser(name, help=help_text, add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    parser = build_parser(command if command in COMMANDS else None)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        status = int(_load(args.command).run(args) or 0)
        sys.stdout.flush()  # a closed pipe shows here, inside the handler below
        return status
    except UsageError as exc:
        print(f"phonglab {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        # the reader went away (e.g. `phonglab plan FILE | head`): not an error of ours
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
