"""Field paths: read and replace one field of a scene by its name.

A field path names a value as a scene file writes it: ``model``,
``material.ks``, ``lights[1].position``, ``lights[1].position[2]``,
``camera.eye``, ``geometry.resolution``. The web app's state keys and the
command line's ``--set PATH=VALUE`` use these paths.

:func:`replace_field` works on the scene's file form: it turns the scene
into the dictionary a TOML file would give, sets the value, and checks the
result exactly as a file is checked, so a value refused in a file is refused
here with the same message.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from phonglab.scene.loader import (
    AREA_LIGHT_KEYS,
    CAMERA_KEYS,
    GEOMETRY_KEYS,
    LIGHT_KEYS,
    MATERIAL_KEYS,
    SCENE_KEYS,
    light_type,
    scene_from_dict,
)
from phonglab.scene.model import Scene, SceneError, did_you_mean

_SEGMENT = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)")
_INDEX = re.compile(r"\[(\d+)\]")
_PATH_RULE = "must be a field path such as material.ks, lights[1].position or camera.eye"

#: light types whose position may be given as homogeneous = [x, y, z, w]
_HOMOGENEOUS_TYPES = ("point", "directional")


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
    light_keys = ("type", "homogeneous") + tuple(dict.fromkeys(k for keys in LIGHT_KEYS.values() for k in keys))
    if parts[0] not in SCENE_KEYS:
        raise _no_field(path, parts, 0, SCENE_KEYS)
    if parts[0] in tables and len(parts) > 1 and parts[1] not in tables[parts[0]]:
        raise _no_field(path, parts, 1, tables[parts[0]])
    if parts[0] == "lights" and len(parts) > 1:
        if not isinstance(parts[1], int):
            raise SceneError("must index a light, as in lights[1].position", field=path)
        if len(parts) > 2 and parts[2] not in light_keys:
            raise _no_field(path, parts, 2, light_keys)
    return parts


def format_path(parts) -> str:
    """The inverse of :func:`parse_path`."""
    text = ""
    for part in parts:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def _plain(value):
    """Tuples and arrays as lists, recursively: the form tomllib gives."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def light_to_dict(light) -> dict:
    """A core light as its ``[[lights]]`` table."""
    kind = light_type(light)
    table = {"type": kind}
    for key in LIGHT_KEYS[kind]:
        value = getattr(light, key)
        if value is not None:
            table[key] = _plain(value)
    return table


def scene_to_dict(scene: Scene) -> dict:
    """The scene as the dictionary its TOML file would parse to."""
    g = scene.geometry
    geometry = {"kind": g.kind, "resolution": g.resolution}
    if g.name is not None:
        geometry["name"] = g.name
    if g.path is not None:
        geometry["path"] = g.path
    m = scene.material
    data = {
        "title": scene.title,
        "model": scene.model,
        "interpolation": scene.interpolation,
        "two_sided": scene.two_sided,
        "geometry": geometry,
        "material": {k: _plain(getattr(m, k)) for k in MATERIAL_KEYS},
        "lights": [light_to_dict(light) for light in scene.lights],
        "camera": {k: _plain(getattr(scene.camera, k)) for k in CAMERA_KEYS},
    }
    if scene.probe is not None:
        data["probe"] = list(scene.probe)
    if scene.area_light is not None:
        area = scene.area_light
        data["area_light"] = {k: _plain(getattr(area.light, k)) for k in AREA_LIGHT_KEYS[:5]}
        data["area_light"].update(method=area.method, samples=area.samples)
    return data


def _keys_for(data: dict, parts: list) -> tuple[str, ...] | None:
    """The keys allowed in the table at ``parts``; None when it is not a table of the format."""
    if not parts:
        return SCENE_KEYS
    if parts == ["geometry"]:
        return GEOMETRY_KEYS
    if parts == ["material"]:
        return MATERIAL_KEYS
    if parts == ["camera"]:
        return CAMERA_KEYS
    if parts == ["area_light"]:
        return AREA_LIGHT_KEYS
    if len(parts) == 2 and parts[0] == "lights":
        light = data["lights"][parts[1]]
        kind = light.get("type")
        if kind is None:  # given as homogeneous = [x, y, z, w]: w says which
            hom = light.get("homogeneous")
            kind = "directional" if isinstance(hom, list) and len(hom) == 4 and hom[3] == 0 else "point"
        extra = ("homogeneous",) if kind in _HOMOGENEOUS_TYPES else ()
        return ("type",) + LIGHT_KEYS[kind] + extra
    return None


