"""``phonglab check FILE...``: validate scene files and lessons.

Every file is loaded and checked completely; every problem in every file is
printed as ``FILE:LINE: field.path: what is allowed, got VALUE``, and a good
file as ``ok FILE``. A folder stands for its ``*.toml`` scenes and its
lessons (``*.md`` files whose name starts with a digit).

Exit status: 0 when every file is good, 1 when any has a problem.
"""

from __future__ import annotations

import sys
from pathlib import Path


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "check",
        help="validate scene and lesson files",
        description="Validate scene files (.toml) and lessons (.md); list every problem in every file.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="scene files, lessons, or folders of them")
    parser.add_argument("-q", "--quiet", action="store_true", help="print only the problems")
    return parser


def expand(names) -> list[Path]:
    """The files to check: each name, with folders replaced by the scenes and lessons inside."""
    from phonglab.scene import lesson_files

    files = []
    for name in names:
        path = Path(name)
        if path.is_dir():
            inside = sorted(path.glob("*.toml")) + lesson_files(path)
            files.extend(inside or [path])
        else:
            files.append(path)
    return files


def _read_mesh(loaded, path) -> None:
    """Read a scene's mesh file as export would, so a file that passes check also exports.

    Parametric shapes are skipped; a mesh file was already sized from its
    header when the scene loaded, so reading it is bounded.
    """
    scene = getattr(loaded, "scene", loaded)
    geometry = getattr(scene, "geometry", None)
    if geometry is None or geometry.kind not in ("file", "pyvista"):
        return
    from phonglab.render.mesh import build_mesh  # VTK: only when a scene reads a mesh
    from phonglab.scene import SceneError

    try:
        build_mesh(geometry)
    except SceneError as exc:
        raise exc.located(file=str(path)) from None


def run(args) -> int:
    from phonglab.scene import SceneError, load

    bad_files = problems = 0
    files = expand(args.files)
    for path in files:
        try:
            _read_mesh(load(path), path)
        except SceneError as exc:
            errors = getattr(exc, "errors", [exc])
            bad_files += 1
            problems += len(errors)
            for error in errors:
                print(error)
        else:
            if not args.quiet:
                print(f"ok {path}")
    if bad_files:
        files_word = "file" if len(files) == 1 else "files"
        problem_word = "problem" if problems == 1 else "problems"
        print(f"{problems} {problem_word} in {bad_files} of {len(files)} {files_word}", file=sys.stderr)
        return 1
    return 0
