"""Field paths: name and read one field of a scene, in its file form.

A field path names a value as a scene file writes it: ``model``,
``material.ks``, ``lights[1].position``, ``lights[1].position[2]``,
``camera.eye``, ``geometry.resolution``, ``objects[1].material.kd``. In a
scene of several objects, ``geometry`` and ``material`` name the first
object's (``objects[0].material.ks``). The web app's state keys and the
command line's ``--set PATH=VALUE`` use these paths.

:func:`scene_to_dict` gives a scene's file form (the dictionary its TOML file
would parse to) and :func:`field_value` reads one field of it. Writing a
field is :mod:`phonglab.scene.editing`'s job (``Scene.replace``).
"""

from __future__ import annotations

import re
import tomllib

from phonglab.scene.checks import check_nesting
from phonglab.scene.errors import SceneError, did_you_mean
from phonglab.scene.schema import (
    AREA_LIGHT_KEYS,
    CAMERA_KEYS,
    GEOMETRY_KEYS,
    HOMOGENEOUS_TYPES,
    MAX_VALUE_CHARS,
    LIGHT_KEYS,
    MATERIAL_KEYS,
    OBJECT_KEYS,
    SCENE_FIELDS,
    SCENE_KEYS,
    light_type,
    table_light_type,
)

_SEGMENT = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)")
_INDEX = re.compile(r"\[(\d+)\]")
_PATH_RULE = "must be a field path such as material.ks, lights[1].position or camera.eye"



def parse_path(path: str) -> list[str | int]:
    """Split a field path into keys and indices.

    Examples
    --------
    >>> parse_path("lights[1].position[2]")
    ['lights', 1, 'position', 2]

    Raises
    ------
    SceneError
        When ``path`` is not of that form.
    """
    if not isinstance(path, str) or not path:
        raise SceneError(_PATH_RULE, value=path)
    parts: list[str | int] = []
    for segment in path.split("."):
        match = _SEGMENT.fullmatch(segment)
        if not match:
            raise SceneError(_PATH_RULE, value=path)
        parts.append(match.group(1))
        parts.extend(int(i) for i in _INDEX.findall(match.group(2)))
    return parts


def check_path_shape(path: str) -> list[str | int]:
    """Check a field path against the file format alone, without a scene.

    Used where the scene itself could not be built: table names and keys are
    checked, light indices and light types are not.

    Raises
    ------
    SceneError
        When the path is malformed or names no field of any scene.
    """
    parts = parse_path(path)
    tables = {"geometry": GEOMETRY_KEYS, "material": MATERIAL_KEYS, "camera": CAMERA_KEYS}
    if parts[0] == "objects" and len(parts) > 1:
        if not isinstance(parts[1], int):
            raise SceneError("must index an object, as in objects[1].material.ks", field=path)
        if len(parts) > 2 and parts[2] not in OBJECT_KEYS:
            raise no_field(path, parts, 2, OBJECT_KEYS)
        if len(parts) > 3 and parts[2] in tables and parts[3] not in tables[parts[2]]:
            raise no_field(path, parts, 3, tables[parts[2]])
        return parts
    light_keys = ("type", "homogeneous") + tuple(dict.fromkeys(k for keys in LIGHT_KEYS.values() for k in keys))
    if parts[0] not in SCENE_KEYS:
        raise no_field(path, parts, 0, SCENE_KEYS)
    if parts[0] in tables and len(parts) > 1 and parts[1] not in tables[parts[0]]:
        raise no_field(path, parts, 1, tables[parts[0]])
    if parts[0] == "lights" and len(parts) > 1:
        if not isinstance(parts[1], int):
            raise SceneError("must index a light, as in lights[1].position", field=path)
        if len(parts) > 2 and parts[2] not in light_keys:
            raise no_field(path, parts, 2, light_keys)
    return parts


