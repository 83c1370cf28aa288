"""Build the parts of a scene from its table form, collecting every problem.

A scene's table form is what its TOML file parses to (or what
:func:`phonglab.scene.fieldpath.scene_to_dict` gives). :func:`scene_parts`
checks it once and returns the keyword arguments of a ``Scene``; every
problem found is recorded with its field path (``lights[1].position``), so the
loader can add the file and line and report them all at once.

Who checks what, once:

* table keys (unknown, required) and the TOML shape of values: here;
* material, light and area-light values: the core (``core.Material``, the
  lights, ``core.AreaLight``), whose :class:`~phonglab.core.InvalidValue`
  names the field it refused, mapped here to the file's field path;
* geometry, camera and area-light options: their constructors in
  :mod:`phonglab.scene.parts`;
* mesh files on disk: here, once, through :func:`phonglab.scene.paths.find_mesh_file`;
* the scene's options (model, interpolation, ...): here; ``Scene`` trusts them.
"""

from __future__ import annotations

import dataclasses

from phonglab import core
from phonglab.scene.checks import check_bool, check_choice, check_number, check_shape, check_text, check_vector
from phonglab.scene.errors import SceneError, SceneErrors, did_you_mean, join_path
from phonglab.scene.limits import check_light_count, check_limits
from phonglab.scene.objects import SceneObject, check_object_count, check_total_triangles
from phonglab.scene.parts import AreaLightSetup, Camera, Geometry
from phonglab.scene.paths import find_mesh_file
from phonglab.scene.schema import (
    AREA_LIGHT_KEYS,
    CAMERA_KEYS,
    CORE_FIELDS,
    GEOMETRY_KEYS,
    HOMOGENEOUS_KEYS,
    LIGHT_CLASSES,
    LIGHT_KEYS,
    LIGHT_REQUIRED,
    MAX_LIGHTS,
    MATERIAL_KEYS,
    MATERIAL_REQUIRED,
    OBJECT_KEYS,
    SCENE_DEFAULTS,
    SCENE_FIELDS,
    SCENE_KEYS,
    limit_rule,
)
from phonglab.scene.toml_lines import render_key

#: core class -> the smallest valid arguments, standing in for a required field that is missing or refused
_NEUTRAL = {
    core.Material: {"ka": 0.0, "kd": 0.0, "ks": 0.0, "shininess": 1.0},
    core.AmbientLight: {},
    core.PointLight: {"position": (0.0, 0.0, 1.0)},
    core.DirectionalLight: {"direction": (0.0, 0.0, 1.0)},
    core.SpotLight: {"position": (0.0, 0.0, 1.0), "direction": (0.0, 0.0, -1.0)},
    core.AreaLight: {"position": (0.0, 0.0, 1.0)},
}


class Problems:
    """Collects SceneErrors while a table is checked."""

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

    def raise_all(self, *, file=None, lines=None) -> None:
        """Raise the problems, each with its file and line (``lines.line(field)``), ordered by line.

        Without a file the only problem is raised as it is; several always
        come as one :class:`SceneErrors`.
        """
        if not self.errors:
            return
        if file is None and len(self.errors) == 1:
            raise self.errors[0]
        located = [e.located(file=file, line=lines.line(e.field) if lines else None) for e in self.errors]
        located.sort(key=lambda e: e.line or 0)
        raise SceneErrors(located)


# ---------------------------------------------------------------------------
# core objects: the core checks the values, refusals are mapped to field paths


def _refusal(exc: core.InvalidValue, path: str, given: dict) -> tuple[str, SceneError]:
    """The refused key and the core's refusal (``InvalidValue.field`` = ``"Class.key"``) at its file path."""
    key = exc.field.rsplit(".", 1)[-1]
    if key not in given and "homogeneous" in given:  # the light that homogeneous = [x, y, z, w] made
        key = "homogeneous"
    rule = CORE_FIELDS.get(key, (None, None))[1]
    if exc.limit is not None:  # above the core's upper limit: its words name the limit
        rule = limit_rule(exc.allowed)
    return key, SceneError(rule or exc.allowed, field=join_path(path, key), value=given.get(key, exc.value))