def _no_field(path, parts, i, keys, hint=None):
    near = did_you_mean(parts[i], keys) if keys else None
    listing = ("allowed here: " + ", ".join(keys)) if keys else None
    hint = hint or (f"{near} ({listing})" if near else listing)
    return SceneError("no such field", field=path, hint=hint)


def _homogeneous_of(light: dict) -> list:
    """The ``[x, y, z, w]`` form of a point or directional light table."""
    if light["type"] == "point":
        return list(light["position"]) + [1.0]
    return list(light["direction"]) + [0.0]


def _locate(data: dict, path: str, parts: list):
    """Walk ``parts`` through ``data``; return (container, key) of the field, checked against the format."""
    node = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(part, str):
            keys = _keys_for(data, parts[:i]) if isinstance(node, dict) else None
            if keys is None or part not in keys:
                raise _no_field(path, parts, i, keys)
            if part == "homogeneous" and not last:
                node[part] = _homogeneous_of(node)  # index into [x, y, z, w]
            if last:
                return node, part
            if part not in node:  # an optional field left out (probe, a light's diffuse)
                raise SceneError(f"is not set, so {format_path(parts[: i + 1])} has no parts", field=path)
            node = node[part]
        else:
            if not isinstance(node, list):
                raise SceneError(f"{format_path(parts[:i])} is not a list", field=path)
            if part >= len(node):
                what = "light" if parts[:i] == ["lights"] else "item"
                count = f"{len(node)} {what}s" if len(node) != 1 else f"1 {what}"
                rule = f"index must be below {len(node)}" if node else "the list is empty"
                raise SceneError(f"no such {what}: {rule} ({count})", field=path)
            if last:
                return node, part
            node = node[part]
    raise SceneError(_PATH_RULE, value=path)


def field_value(scene: Scene, path: str):
    """The current value at ``path``, in file form (lists, not tuples).

    Raises
    ------
    SceneError
        When the path does not name a field of this scene.
    """
    parts = parse_path(path)
    data = scene_to_dict(scene)
    container, key = _locate(data, path, parts)
    if isinstance(container, dict) and key not in container:
        if key == "homogeneous":
            return _homogeneous_of(container)
        return None
    return container[key]


def replace_field(scene: Scene, path: str, value) -> Scene:
    """A copy of ``scene`` with the field at ``path`` set to ``value`` (see :meth:`Scene.replace`).

    ``None`` removes an optional field (``probe``, a light's ``diffuse``).
    Setting ``lights[i].homogeneous`` (or one of its four entries) turns the
    light into a point light (w > 0) or a directional one (w = 0); setting
    ``lights[i].type`` carries the light over (see ``_carry_light_over``) and
    keeps only the keys the new type has.

    Raises
    ------
    SceneError
        A bad path (naming the path and the fields allowed there) or a bad
        value (naming the path, the value and what is allowed).
    """
    data = scene_to_dict(scene)
    _assign(scene, data, path, value)
    return _build(scene, data)


def replace_fields(scene: Scene, settings) -> Scene:
    """A copy of ``scene`` with every ``(path, value)`` of ``settings`` applied, validated once.

    The settings are applied in order to the scene's table and the result is
    checked as a whole, so an experiment may move the eye and the up vector
    together, or turn a point light into a spotlight and set its cone, with no
    half-done state checked in between. Errors are as in :func:`replace_field`.
    """
    data = scene_to_dict(scene)
    for path, value in settings:
        _assign(scene, data, path, value)
    return _build(scene, data)


