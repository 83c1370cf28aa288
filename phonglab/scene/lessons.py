"""Lessons: Markdown with a scene as TOML front matter, and the lesson list.

A lesson file's first line is ``+++``, followed by the scene as TOML (as in a
scene file, plus the lesson's keys), a closing ``+++`` line and the lesson
text. :func:`load_lesson` checks it once into a :class:`~phonglab.scene.model.Lesson`,
reporting every problem with its file and line. :func:`load_entry` reads any
lesson or scene file for the lesson list without raising: the entry keeps
the title and number the lesson has (or, for a broken file, would have) and
the problems; :func:`catalog` lists a folder's entries for the app.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from phonglab.scene.build import Problems, scene_parts
from phonglab.scene.check import build_check
from phonglab.scene.checks import check_choice, check_int, check_text, markdown_depth
from phonglab.scene.editing import settings_problems
from phonglab.scene.errors import SceneError, SceneErrors, join_path
from phonglab.scene.fieldpath import check_path_shape, field_value
from phonglab.scene.loader import display, lesson_files, load_scene, parse_toml, read_text
from phonglab.scene.model import Experiment, Lesson, Scene
from phonglab.scene.schema import (CLAIM_ABOUT, CLAIM_KEYS, CLAIM_REQUIRED, EXPERIMENT_KEYS, FALSE_WHEN_KEYS,
                                   LESSON_KEYS, MAX_NESTING)
from phonglab.scene.claims import Claim, FalseWhen, about_problem, parse_check, replaced_check, seeing_word
from phonglab.scene.toml_lines import KeyLines, render_key

#: a Markdown heading line: "# Title"
_HEADING = re.compile(r"^#\s+(.+?)\s*#*\s*$", re.MULTILINE)

#: Markdown the lesson page cannot show: pattern -> (what it is, what to do instead)
BODY_REFUSED = (
    (re.compile(r"!\[[^\]]*\]\("), "an image", "the page does not serve image files; describe it in words or "
                                             "show it with the lesson's scene"),
    (re.compile(r"<\s*(script|style|iframe|img|object|embed|form|input|link|meta)\b", re.IGNORECASE),
     "raw HTML the page does not run or show", "write it in Markdown"),
)


def body_problems(body: str, first_line: int) -> list[SceneError]:
    """What in a lesson's Markdown text the page could not show, each with its file line.

    Everything else the lessons use (headings of every level, paragraphs,
    lists, tables, code, emphasis, links, ``$...$`` and ``$$...$$`` maths)
    is rendered by the page; what it cannot render is refused here rather
    than dropped silently.
    """
    found = []
    in_code = False
    for offset, line in enumerate(body.splitlines()):
        if line.lstrip().startswith("```"):
            in_code = not in_code
        if in_code or line.startswith("    "):
            continue  # code is shown as written
        for pattern, what, instead in BODY_REFUSED:
            match = pattern.search(line)
            if match:
                found.append(SceneError(f"{what} cannot be shown in the lesson text", field="text",
                                        value=line.strip()[:60], hint=instead, line=first_line + offset))
    text = re.sub(r"```.*?```", "", body, flags=re.DOTALL)
    if len(re.findall(r"(?<!\\)\$\$", text)) % 2:
        found.append(SceneError("a display formula opened with $$ is never closed", field="text",
                                hint="close it with $$, or write \\$ for a dollar sign", line=first_line))
    return found


def split_front_matter(text: str, shown: str) -> tuple[str, str, int]:
    """Split a lesson into (front matter TOML, Markdown body, line of the front matter's first line).

    Raises
    ------
    SceneErrors
        When the file does not start with a ``+++`` line or the front matter
        is never closed.
    """
    lines = text.lstrip("\ufeff").splitlines(keepends=True)
    if not lines or lines[0].strip() != "+++":
        got = lines[0].strip() if lines else ""
        raise SceneErrors(
            [
                SceneError(
                    "a lesson must start with TOML front matter between two +++ lines",
                    file=shown,
                    line=1,
                    value=got[:40] if got else "an empty file",
                )
            ]
        )
    for i in range(1, len(lines)):
        if lines[i].strip() == "+++":
            return "".join(lines[1:i]), "".join(lines[i + 1 :]), 2
    raise SceneErrors(
        [SceneError("the front matter opened by +++ on line 1 is never closed by a +++ line", file=shown, line=1)]
    )


def front_matter_lines(path) -> KeyLines:
    """The file line of every key of a lesson's front matter (``claims[2].check`` -> 57), for reports.

    Raises
    ------
    SceneErrors
        When the file cannot be read or has no front matter.
    """
    shown = display(path)
    front, _, first = split_front_matter(read_text(path, shown), shown)
    return KeyLines(front, first)


def number_from_name(path) -> int | None:
    """A lesson's default number: the file name's leading digits (``07-diffuse.md`` is 7), else None."""
    digits = re.match(r"\d+", Path(path).name)
    return int(digits.group()) if digits else None


def title_from_body(body: str) -> str | None:
    """A lesson's default title: the text's first ``#`` heading, else None."""
    heading = _HEADING.search(body)
    return heading.group(1) if heading else None


@dataclass
class _Reading:
    """What reading a lesson file gave: the lesson if it is sound, its title and number, every problem."""

    lesson: Lesson | None = None
    title: str = ""
    number: int | None = None
    errors: list = field(default_factory=list)


def _read_lesson(path) -> _Reading:
    """Read and check a lesson, collecting every problem (located) instead of raising."""
    shown = display(path)
    reading = _Reading(number=number_from_name(path))
    try:
        text = read_text(path, shown)
        front, body, first = split_front_matter(text, shown)
        reading.title = title_from_body(body) or ""
        data = parse_toml(front, shown, first)
        _check_markdown(body, shown, first + front.count("\n") + 2)
    except SceneErrors as exc:
        reading.errors = list(exc.errors)
        return reading
    problems = Problems()
    for error in body_problems(body, first + len(front.splitlines()) + 1):
        problems.add(error)
    parts = scene_parts(data, problems, extra_keys=LESSON_KEYS, base_dir=Path(path).resolve().parent)
    scene = Scene(source=os.fspath(path), **parts) if parts is not None else None

    # lesson keys
    number = data.get("number")
    if number is None:
        if reading.number is None:
            problems.add(SceneError("is required when the file name does not start with the lesson number", field="number"))
    else:
        number = problems.run(check_int, "number", number, low=0)
        reading.number = number if number is not None else reading.number
    title = data.get("title")
    if title is None:
        if not reading.title:
            problems.add(SceneError("is required when the text has no # heading", field="title"))
    elif isinstance(title, str):  # a title that is not text is the scene's problem (SCENE_KEYS)
        reading.title = title
    texts = {}
    for key in ("goal", "question", "answer"):
        texts[key] = problems.run(check_text, key, data.get(key, "")) or ""
        if markdown_depth(texts[key])[0] > MAX_NESTING:  # shown as Markdown too
            problems.add(SceneError(f"nests lists or quotes past {MAX_NESTING} levels", field=key))
            texts[key] = ""
    mistake = data.get("mistake")
    if mistake is not None:
        # imported here: only a lesson naming a mistake needs the teaching layer loaded
        from phonglab.teaching.mistakes import MISTAKES

        mistake = problems.run(check_choice, "mistake", mistake, tuple(MISTAKES))
    check = build_check(data["check"], problems, question=texts["question"]) if "check" in data else None
    controls = _build_controls(data.get("controls", []), scene, problems)
    experiments = []
    raw_experiments = data.get("experiments", [])
    if not isinstance(raw_experiments, list):
        problems.add(SceneError("must be a list of [[experiments]] tables", field="experiments", value=raw_experiments))
        raw_experiments = []
    for i, item in enumerate(raw_experiments):
        experiment = _build_experiment(item, f"experiments[{i}]", scene, problems)
        if experiment is not None:
            experiments.append(experiment)
    claims = _build_claims(data.get("claims", []), scene, experiments, len(raw_experiments), problems)

    try:
        problems.raise_all(file=shown, lines=KeyLines(front, first))
    except SceneErrors as exc:
        reading.errors = list(exc.errors)
        return reading
    reading.lesson = Lesson(
        path=os.fspath(path),
        number=reading.number,
        title=reading.title,
        goal=texts["goal"],
        scene=scene,
        body=body,
        controls=tuple(controls),
        experiments=tuple(experiments),
        question=texts["question"],
        answer=texts["answer"],
        mistake=mistake,
        claims=tuple(claims),
        check=check,
    )
    return reading


def _check_markdown(body: str, shown: str, first_line: int) -> None:
    """Refuse a lesson text whose lists or quotes nest past MAX_NESTING (the Markdown renderer recurses)."""
    depth, line = markdown_depth(body)
    if depth > MAX_NESTING:
        raise SceneErrors([SceneError(f"nests lists or quotes {depth} deep, at most {MAX_NESTING} allowed",
                                      file=shown, line=first_line + line - 1)])


def load_lesson(path) -> Lesson:
    """Load and check a lesson: Markdown with the scene as TOML front matter.

    The front matter holds a scene (as in a scene file) and the lesson's
    keys: ``number`` (default: the file name's leading digits), ``goal``,
    ``controls`` (field paths), ``[[experiments]]`` with ``label``, ``text``
    and ``set = {"material.shininess" = 10}``, ``question``, ``answer``,
    ``mistake`` and an answerable ``[check]`` (:mod:`phonglab.scene.check`). ``title`` defaults to the body's first ``#`` heading.

    Raises
    ------
    SceneErrors
        Every problem in the file, located.
    """
    reading = _read_lesson(path)
    if reading.errors:
        raise SceneErrors(reading.errors)
    return reading.lesson


def _build_controls(raw, scene: Scene | None, problems: Problems) -> list[str]:
    """The lesson's control paths, each naming a field of its scene."""
    if not isinstance(raw, list):
        problems.add(SceneError("must be a list of field paths", field="controls", value=raw))
        return []
    controls = []
    for i, control in enumerate(raw):
        where = f"controls[{i}]"
        if problems.run(check_text, where, control) is None:
            continue
        try:
            if scene is not None:
                field_value(scene, control)
            else:
                check_path_shape(control)
        except SceneError as exc:
            problems.add(SceneError(exc.problem, field=where, value=control, hint=exc.hint))
            continue
        controls.append(control)
    return controls


def _flatten(table: dict, prefix: str = "") -> list[tuple[str, object]]:
    """``{"material": {"ks": 0}}`` and ``{"material.ks": 0}`` both give ``[("material.ks", 0)]``."""
    out = []
    for key, value in table.items():
        path = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            out.extend(_flatten(value, path))
        else:
            out.append((path, value))
    return out


def _build_experiment(item, where: str, scene: Scene | None, problems: Problems) -> Experiment | None:
    table = problems.table(where, item, EXPERIMENT_KEYS, required=("label",))
    if table is None:
        return None
    label = problems.run(check_text, join_path(where, "label"), table.get("label", ""))
    text = problems.run(check_text, join_path(where, "text"), table.get("text", ""))
    raw = table.get("set", {})
    if not isinstance(raw, dict):
        problems.add(SceneError('must be a table of field paths and values, e.g. {"material.ks" = 0}', field=join_path(where, "set"), value=raw))
        return None
    settings = _flatten(raw)
    ok = label is not None and text is not None
    # the settings, applied together to the lesson's scene, must give a valid scene
    set_path = join_path(where, "set")
    if scene is None:  # the scene is broken: check the paths alone
        found = []
        for path, _ in settings:
            try:
                check_path_shape(path)
            except SceneError as exc:
                found.append((path, exc))
    else:
        found = settings_problems(scene, settings)
    for culprit, error in found:
        ok = False
        for one in getattr(error, "errors", [error]):
            problems.add(
                SceneError(
                    (f"{one.field}: " if one.field and one.field != culprit else "") + one.problem,
                    field=join_path(set_path, render_key(culprit)) if culprit else set_path,
                    value=one.value,
                    hint=one.hint,
                )
            )
    return Experiment(label=label, text=text, settings=tuple(settings)) if ok else None


def _claim_settings(raw_set, base: Scene | None, where: str, problems: Problems) -> list | None:
    """A claim's (or its ``false_when``'s) ``set`` table as settings checked on ``base``; None if refused."""
    if not isinstance(raw_set, dict):
        problems.add(SceneError('must be a table of field paths and values, e.g. {"material.ks" = 0}',
                                field=where, value=raw_set))
        return None
    settings = _flatten(raw_set)
    found = settings_problems(base, settings) if base is not None else []
    for culprit, error in found:
        for one in getattr(error, "errors", [error]):
            problems.add(SceneError(one.problem, value=one.value, hint=one.hint,
                                    field=join_path(where, render_key(culprit)) if culprit else where))
    return None if found else settings


def _build_false_when(raw, base: Scene | None, check: str | None, where: str, problems: Problems):
    """A claim's ``false_when``: settings and/or a replacement in the check, under which the check must fail."""
    table = problems.table(where, raw, FALSE_WHEN_KEYS)
    if table is None:
        return None
    if not table:
        problems.add(SceneError("must change something: a set table, a replace pair, or both", field=where,
                                value=raw, hint='e.g. { replace = ["0.35", "0.45"] } or { set = { "exposure" = 1 } }'))
        return None
    settings = ()
    if "set" in table:
        found = _claim_settings(table["set"], base, join_path(where, "set"), problems)
        if found is None:
            return None
        settings = tuple(found)
    replace = table.get("replace")
    if replace is not None:
        at = join_path(where, "replace")
        if not (isinstance(replace, list) and len(replace) == 2 and all(isinstance(t, str) and t for t in replace)
                and replace[0] != replace[1]):
            problems.add(SceneError("must be two different, non-empty texts: what to replace in the check and "
                                    "what replaces it", field=at, value=replace))
            return None
        if check is None:
            return None
        if replace[0] not in check:
            problems.add(SceneError("the text to replace is not in the check", field=at, value=replace[0],
                                    hint=f"the check is {check.strip()!r}"))
            return None
        try:
            parse_check(replaced_check(check, tuple(replace)))
        except SceneError as exc:
            problems.add(SceneError(f"the check with the replacement {exc.problem}", field=at, value=exc.value,
                                    hint=exc.hint))
            return None
        replace = tuple(replace)
    return FalseWhen(settings=settings, replace=replace)


def _build_claims(raw, scene: Scene | None, experiments: list, n_experiments: int, problems: Problems) -> list[Claim]:
    """The lesson's ``[[claims]]``: sentence, kind, check expression, the settings they are checked under
    and the change that must make the check fail."""
    if not isinstance(raw, list):
        problems.add(SceneError("must be a list of [[claims]] tables", field="claims", value=raw))
        return []
    claims = []
    for i, item in enumerate(raw):
        where = f"claims[{i}]"
        table = problems.table(where, item, CLAIM_KEYS, required=CLAIM_REQUIRED)
        if table is None:
            continue
        says = problems.run(check_text, join_path(where, "says"), table.get("says", ""))
        about = problems.run(check_choice, join_path(where, "about"), table["about"], CLAIM_ABOUT) \
            if "about" in table else None
        check = table.get("check")
        try:
            tree = parse_check(check)
        except SceneError as exc:
            problems.add(SceneError(exc.problem, field=join_path(where, "check"), value=exc.value, hint=exc.hint))
            check = tree = None
        if about is not None and tree is not None:
            wrong = about_problem(about, tree)
            if wrong:
                problems.add(SceneError(wrong, field=join_path(where, "about"), value=about))
                about = None
        if about == "model" and says and seeing_word(says):
            problems.add(SceneError("the sentence says what the student sees, so it must be checked on the picture",
                                    field=join_path(where, "about"), value=about,
                                    hint=f'"{seeing_word(says)}" is about the picture: say about = "picture" and '
                                         "measure it with shown_*, or word the sentence as the model's numbers"))
            about = None
        number = table.get("experiment")
        base = scene
        if number is not None:
            number = problems.run(check_int, join_path(where, "experiment"), number, low=1)
            if number is not None and number > n_experiments:
                problems.add(SceneError(f"must name one of the lesson's {n_experiments} experiments (from 1)",
                                        field=join_path(where, "experiment"), value=number))
                number = None
            elif number is not None and scene is not None and len(experiments) == n_experiments:
                base = scene.replace_many(experiments[number - 1].settings)
        settings = _claim_settings(table.get("set", {}), base, join_path(where, "set"), problems)
        false_when = None
        if "false_when" in table:
            own = base.replace_many(settings) if base is not None and settings else base
            false_when = _build_false_when(table["false_when"], own, check, join_path(where, "false_when"),
                                           problems)
        if None not in (says, about, check, settings, false_when) and (number is not None
                                                                       or "experiment" not in table):
            claims.append(Claim(says=says, check=check.strip(), about=about, false_when=false_when,
                                experiment=number, settings=tuple(settings), index=i))
    return claims


def load(path) -> Scene | Lesson:
    """Load a scene (``.toml``) or a lesson (``.md``), by extension.

    Raises
    ------
    SceneErrors
        Every problem in the file, or an unknown extension.
    """
    suffix = Path(path).suffix.lower()
    if suffix == ".toml":
        return load_scene(path)
    if suffix in (".md", ".markdown"):
        return load_lesson(path)
    raise SceneErrors(
        [SceneError("must be a scene file (.toml) or a lesson (.md)", file=display(path), value=suffix or "no extension")]
    )


def list_lessons(folder) -> list[Lesson]:
    """Load every lesson in ``folder`` (see :func:`lesson_files`), ordered by number.

    Raises
    ------
    SceneErrors
        Every problem in every lesson file.
    """
    lessons, errors = [], []
    for path in lesson_files(folder):
        try:
            lessons.append(load_lesson(path))
        except SceneErrors as exc:
            errors.extend(exc.errors)
    if errors:
        raise SceneErrors(errors)
    return sorted(lessons, key=lambda lesson: (lesson.number, lesson.path))


# ---------------------------------------------------------------------------
# the lesson list


def title_from_name(path) -> str:
    """A title made from a file name, for a file that gives none: ``02-broken-one.md`` is "Broken one"."""
    path = Path(path)
    stem = path.stem.split("-", 1)[-1] if "-" in path.stem else path.stem
    return stem.replace("-", " ").replace("_", " ").capitalize()


@dataclass
class Entry:
    """One item of the lesson list: a lesson or scene file, loaded or not.

    Attributes
    ----------
    path : Path
    number : int or None
        The lesson's number (as :func:`load_lesson` determines it, also for a
        broken lesson); None for a scene file or a file with no number.
    title : str
        The lesson's title, the scene's title or stem, or one made from the
        file name when the file gives none.
    lesson : Lesson or None
        None for a scene file or a broken lesson.
    scene : Scene or None
        None for a broken file.
    errors : list of str
        Every problem, one ``FILE:LINE: field: problem`` line each.
    """

    path: Path
    number: int | None = None
    title: str = ""
    lesson: Lesson | None = None
    scene: Scene | None = None
    errors: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """Whether the file gave a scene without problems."""
        return self.scene is not None and not self.errors


def load_entry(path) -> Entry:
    """Read a lesson (``.md``) or scene (``.toml``) file for the lesson list; problems go into ``errors``."""
    entry = Entry(path=Path(path))
    if entry.path.suffix.lower() == ".toml":
        try:
            entry.scene = load_scene(entry.path)
            entry.title = entry.scene.title or entry.path.stem
        except SceneError as exc:
            entry.errors = [str(e) for e in getattr(exc, "errors", [exc])]
    else:
        reading = _read_lesson(entry.path)
        entry.lesson, entry.title, entry.number = reading.lesson, reading.title, reading.number
        entry.scene = reading.lesson.scene if reading.lesson is not None else None
        entry.errors = [str(e) for e in reading.errors]
    entry.title = entry.title or title_from_name(entry.path)
    return entry


def catalog(target) -> tuple[list[Entry], int]:
    """The lesson list for ``target`` and the index to open first.

    ``target`` is a folder of lessons, a lesson file (its folder's lessons are
    listed, it opens first) or a scene file (listed alone).
    """
    target = Path(target)
    if target.is_dir():
        return [load_entry(p) for p in lesson_files(target)], 0
    if target.suffix.lower() == ".toml":
        return [load_entry(target)], 0
    files = lesson_files(target.parent)
    if target.resolve() not in [p.resolve() for p in files]:
        files = [target] + files
    entries = [load_entry(p) for p in files]
    first = next(i for i, e in enumerate(entries) if e.path.resolve() == target.resolve())
    return entries, first