def _core_object(make, values: dict, path: str, problems: Problems, *, complete: bool, neutral: dict):
    """``make(**values)``, the core checking every value; each refusal is recorded at its field path.

    The core stops at the first bad value, so after a refusal the field is
    set back to its default (a required one to its ``neutral`` value) and the
    core asked again, until it accepts: every bad value is reported, each
    judged next to the others. ``complete`` False means a key or shape
    problem was recorded already: missing fields are filled from ``neutral``
    to check the rest, and no object is returned.
    """
    trial = dict(values) if complete else {**neutral, **values}
    refused = set()
    while True:
        try:
            made = make(**trial)
        except core.InvalidValue as exc:
            key, error = _refusal(exc, path, values)
            if key in refused:  # refused again next to a default: reported already
                return None
            problems.add(error)
            refused.add(key)
            if key not in trial:  # no progress possible
                return None
            if key in neutral:
                trial[key] = neutral[key]
            else:
                del trial[key]
        else:
            return made if complete and not refused else None


def _shaped(table: dict, path: str, keys, problems: Problems) -> dict:
    """The values of ``keys`` in ``table`` whose TOML shape is right; the others are recorded as problems."""
    values = {}
    for key in keys:
        if key in table:
            shape, rule = CORE_FIELDS[key]
            value = problems.run(check_shape, join_path(path, key), table[key], shape, rule)
            if value is not None:
                values[key] = value
    return values


def build_material(data, problems: Problems, path="material"):
    start = len(problems.errors)
    table = problems.table(path, data, MATERIAL_KEYS, required=MATERIAL_REQUIRED)
    if table is None:
        return None
    values = _shaped(table, path, MATERIAL_KEYS, problems)
    complete = len(problems.errors) == start
    return _core_object(core.Material, values, path, problems, complete=complete, neutral=_NEUTRAL[core.Material])


def build_light(data, problems: Problems, path: str):
    if not isinstance(data, dict):
        problems.add(SceneError("must be a table", field=path, value=data))
        return None
    start = len(problems.errors)
    if "homogeneous" in data:
        return _build_homogeneous_light(data, problems, path, start)
    kind = data.get("type")
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
    if problems.table(path, data, ("type",) + LIGHT_KEYS[kind], required=LIGHT_REQUIRED[kind],
                      why=f" for a {kind} light") is None:
        return None
    values = _shaped(data, path, LIGHT_KEYS[kind], problems)
    cls = LIGHT_CLASSES[kind]
    return _core_object(cls, values, path, problems, complete=len(problems.errors) == start, neutral=_NEUTRAL[cls])


def _build_homogeneous_light(data: dict, problems: Problems, path: str, start: int):
    """A light given as ``homogeneous = [x, y, z, w]``: w = 0 directional, w > 0 point."""
    kind = data.get("type")
    for key in ("position", "direction"):  # homogeneous already places the light
        if key in data:
            problems.add(
                SceneError(
                    "cannot be given next to homogeneous = [x, y, z, w], which already places the light",
                    field=join_path(path, key),
                    value=data[key],
                )
            )
    table = problems.table(path, {k: v for k, v in data.items() if k not in ("position", "direction")}, HOMOGENEOUS_KEYS)
    values = _shaped(data, path, [k for k in HOMOGENEOUS_KEYS if k != "type"], problems)
    hom = values.get("homogeneous")
    w_type = None if hom is None or hom[3] < 0 else "directional" if hom[3] == 0 else "point"
    if kind is not None and w_type is not None and kind != w_type:
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
    if table is None:
        return None
    neutral = {"homogeneous": (0.0, 0.0, 1.0, 0.0 if w_type == "directional" else 1.0)}

    def make(homogeneous, **rest):
        return core.light_from_homogeneous(homogeneous, **rest)

    return _core_object(make, values, path, problems,
                        complete=len(problems.errors) == start, neutral=neutral)


