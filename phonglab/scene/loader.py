"""Read scene files (TOML) and lessons (Markdown with TOML front matter).

A scene file is TOML read with :mod:`tomllib`; a lesson is Markdown whose
first line is ``+++``, followed by the scene as TOML, a closing ``+++`` line
and the lesson text. Both are checked once, here, into the frozen
dataclasses of :mod:`phonglab.scene.model` and the core's ``Material`` and
lights. Every problem found is reported, not only the first: loading raises
:class:`~phonglab.scene.model.SceneErrors` listing each one as
``FILE:LINE: field.path: what is allowed, got VALUE``.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from pathlib import Path

from phonglab import core
from phonglab.scene import paths
from phonglab.scene.model import (
    AreaLightSetup,
    GEOMETRY_KINDS,
    INTERPOLATIONS,
    MODELS,
    RESOLUTION_RANGE,
    Camera,
    Experiment,
    Geometry,
    Lesson,
    Scene,
    SceneError,
    SceneErrors,
    check_bool,
    check_choice,
    check_int,
    check_number,
    check_text,
    check_vector,
    did_you_mean,
    join_path,
)
from phonglab.scene.toml_lines import KeyLines, render_key

# ---------------------------------------------------------------------------
# the file format: which keys each table allows

#: keys of a scene file's top level
SCENE_KEYS = ("title", "model", "interpolation", "two_sided", "probe", "geometry", "material", "lights", "camera",
              "area_light")
#: further top-level keys of a lesson's front matter
LESSON_KEYS = ("number", "goal", "controls", "experiments", "question", "answer", "mistake")
GEOMETRY_KEYS = ("kind", "resolution", "name", "path")
MATERIAL_KEYS = ("ka", "kd", "ks", "shininess", "emission", "opacity")
MATERIAL_REQUIRED = ("ka", "kd", "ks", "shininess")
CAMERA_KEYS = ("eye", "focal_point", "up", "view_angle", "infinite_viewer")
#: the [area_light] table: the core AreaLight's fields, then how it is evaluated
AREA_LIGHT_KEYS = ("position", "edge_u", "edge_v", "color", "intensity", "method", "samples")
EXPERIMENT_KEYS = ("label", "text", "set")
#: light type -> keys allowed in its table (besides "type")
LIGHT_KEYS = {
    "ambient": ("color", "intensity"),
    "point": ("position", "color", "intensity", "diffuse", "specular", "attenuation"),
    "directional": ("direction", "color", "intensity", "diffuse", "specular"),
    "spot": ("position", "direction", "cutoff", "exponent", "color", "intensity", "diffuse", "specular", "attenuation"),
}
#: keys a light table must have, by type
LIGHT_REQUIRED = {"ambient": (), "point": ("position",), "directional": ("direction",), "spot": ("position", "direction")}
#: keys allowed next to ``homogeneous = [x, y, z, w]`` (type then follows from w)
HOMOGENEOUS_KEYS = ("type", "homogeneous", "color", "intensity", "diffuse", "specular", "attenuation")
#: light type -> core class
LIGHT_CLASSES = {
    "ambient": core.AmbientLight,
    "point": core.PointLight,
    "directional": core.DirectionalLight,
    "spot": core.SpotLight,
}
#: fields holding a colour: a number or an RGB list, each >= 0
COLOR_FIELDS = ("ka", "kd", "ks", "emission", "color", "diffuse", "specular")

_RGB_RULE = "must be a finite number >= 0 or a list of 3 of them (RGB)"


def light_type(light) -> str:
    """The file-format type name of a core light ("spot", "point", ...)."""
    for name in ("spot", "point", "directional", "ambient"):  # SpotLight is a PointLight: test it first
        if isinstance(light, LIGHT_CLASSES[name]):
            return name
    raise TypeError(f"not a phonglab light: {light!r}")


# ---------------------------------------------------------------------------
# value checks specific to the file format


def check_rgb(path, value):
    """A colour: a number or 3 numbers, each finite and >= 0."""
    if isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise SceneError(_RGB_RULE, field=path, value=value, hint=f"{len(value)} given")
        ok = all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v >= 0 for v in value)
        if not ok:
            raise SceneError(_RGB_RULE, field=path, value=value)
        return tuple(float(v) for v in value)
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value >= 0:
        return float(value)
    raise SceneError(_RGB_RULE, field=path, value=value)


def check_homogeneous(path, value):
    """``[x, y, z, w]``: four finite numbers with w >= 0 (w = 0 a directional light)."""
    rule = "must be a list of 4 finite numbers [x, y, z, w] with w >= 0 (w = 0 directional, w = 1 point)"
    if not isinstance(value, (list, tuple)):
        raise SceneError(rule, field=path, value=value)
    if len(value) != 4:
        raise SceneError(rule, field=path, value=value, hint=f"{len(value)} given")
    ok = all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    if not ok or value[3] < 0 or not any(value[:3]) and value[3] == 0:
        raise SceneError(rule, field=path, value=value)
    return tuple(float(v) for v in value)


#: light field -> check(path, value), before the core's own validation
LIGHT_CHECKS = {
    "position": check_vector,
    "direction": lambda p, v: check_vector(p, v, nonzero=True),
    "color": check_rgb,
    "diffuse": check_rgb,
    "specular": check_rgb,
    "intensity": lambda p, v: check_number(p, v, low=0),
    "attenuation": lambda p, v: check_vector(p, v),
    "cutoff": lambda p, v: check_number(p, v, low=0, low_open=True),
    "exponent": lambda p, v: check_number(p, v, low=0),
    "homogeneous": check_homogeneous,
}
MATERIAL_CHECKS = {
    "ka": check_rgb,
    "kd": check_rgb,
    "ks": check_rgb,
    "emission": check_rgb,
    "shininess": lambda p, v: check_number(p, v, low=0),
    "opacity": lambda p, v: check_number(p, v, low=0, high=1),
}


class _Problems:
    """Collects SceneErrors while a file is checked."""

    def __init__(self):
        self.errors: list[SceneError] = []

    def add(self, error: SceneError) -> None:
        if isinstance(error, SceneErrors):
            self.errors.extend(error.errors)
        else:
            self.errors.append(error)

    def run(self, fn, *args, **kwargs):
        """``fn(*args)``, or None after recording its SceneError."""
        try:
            return fn(*args, **kwargs)
        except SceneError as exc:
            self.add(exc)
            return None

    def table(self, path, value, allowed, *, required=(), why="") -> dict | None:
        """Check that ``value`` is a table with only ``allowed`` keys and the ``required`` ones."""
        if not isinstance(value, dict):
            self.add(SceneError("must be a table", field=path, value=value))
            return None
        for key in value:
            if key not in allowed:
                hint = did_you_mean(key, allowed)
                listing = "allowed: " + ", ".join(allowed)
                self.add(
                    SceneError(
                        "unknown key",
                        field=join_path(path, render_key(key)),
                        hint=f"{hint} ({listing})" if hint else listing,
                    )
                )
        for key in required:
            if key not in value:
                self.add(SceneError("is required" + why, field=join_path(path, key)))
        return value


def _core_error(exc: ValueError, table_path: str, given: dict) -> SceneError:
    """A core ValueError raised while building a material or light, as a SceneError."""
    name = getattr(exc, "field", "") or ""
    key = name.rsplit(".", 1)[-1] if name else ""
    if key not in given:  # find the key the message is about
        key = next((k for k in given if re.search(rf"\b{re.escape(k)}\b", str(exc))), "")
    allowed = getattr(exc, "allowed", None)
    path = join_path(table_path, key) if key else table_path
    if allowed is not None:
        return SceneError(allowed, field=path, value=given.get(key, getattr(exc, "value", None)))
    return SceneError(str(exc), field=path)


# ---------------------------------------------------------------------------
# building the parts of a scene


def build_geometry(data, problems: _Problems, base_dir=None) -> Geometry | None:
    table = problems.table("geometry", data, GEOMETRY_KEYS, required=("kind",))
    if table is None or "kind" not in table:
        return None
    kind = problems.run(check_choice, "geometry.kind", table["kind"], GEOMETRY_KINDS)
    resolution = problems.run(
        check_int, "geometry.resolution", table.get("resolution", 48), low=RESOLUTION_RANGE[0], high=RESOLUTION_RANGE[1]
    )
    name, path = table.get("name"), table.get("path")
    if kind is None or resolution is None:
        return None
    try:
        name, path = paths.check_geometry_source(kind, name, path, base_dir)
    except SceneError as exc:
        problems.add(exc.located(field="geometry"))
        return None
    return problems.run(Geometry, kind, resolution, name, path)


def build_material(data, problems: _Problems, path="material"):
    table = problems.table(path, data, MATERIAL_KEYS, required=MATERIAL_REQUIRED)
    if table is None:
        return None
    values, ok = {}, True
    for key, value in table.items():
        if key in MATERIAL_CHECKS:
            checked = problems.run(MATERIAL_CHECKS[key], join_path(path, key), value)
            ok &= checked is not None
            values[key] = checked
    if not ok or any(k not in table for k in MATERIAL_REQUIRED) or len(values) != len(table):
        return None
    try:
        return core.Material(**values)
    except ValueError as exc:
        problems.add(_core_error(exc, path, table))
        return None


def build_light(data, problems: _Problems, path: str):
    if not isinstance(data, dict):
        problems.add(SceneError("must be a table", field=path, value=data))
        return None
    homogeneous = "homogeneous" in data
    kind = data.get("type")
    if homogeneous:
        # type follows from w; a given type must agree with it
        for key in ("position", "direction"):
            if key in data:
                problems.add(
                    SceneError(
                        "cannot be given next to homogeneous = [x, y, z, w], which already places the light",
                        field=join_path(path, key),
                        value=data[key],
                    )
                )
        table = problems.table(path, {k: v for k, v in data.items() if k not in ("position", "direction")}, HOMOGENEOUS_KEYS)
        w_type = None
        hom = problems.run(check_homogeneous, join_path(path, "homogeneous"), data["homogeneous"])
        if hom is not None:
            w_type = "directional" if hom[3] == 0 else "point"
        if kind is not None and kind != w_type and w_type is not None:
            problems.add(
                SceneError(
                    f'must be "{w_type}" or left out: homogeneous w = {hom[3]:g} makes a {w_type} light',
                    field=join_path(path, "type"),
                    value=kind,
                )
            )
            return None
        if w_type == "directional" and "attenuation" in data:
            problems.add(
                SceneError(
                    "is not allowed: homogeneous w = 0 makes a directional light, which has no distance",
                    field=join_path(path, "attenuation"),
                    value=data["attenuation"],
                )
            )
            return None
        if table is None or hom is None:
            return None
        allowed_keys = HOMOGENEOUS_KEYS
    else:
        if kind is None:
            problems.add(
                SceneError(
                    "is required: one of " + ", ".join(f'"{t}"' for t in LIGHT_KEYS) + " (or give homogeneous = [x, y, z, w])",
                    field=join_path(path, "type"),
                )
            )
            return None
        kind = problems.run(check_choice, join_path(path, "type"), kind, tuple(LIGHT_KEYS))
        if kind is None:
            return None
        allowed_keys = ("type",) + LIGHT_KEYS[kind]
        if problems.table(path, data, allowed_keys, required=LIGHT_REQUIRED[kind], why=f" for a {kind} light") is None:
            return None
    values, ok = {}, True
    for key, value in data.items():
        if key == "type" or key not in allowed_keys:
            ok &= key == "type"
            continue
        if key == "homogeneous":  # checked above
            values[key] = hom
            continue
        checked = problems.run(LIGHT_CHECKS[key], join_path(path, key), value)
        ok &= checked is not None
        values[key] = checked
    if not ok or (not homogeneous and any(k not in data for k in LIGHT_REQUIRED[kind])):
        return None
    try:
        if homogeneous:
            position = values.pop("homogeneous")
            return core.light_from_homogeneous(position, **values)
        return LIGHT_CLASSES[kind](**values)
    except ValueError as exc:
        problems.add(_core_error(exc, path, data))
        return None


def build_camera(data, problems: _Problems) -> Camera | None:
    table = problems.table("camera", data, CAMERA_KEYS)
    if table is None or any(k not in CAMERA_KEYS for k in table):
        return None
    try:
        return Camera(**table)
    except SceneError as exc:
        problems.add(exc.located(field="camera"))
        return None


def build_area_light(data, problems: _Problems, path="area_light") -> AreaLightSetup | None:
    table = problems.table(path, data, AREA_LIGHT_KEYS, required=("position",))
    if table is None or "position" not in table:
        return None
    light_keys = {k: v for k, v in table.items() if k not in ("method", "samples")}
    try:
        light = core.AreaLight(**light_keys)
    except ValueError as exc:
        problems.add(_core_error(exc, path, light_keys))
        return None
    options = {k: table[k] for k in ("method", "samples") if k in table}
    return problems.run(AreaLightSetup, light, **options)


def _build_scene(data: dict, problems: _Problems, *, extra_keys=(), source=None, base_dir=None) -> Scene | None:
    """Check a parsed scene table; record problems and return the Scene if there were none."""
    start = len(problems.errors)
    problems.table("", data, SCENE_KEYS + tuple(extra_keys), required=("geometry", "material"))
    geometry = build_geometry(data["geometry"], problems, base_dir) if "geometry" in data else None
    material = build_material(data["material"], problems) if "material" in data else None
    lights = []
    raw_lights = data.get("lights", [])
    if not isinstance(raw_lights, list):
        problems.add(SceneError("must be a list of [[lights]] tables", field="lights", value=raw_lights))
    else:
        for i, item in enumerate(raw_lights):
            lights.append(build_light(item, problems, f"lights[{i}]"))
    camera = build_camera(data.get("camera", {}), problems)
    options = {}
    if "area_light" in data:
        options["area_light"] = build_area_light(data["area_light"], problems)
    for key, check in (
        ("model", lambda p, v: check_choice(p, v, MODELS)),
        ("interpolation", lambda p, v: check_choice(p, v, INTERPOLATIONS)),
        ("two_sided", check_bool),
        ("probe", check_vector),
        ("title", check_text),
    ):
        if key in data:
            value = problems.run(check, key, data[key])
            if value is not None:
                options[key] = value
    if len(problems.errors) > start:
        return None
    return problems.run(Scene, geometry, material, tuple(lights), camera, source=source, **options)


def _raise(problems: _Problems, *, file=None, lines: KeyLines | None = None) -> None:
    """Raise the collected problems, each with its file and line, ordered by line."""
    if not problems.errors:
        return
    located = [e.located(file=file, line=lines.line(e.field) if lines else None) for e in problems.errors]
    located.sort(key=lambda e: e.line or 0)
    raise SceneErrors(located)


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
    problems = _Problems()
    scene = _build_scene(data, problems, source=source, base_dir=base_dir)
    if len(problems.errors) == 1:
        raise problems.errors[0]
    _raise(problems)
    return scene


# ---------------------------------------------------------------------------
# files


def _display(path) -> str:
    """The file name for messages: as the caller gave it."""
    return os.fspath(path)


def _read_text(path, shown) -> str:
    try:
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneErrors([SceneError("no such file", file=shown)]) from None
    except IsADirectoryError:
        raise SceneErrors([SceneError("is a folder, not a scene or lesson file", file=shown)]) from None
    except UnicodeDecodeError as exc:
        raise SceneErrors([SceneError(f"is not UTF-8 text ({exc.reason} at byte {exc.start})", file=shown)]) from None
    except OSError as exc:
        raise SceneErrors([SceneError(f"cannot be read: {exc.strerror}", file=shown)]) from None


def _parse_toml(text: str, shown: str, first_line: int = 1) -> dict:
    """tomllib.loads, with a syntax error turned into a located SceneError."""
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
    shown = _display(path)
    text = _read_text(path, shown)
    data = _parse_toml(text, shown)
    problems = _Problems()
    scene = _build_scene(data, problems, source=os.fspath(path), base_dir=Path(path).resolve().parent)
    _raise(problems, file=shown, lines=KeyLines(text))
    return scene


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


def load_lesson(path) -> Lesson:
    """Load and check a lesson: Markdown with the scene as TOML front matter.

    The front matter holds a scene (as in a scene file) and the lesson's
    keys: ``number`` (default: the file name's leading digits), ``goal``,
    ``controls`` (field paths), ``[[experiments]]`` with ``label``, ``text``
    and ``set = {"material.shininess" = 10}``, ``question``, ``answer`` and
    ``mistake``. ``title`` defaults to the body's first ``#`` heading.

    Raises
    ------
    SceneErrors
        Every problem in the file, located.
    """
    from phonglab.scene.fieldpath import check_path_shape, field_value

    shown = _display(path)
    text = _read_text(path, shown)
    front, body, first = split_front_matter(text, shown)
    data = _parse_toml(front, shown, first)
    lines = KeyLines(front, first)
    problems = _Problems()
    scene = _build_scene(
        data, problems, extra_keys=LESSON_KEYS, source=os.fspath(path), base_dir=Path(path).resolve().parent
    )

    # lesson keys
    number = data.get("number")
    if number is None:
        digits = re.match(r"\d+", Path(path).name)
        if digits:
            number = int(digits.group())
        else:
            problems.add(SceneError("is required when the file name does not start with the lesson number", field="number"))
    else:
        number = problems.run(check_int, "number", number, low=0)
    title = data.get("title")
    if title is None:
        heading = re.search(r"^#\s+(.+?)\s*#*\s*$", body, re.MULTILINE)
        title = heading.group(1) if heading else ""
        if not heading:
            problems.add(SceneError("is required when the text has no # heading", field="title"))
    texts = {}
    for key in ("goal", "question", "answer"):
        texts[key] = problems.run(check_text, key, data.get(key, "")) or ""
    mistake = data.get("mistake")
    if mistake is not None:
        from phonglab.teaching.mistakes import MISTAKES  # NumPy-only; no cycle back to scene

        mistake = problems.run(check_choice, "mistake", mistake, tuple(MISTAKES))

    controls = []
    raw_controls = data.get("controls", [])
    if not isinstance(raw_controls, list):
        problems.add(SceneError("must be a list of field paths", field="controls", value=raw_controls))
        raw_controls = []
    for i, control in enumerate(raw_controls):
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

    experiments = []
    raw_experiments = data.get("experiments", [])
    if not isinstance(raw_experiments, list):
        problems.add(SceneError("must be a list of [[experiments]] tables", field="experiments", value=raw_experiments))
        raw_experiments = []
    for i, item in enumerate(raw_experiments):
        experiment = _build_experiment(item, f"experiments[{i}]", scene, problems)
        if experiment is not None:
            experiments.append(experiment)

    _raise(problems, file=shown, lines=lines)
    return Lesson(
        path=os.fspath(path),
        number=number,
        title=title,
        goal=texts["goal"],
        scene=scene,
        body=body,
        controls=tuple(controls),
        experiments=tuple(experiments),
        question=texts["question"],
        answer=texts["answer"],
        mistake=mistake,
    )


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


def _build_experiment(item, where: str, scene: Scene | None, problems: _Problems) -> Experiment | None:
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
    from phonglab.scene.fieldpath import check_path_shape, settings_problems

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
        [SceneError("must be a scene file (.toml) or a lesson (.md)", file=_display(path), value=suffix or "no extension")]
    )


def lesson_files(folder) -> list[Path]:
    """The lesson files in ``folder``: ``*.md`` whose name starts with a digit, sorted."""
    found = [p for p in Path(folder).glob("*.md") if p.name[:1].isdigit()]
    return sorted(found, key=lambda p: (int(re.match(r"\d+", p.name).group()), p.name))


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