def format_path(parts) -> str:
    """The inverse of :func:`parse_path`."""
    text = ""
    for part in parts:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def plain(value):
    """Tuples and arrays as lists, recursively: the form tomllib gives."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    return value


def light_to_dict(light) -> dict:
    """A core light as its ``[[lights]]`` table."""
    kind = light_type(light)
    table = {"type": kind}
    for key in LIGHT_KEYS[kind]:
        value = getattr(light, key)
        if value is not None:
            table[key] = plain(value)
    return table


def geometry_to_dict(g) -> dict:
    """A Geometry as its ``[geometry]`` table (``center`` and ``scale`` only when they are not the defaults)."""
    geometry = {"kind": g.kind, "resolution": g.resolution}
    if g.name is not None:
        geometry["name"] = g.name
    if g.path is not None:
        geometry["path"] = g.path
    if any(g.center):
        geometry["center"] = list(g.center)
    if g.scale != 1.0:
        geometry["scale"] = g.scale
    return geometry


def material_to_dict(m) -> dict:
    """A core Material as its ``[material]`` table."""
    return {k: plain(getattr(m, k)) for k in MATERIAL_KEYS}


def scene_to_dict(scene) -> dict:
    """The scene as the dictionary its TOML file would parse to.

    A scene of one unnamed object is written with ``geometry`` and
    ``material``; any other with ``objects``, a table per object.
    """
    # the plain fields, from the schema's table (the probe is written below, when there is one)
    data = {f.name: plain(getattr(scene, f.name)) for f in SCENE_FIELDS if f.option and f.name != "probe"}
    if scene.objects:
        data["objects"] = [{"name": o.name, "geometry": geometry_to_dict(o.geometry),
                            "material": material_to_dict(o.material)} for o in scene.objects]
    else:
        data.update(geometry=geometry_to_dict(scene.geometry), material=material_to_dict(scene.material))
    data.update(lights=[light_to_dict(light) for light in scene.lights],
                camera={k: plain(getattr(scene.camera, k)) for k in CAMERA_KEYS})
    if scene.probe is not None:
        data["probe"] = list(scene.probe)
    if scene.area_light is not None:
        area = scene.area_light
        data["area_light"] = {k: plain(getattr(area.light, k)) for k in AREA_LIGHT_KEYS[:5]}
        data["area_light"].update(method=area.method, samples=area.samples)
    return data


def keys_for(data: dict, parts: list) -> tuple[str, ...] | None:
    """The keys allowed in the table at ``parts``; None when it is not a table of the format."""
    if not parts:
        return SCENE_KEYS
    if parts == ["geometry"] or (len(parts) == 3 and parts[0] == "objects" and parts[2] == "geometry"):
        return GEOMETRY_KEYS
    if parts == ["material"] or (len(parts) == 3 and parts[0] == "objects" and parts[2] == "material"):
        return MATERIAL_KEYS
    if len(parts) == 2 and parts[0] == "objects":
        return OBJECT_KEYS
    if parts == ["camera"]:
        return CAMERA_KEYS
    if parts == ["area_light"]:
        return AREA_LIGHT_KEYS
    if len(parts) == 2 and parts[0] == "lights":
        kind = table_light_type(data["lights"][parts[1]])
        extra = ("homogeneous",) if kind in HOMOGENEOUS_TYPES else ()
        return ("type",) + LIGHT_KEYS[kind] + extra
    return None


def no_field(path, parts, i, keys, hint=None):
    near = did_you_mean(parts[i], keys) if keys else None
    listing = ("allowed here: " + ", ".join(keys)) if keys else None
    hint = hint or (f"{near} ({listing})" if near else listing)
    return SceneError("no such field", field=path, hint=hint)


def homogeneous_of(light: dict) -> list:
    """The ``[x, y, z, w]`` form of a point or directional light table."""
    if light["type"] == "point":
        return list(light["position"]) + [1.0]
    return list(light["direction"]) + [0.0]


def object_parts(data: dict, parts: list) -> list:
    """``parts`` with ``geometry``/``material`` read as the first object's in a scene written with ``objects``.

    The page's ``material.ks`` and ``--set geometry.scale=2`` mean the first
    object of any scene.
    """
    if parts and parts[0] in ("geometry", "material") and "objects" in data and parts[0] not in data:
        return ["objects", 0] + list(parts)
    return parts


def locate_field(data: dict, path: str, parts: list):
    """Walk ``parts`` through ``data``; return (container, key) of the field, checked against the format."""
    parts = object_parts(data, parts)
    node = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(part, str):
            keys = keys_for(data, parts[:i]) if isinstance(node, dict) else None
            if keys is None or part not in keys:
                raise no_field(path, parts, i, keys)
            if part == "homogeneous" and not last:
                node[part] = homogeneous_of(node)  # index into [x, y, z, w]
            if last:
                return node, part
            if part not in node:  # an optional field left out (probe, a light's diffuse)
                raise SceneError(f"is not set, so {format_path(parts[: i + 1])} has no parts", field=path)
            node = node[part]
        else:
            if not isinstance(node, list):
                raise SceneError(f"{format_path(parts[:i])} is not a list", field=path)
            if part >= len(node):
                what = {"lights": "light", "objects": "object"}.get(parts[i - 1], "item") if i == 1 else "item"
                count = f"{len(node)} {what}s" if len(node) != 1 else f"1 {what}"
                rule = f"index must be below {len(node)}" if node else "the list is empty"
                raise SceneError(f"no such {what}: {rule} ({count})", field=path)
            if last:
                return node, part
            node = node[part]
    raise SceneError(_PATH_RULE, value=path)


def field_value(scene, path: str):
    """The current value at ``path``, in file form (lists, not tuples).

    Raises
    ------
    SceneError
        When the path does not name a field of this scene.
    """
    parts = parse_path(path)
    data = scene_to_dict(scene)
    container, key = locate_field(data, path, parts)
    if isinstance(container, dict) and key not in container:
        if key == "homogeneous":
            return homogeneous_of(container)
        return None
    return container[key]


def parse_value(text: str):
    """A value written as in TOML (``100``, ``[1, 2, 3]``, ``true``, ``"phong"``); bare words are strings.

    Raises
    ------
    SceneError
        When the value is longer than :data:`~phonglab.scene.schema.MAX_VALUE_CHARS`
        or nested deeper than :data:`~phonglab.scene.schema.MAX_NESTING`.
    """
    if len(text) > MAX_VALUE_CHARS:
        raise SceneError(f"is too long: {len(text):,} characters, at most {MAX_VALUE_CHARS:,} allowed",
                         value=text)
    check_nesting(text)
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        return text.strip()


def parse_setting(text: str) -> tuple[str, object]:
    """Split ``PATH=VALUE`` (as given to ``--set``) into the path and the parsed value.

    Examples
    --------
    >>> parse_setting("material.shininess=100")
    ('material.shininess', 100)

    Raises
    ------
    SceneError
        When there is no ``=`` or the path is malformed.
    """
    if "=" not in text:
        raise SceneError("must be PATH=VALUE, e.g. material.shininess=100", value=text)
    path, _, raw = text.partition("=")
    path = path.strip()
    parse_path(path)
    try:
        return path, parse_value(raw.strip())
    except SceneError as exc:
        raise exc.located(field=path) from None