def settings_problems(scene: Scene, settings) -> list[tuple[str | None, SceneError]]:
    """Every problem of applying ``settings`` together, as ``(setting path or None, error)``.

    A path that does not exist is blamed on its setting and left out; the
    rest are applied together and the resulting scene checked once, its
    errors blamed on the setting that wrote the field (None when no setting
    did, e.g. a light that a type change left incomplete).
    """
    data = scene_to_dict(scene)
    found: list[tuple[str | None, SceneError]] = []
    applied = []
    for path, value in settings:
        try:
            _assign(scene, data, path, value)
            applied.append(path)
        except SceneError as exc:
            found.append((path, exc))
    try:
        _build(scene, data)
    except SceneError as exc:
        for error in getattr(exc, "errors", [exc]):
            culprit = next((p for p in reversed(applied) if error.field and (
                error.field == p or error.field.startswith((p + ".", p + "[")) or p.startswith(error.field))), None)
            found.append((culprit, error))
    return found


def _build(scene: Scene, data: dict) -> Scene:
    """The scene ``data`` describes, checked; relative mesh paths resolve as for ``scene``."""
    base_dir = Path(scene.source).resolve().parent if scene.source else None
    return scene_from_dict(data, source=scene.source, base_dir=base_dir)


def _assign(scene: Scene, data: dict, path: str, value) -> None:
    """Set ``path`` to ``value`` in ``data``, the table form of ``scene`` (checked later)."""
    parts = parse_path(path)
    container, key = _locate(data, path, parts)
    value = _plain(value)
    if isinstance(container, list):
        container[key] = value
    elif value is None:
        container.pop(key, None)
    else:
        container[key] = value
    # a light table that changed form
    if len(parts) >= 3 and parts[0] == "lights" and parts[2] == "homogeneous":
        light = data["lights"][parts[1]]
        for stale in ("type", "position", "direction"):
            light.pop(stale, None)
        hom = light.get("homogeneous")
        if isinstance(hom, list) and len(hom) == 4 and hom[3] == 0:
            light.pop("attenuation", None)  # a directional light has no distance
    elif len(parts) == 3 and parts[0] == "lights" and parts[2] == "type" and value in LIGHT_KEYS:
        light = data["lights"][parts[1]]
        _carry_light_over(light, light_type(scene.lights[parts[1]]), value,
                          data.get("camera", {}).get("focal_point", (0.0, 0.0, 0.0)))
        for stale in [k for k in light if k != "type" and k not in LIGHT_KEYS[value]]:
            del light[stale]


#: distance from the scene's centre at which a directional light turned into a point light is placed
CONVERTED_LIGHT_DISTANCE = 4.0


def _carry_light_over(light: dict, old_type: str, new_type: str, centre) -> None:
    """Fill what a light of ``new_type`` needs from what the light was, in place.

    The light stays where the student put it: a point light becomes a
    directional light shining from the same side of the scene's centre
    (``centre`` is the camera's focal point), a directional light becomes a
    point light at ``CONVERTED_LIGHT_DISTANCE`` along its direction, and a
    new spotlight is aimed at the centre with a 30° cone.
    """
    centre = [float(c) for c in centre]
    position, direction = light.get("position"), light.get("direction")
    if new_type in ("point", "spot") and position is None and direction is not None:
        norm = sum(float(c) ** 2 for c in direction) ** 0.5 or 1.0
        light["position"] = [c + CONVERTED_LIGHT_DISTANCE * float(d) / norm for c, d in zip(centre, direction)]
    if new_type == "directional" and position is not None:
        towards = [float(p) - c for p, c in zip(position, centre)]
        light["direction"] = towards if any(towards) else [0.0, 0.0, 1.0]
    if new_type == "spot" and old_type != "spot":
        aim = [c - float(p) for c, p in zip(centre, light["position"])]
        light["direction"] = aim if any(aim) else [0.0, 0.0, -1.0]
        light.setdefault("cutoff", 30.0)


def parse_value(text: str):
    """A value written as in TOML (``100``, ``[1, 2, 3]``, ``true``, ``"phong"``); bare words are strings."""
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
    return path, parse_value(raw.strip())