def build_area_light(data, problems: Problems, path="area_light") -> AreaLightSetup | None:
    start = len(problems.errors)
    table = problems.table(path, data, AREA_LIGHT_KEYS, required=("position",))
    if table is None:
        return None
    values = _shaped(table, path, AREA_LIGHT_KEYS[:5], problems)
    light = _core_object(core.AreaLight, values, path, problems, complete=len(problems.errors) == start,
                         neutral=_NEUTRAL[core.AreaLight])
    if light is None:
        return None
    options = {k: table[k] for k in ("method", "samples") if k in table}
    return problems.run(AreaLightSetup, light, **options)


# ---------------------------------------------------------------------------
# the scene's own parts


def build_geometry(data, problems: Problems, base_dir=None, known=None, path="geometry") -> Geometry | None:
    """The geometry, its mesh file checked on disk (relative paths resolved against ``base_dir``).

    A geometry equal to ``known`` (an edited scene's own, checked when it was
    loaded; or one of a tuple of them) is taken as it is, without looking at
    the disk again.
    """
    table = problems.table(path, data, GEOMETRY_KEYS, required=("kind",))
    if table is None or "kind" not in table:
        return None
    known = known if isinstance(known, tuple) else (known,)
    try:
        geometry = Geometry(**{k: v for k, v in table.items() if k in GEOMETRY_KEYS})
        if geometry in known:
            return geometry
        found = find_mesh_file(geometry.kind, geometry.name, geometry.path, base_dir)
    except SceneError as exc:
        problems.add(exc.located(field=path))
        return None
    return dataclasses.replace(geometry, path=found) if geometry.kind == "file" else geometry


def build_objects(data, problems: Problems, base_dir=None, known=None) -> tuple[SceneObject, ...] | None:
    """The ``[[objects]]`` tables as SceneObjects, or None after recording their problems.

    The count is checked before any object is built, and the triangles of all
    the meshes together (read from the shapes and the mesh files' headers)
    before any mesh is built. Names must be given and differ. A translucent
    material (``opacity`` below 1) needs a scene of one object.
    """
    if not isinstance(data, list):
        problems.add(SceneError("must be a list of [[objects]] tables", field="objects", value=data))
        return None
    try:
        check_object_count(len(data))
    except SceneError as exc:
        problems.add(exc)
        return None
    start = len(problems.errors)
    built, names = [], {}
    for i, item in enumerate(data):
        path = f"objects[{i}]"
        table = problems.table(path, item, OBJECT_KEYS, required=OBJECT_KEYS)
        if table is None:
            continue
        name = problems.run(check_text, join_path(path, "name"), table["name"]) if "name" in table else None
        if name is not None and not name.strip():
            problems.add(SceneError("must not be empty: the page names the object by it", field=join_path(path, "name"),
                                    value=name))
        elif name is not None and name in names:
            problems.add(SceneError(f"must differ from objects[{names[name]}].name", field=join_path(path, "name"),
                                    value=name))
        elif name is not None:
            names[name] = i
        geometry = (build_geometry(table["geometry"], problems, base_dir, known, join_path(path, "geometry"))
                    if "geometry" in table else None)
        material = (build_material(table["material"], problems, join_path(path, "material"))
                    if "material" in table else None)
        built.append(SceneObject(name, geometry, material))
    if len(problems.errors) != start:
        return None
    problems.run(check_total_triangles, [o.geometry for o in built])
    if len(built) > 1:
        for i, obj in enumerate(built):
            if obj.material.opacity < 1:
                problems.add(SceneError("must be 1 in a scene of several objects: a translucent surface is blended "
                                        "over one object only", field=f"objects[{i}].material.opacity",
                                        value=obj.material.opacity))
    return tuple(built) if len(problems.errors) == start else None


