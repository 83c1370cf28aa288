"""``phonglab check FILE...``: validate scene files and lessons, and run the lessons' claims.

Every file is loaded and checked completely; every problem in every file is
printed as ``FILE:LINE: field.path: what is allowed, got VALUE``, and a good
file as ``ok FILE``. A folder stands for its ``*.toml`` scenes and its
lessons (``*.md`` files whose name starts with a digit).

A lesson that loads has its ``[[claims]]`` run on its own scene (the model's
numbers and the picture the page shows), each in the same form:

* a false claim: ``FILE:LINE: claims[2].check: the sentence is false: "..."``,
  with the check and every value it measured;
* a check too weak to fail: ``FILE:LINE: claims[2].false_when: ...``, when
  the check still holds with the sentence made false (its ``false_when``);
* an experiment no claim speaks of is a note (``FILE:LINE: experiments[1]:
  note: ...``), not a problem.

``--no-claims`` skips the claims (they render pictures: a few seconds a lesson).

Exit status: 0 when every file is good, 1 when any has a problem or a claim fails.
"""

from __future__ import annotations

import sys
from pathlib import Path


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "check",
        help="validate scene and lesson files",
        description="Validate scene files (.toml) and lessons (.md); list every problem in every file; "
                    "run each lesson's claims on its own scene.",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="scene files, lessons, or folders of them")
    parser.add_argument("-q", "--quiet", action="store_true", help="print only the problems")
    parser.add_argument("--no-claims", action="store_true",
                        help="do not run the lessons' claims (faster: no pictures are rendered)")
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

    Every object's; parametric shapes are skipped; a mesh file was already
    sized from its header when the scene loaded, so reading it is bounded.
    """
    scene = getattr(loaded, "scene", loaded)
    if scene is None:
        return
    several = len(scene.all_objects) > 1
    for index, obj in enumerate(scene.all_objects):  # every object's mesh
        if obj.geometry.kind not in ("file", "pyvista"):
            continue
        from phonglab.render.mesh import build_mesh  # VTK: only when a scene reads a mesh
        from phonglab.scene import SceneError

        try:
            build_mesh(obj.geometry)
        except SceneError as exc:
            raise exc.located(file=str(path), field=f"objects[{index}]" if several else None) from None


def claim_report(lesson, path) -> tuple[list, list]:
    """Run a lesson's claims: (problems, notes), each a located SceneError.

    A problem is a claim whose check fails on the lesson's scene, or whose
    check still holds under its ``false_when``; a note is an experiment no
    claim speaks of.
    """
    from phonglab.accuracy.claims import check_claim, check_false_when  # VTK: only when claims run
    from phonglab.scene import SceneError
    from phonglab.scene.lessons import front_matter_lines

    lines = front_matter_lines(path)
    shown = str(path)
    problems, notes = [], []
    for claim in lesson.claims:
        where = f"claims[{claim.index}]"
        result = check_claim(lesson, claim)
        if not result.passed:
            gave = result.error or f"gave {result.value}"
            problems.append(SceneError(f'the sentence is false: "{claim.says}"', field=f"{where}.check",
                                       file=shown, line=lines.line(f"{where}.check"),
                                       hint=f"the check {claim.check} {gave} with {result.measured_text()}"))
            continue
        weak = check_false_when(lesson, claim)
        if not weak.passed:
            changed = ", ".join(f"{p} = {v}" for p, v in weak.changed)
            gave = weak.error or f"still gives {weak.value}"
            problems.append(SceneError(
                "the check cannot tell the sentence from its opposite: with the sentence made false "
                f"({changed}) it {gave}", field=f"{where}.false_when", file=shown,
                line=lines.line(f"{where}.false_when"),
                hint=f"measured {weak.measured_text()}; make the check test the sentence's own number or direction"))
    covered = {claim.experiment for claim in lesson.claims}
    for number, experiment in enumerate(lesson.experiments, start=1):
        if number not in covered:
            where = f"experiments[{number - 1}]"
            notes.append(SceneError(f'note: no claim checks what this experiment ("{experiment.label}") shows',
                                    field=where, file=shown, line=lines.line(where),
                                    hint=f"add a [[claims]] table with experiment = {number}"))
    return problems, notes


def run(args) -> int:
    from phonglab.scene import Lesson, SceneError, load

    bad_files = problems = 0
    files = expand(args.files)
    numbered: dict = {}  # (folder, lesson number) -> the first checked lesson that has it
    for path in files:
        try:
            loaded = load(path)
            _read_mesh(loaded, path)
        except SceneError as exc:
            errors = getattr(exc, "errors", [exc])
            bad_files += 1
            problems += len(errors)
            for error in errors:
                print(error)
            continue
        found, notes = [], []
        if isinstance(loaded, Lesson):
            first = numbered.setdefault((Path(path).resolve().parent, loaded.number), Path(path))
            if first != Path(path):  # two lessons of one folder under one number: the page would list both as "4 · …"
                found.append(f"{path}: number: lesson {loaded.number} is also {first.name}; "
                             "each lesson in a folder needs a number of its own")
        if isinstance(loaded, Lesson) and not args.no_claims:
            claims_found, notes = claim_report(loaded, path)
            found += claims_found
        for error in found + notes:
            print(error)
        if found:
            bad_files += 1
            problems += len(found)
        elif not args.quiet:
            claims = len(loaded.claims) if isinstance(loaded, Lesson) and not args.no_claims else 0
            print(f"ok {path}" + (f" ({claims} claim{'s' if claims != 1 else ''} hold)" if claims else ""))
    if bad_files:
        files_word = "file" if len(files) == 1 else "files"
        problem_word = "problem" if problems == 1 else "problems"
        print(f"{problems} {problem_word} in {bad_files} of {len(files)} {files_word}", file=sys.stderr)
        return 1
    return 0