def build_camera(data, problems: Problems) -> Camera | None:
    table = problems.table("camera", data, CAMERA_KEYS)
    if table is None or any(k not in CAMERA_KEYS for k in table):
        return None
    try:
        return Camera(**table)
    except SceneError as exc:
        problems.add(exc.located(field="camera"))
        return None


#: scene option -> check(path, value)
def option_check(field):
    """The check of a plain field's file value, from its entry's value rule (``SceneField.value``)."""
    kind, *args = field.value
    if kind == "choice":
        return lambda path, value: check_choice(path, value, args[0])
    if kind == "number":
        low, high, low_open = args
        return lambda path, value: check_number(path, value, low=low, high=high, low_open=low_open)
    return {"bool": check_bool, "text": check_text, "vector": check_vector}[kind]


#: the scene's plain fields (``model``, ``exposure``...) -> the check of a file's value, from SCENE_FIELDS
_OPTION_CHECKS = {f.name: option_check(f) for f in SCENE_FIELDS if f.option}


def scene_parts(data: dict, problems: Problems, *, extra_keys=(), base_dir=None, known_geometry=None) -> dict | None:
    """The keyword arguments of the ``Scene`` that ``data`` describes, or None after recording its problems.

    Parameters
    ----------
    data : dict
        A scene's table form (parsed TOML).
    problems : Problems
        Receives every problem, with its field path.
    extra_keys : tuple of str
        Further top-level keys allowed (a lesson's).
    base_dir : path, optional
        Folder against which a relative ``geometry.path`` is resolved.
    known_geometry : Geometry or tuple of Geometry, optional
        Taken as it is when ``data`` describes it (see :func:`build_geometry`).

    Notes
    -----
    The objects are given either as ``[geometry]`` and ``[material]`` (one
    object) or as ``[[objects]]``, not both; the first object's geometry and
    material become the scene's ``geometry`` and ``material``.
    """
    start = len(problems.errors)
    several = "objects" in data
    problems.table("", data, SCENE_KEYS + tuple(extra_keys), required=() if several else ("geometry", "material"))
    parts = dict(SCENE_DEFAULTS, area_light=None, objects=())
    if several:
        for key in ("geometry", "material"):
            if key in data:
                problems.add(SceneError("cannot be given next to [[objects]]: list every object there, with its "
                                        "geometry and material", field=key))
        objects = build_objects(data["objects"], problems, base_dir, known_geometry)
        parts["objects"] = objects or ()
        parts["geometry"] = objects[0].geometry if objects else None
        parts["material"] = objects[0].material if objects else None
    else:
        parts["geometry"] = (build_geometry(data["geometry"], problems, base_dir, known_geometry)
                             if "geometry" in data else None)
        parts["material"] = build_material(data["material"], problems) if "material" in data else None
    lights = []
    raw_lights = data.get("lights", [])
    if not isinstance(raw_lights, list):
        problems.add(SceneError("must be a list of [[lights]] tables", field="lights", value=raw_lights))
    elif len(raw_lights) > MAX_LIGHTS:  # refused before each is built
        problems.run(check_light_count, len(raw_lights))
    else:
        for i, item in enumerate(raw_lights):
            lights.append(build_light(item, problems, f"lights[{i}]"))
    parts["lights"] = tuple(lights)
    parts["camera"] = build_camera(data.get("camera", {}), problems)
    if "area_light" in data:
        parts["area_light"] = build_area_light(data["area_light"], problems)
    for key, check in _OPTION_CHECKS.items():
        if key in data:
            parts[key] = problems.run(check, key, data[key])
    if len(problems.errors) == start:
        # limits that need the parts together, shared by files, edits and the page
        for error in check_limits(parts, data):
            problems.add(error)
    return parts if len(problems.errors) == start else None
