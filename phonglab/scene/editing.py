"""Editing a scene: set fields by path, retype a light, place lights and the eye.

:func:`replace_field` (``Scene.replace``) works on the scene's file form: it
turns the scene into the dictionary a TOML file would give
(:func:`~phonglab.scene.fieldpath.scene_to_dict`), sets the value, and checks
the result exactly as a file is checked (:func:`~phonglab.scene.build.scene_parts`),
so a value refused in a file is refused here with the same message. An edit
inside the material, the camera or one light (every slider of the page)
builds and checks that part alone, with the same builders, and the limits
on the whole scene (:func:`~phonglab.scene.limits.check_limits`): the other
parts were checked when the scene was made, and are kept as they are.

Changing a light's type keeps the light where it was
(:func:`retyped_light_table`, the one set of defaults for it). Lights and the
eye are also placed by azimuth, elevation and distance around the camera's
focal point, in a :class:`Frame` (:func:`move_light`, :func:`move_eye`).

The functions take any scene (they read its fields and call its
``replace``); none imports the ``Scene`` class, whose methods call them.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

from phonglab.scene.build import Problems, build_camera, build_light, build_material, scene_parts
from phonglab.scene.errors import SceneError
from phonglab.scene.fieldpath import field_value, locate_field, parse_path, plain, scene_to_dict
from phonglab.scene.limits import check_limits
from phonglab.scene.schema import LIGHT_KEYS, light_type, table_light_type

#: a spotlight's cone when a light becomes a spot
SPOT_DEFAULTS = {"cutoff": 25.0, "exponent": 2.0}
#: nearest distance from the focal point at which a light with no place (directional) becomes a point light
RETYPE_MIN_DISTANCE = 3.0
#: what a light keeps when its type changes (where the new type has it)
_KEPT_WHEN_RETYPED = ("color", "intensity", "diffuse", "specular")


# ---------------------------------------------------------------------------
# setting fields by path


def replace_field(scene, path: str, value):
    """A copy of ``scene`` with the field at ``path`` set to ``value`` (see :meth:`Scene.replace`).

    ``None`` removes an optional field (``probe``, a light's ``diffuse``).
    Setting ``lights[i].homogeneous`` (or one of its four entries) turns the
    light into a point light (w > 0) or a directional one (w = 0); setting
    ``lights[i].type`` carries the light over (:func:`retyped_light_table`).

    Raises
    ------
    SceneError
        A bad path (naming the path and the fields allowed there) or a bad
        value (naming the path, the value and what is allowed).
    """
    data = scene_to_dict(scene)
    _assign(data, path, value)
    return _build(scene, data, _edited_part(path))


def _edited_part(path: str):
    """The one part of a scene an edit at ``path`` stays inside: ``"material"``, ``"camera"``, a light's index, or None."""
    parts = parse_path(path)
    if len(parts) < 2:
        return None
    if parts[0] in ("material", "camera"):
        return parts[0]
    return parts[1] if parts[0] == "lights" and isinstance(parts[1], int) else None


def replace_fields(scene, settings):
    """A copy of ``scene`` with every ``(path, value)`` of ``settings`` applied, validated once.

    The settings are applied in order to the scene's table and the result is
    checked as a whole, so an experiment may move the eye and the up vector
    together, or turn a point light into a spotlight and set its cone, with no
    half-done state checked in between; settings all inside one part (the
    material, the camera, one light) build only that part again, as
    :func:`replace_field` does. Errors are as in :func:`replace_field`.
    """
    data = scene_to_dict(scene)
    parts = set()
    for path, value in settings:
        _assign(data, path, value)
        parts.add(_edited_part(path))
    return _build(scene, data, parts.pop() if len(parts) == 1 else None)


def settings_problems(scene, settings) -> list[tuple[str | None, SceneError]]:
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
            _assign(data, path, value)
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


def _build(scene, data: dict, part=None):
    """The scene ``data`` describes, checked; relative mesh paths resolve as for ``scene``.

    The scene's own geometry is kept as it is (its mesh file was checked when
    the scene was loaded); a changed one is checked, on disk too. With
    ``part`` (:func:`_edited_part`: the only part of ``data`` that differs
    from ``scene``'s form), only that part is built again.
    """
    if part is not None:
        rebuilt = _rebuild_part(scene, data, part)
        if rebuilt is not None:
            return rebuilt
    base_dir = Path(scene.source).resolve().parent if scene.source else None
    problems = Problems()
    known = tuple(o.geometry for o in scene.all_objects)
    parts = scene_parts(data, problems, base_dir=base_dir, known_geometry=known)
    problems.raise_all()
    return dataclasses.replace(scene, **parts)


def _rebuild_part(scene, data: dict, part):
    """``scene`` with its ``part`` built from ``data`` and checked as :func:`_build` checks it, or None to build it all."""
    if part == "material" and "material" not in data:
        return None  # a scene of [[objects]]: its first object's material is inside them
    problems = Problems()
    if part == "material":
        fields = {"material": build_material(data["material"], problems)}
    elif part == "camera":
        fields = {"camera": build_camera(data["camera"], problems)}
    else:
        lights = list(scene.lights)
        lights[part] = build_light(data["lights"][part], problems, f"lights[{part}]")
        fields = {"lights": tuple(lights)}
    problems.raise_all()
    if any(value is None for value in fields.values()):
        return None
    whole = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene)}
    whole.update(fields)
    for error in check_limits(whole, data):  # what needs the parts together
        problems.add(error)
    problems.raise_all()
    return dataclasses.replace(scene, **fields)


def _assign(data: dict, path: str, value) -> None:
    """Set ``path`` to ``value`` in ``data``, a scene's table form (checked later)."""
    parts = parse_path(path)
    container, key = locate_field(data, path, parts)
    value = plain(value)
    if len(parts) == 3 and parts[0] == "lights" and parts[2] == "type" and value in LIGHT_KEYS:
        camera = data.get("camera", {})
        data["lights"][parts[1]] = retyped_light_table(
            data["lights"][parts[1]], value, camera.get("focal_point", (0.0, 0.0, 0.0)), camera.get("eye", (0.0, 0.0, 4.0))
        )
        return
    if parts == ["objects"]:
        # the objects listed anew: they replace the scene's [geometry] and [material], if it had those
        data.pop("geometry", None)
        data.pop("material", None)
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


# ---------------------------------------------------------------------------
# changing a light's type


def retyped_light_table(table: dict, kind: str, focal, eye) -> dict:
    """A ``[[lights]]`` table turned into a ``kind`` light that stays where it was.

    The place is the offset from the focal point: a point light or spot keeps
    its position, a directional light becomes one shining from that side
    (``direction`` = the unit offset), and a directional light (which has no
    distance) becomes a point light ``max(RETYPE_MIN_DISTANCE, |eye - focal|)``
    from the focal point along its direction. A new spot is aimed at the focal
    point with :data:`SPOT_DEFAULTS`; point and spot lights keep their
    attenuation. Colour, intensity, diffuse and specular are kept; the rest
    goes. Used by ``Scene.replace("lights[i].type", kind)`` and the app's type
    control alike.

    Parameters
    ----------
    table : dict
        The light's table (file form; ``homogeneous`` is understood).
    kind : str
        ``"point"``, ``"directional"``, ``"spot"`` or ``"ambient"``.
    focal, eye : 3 floats
        The camera's focal point and eye.

    Returns
    -------
    dict
        A new table; ``table`` itself when it already has that type.
    """
    if table_light_type(table) == kind:
        return table
    new = {k: table[k] for k in _KEPT_WHEN_RETYPED if k in table and k in LIGHT_KEYS[kind]}
    new["type"] = kind
    if kind == "ambient":
        return new
    # where the light is
    position, direction = _numbers(table.get("position"), 3), _numbers(table.get("direction"), 3)
    hom = _numbers(table.get("homogeneous"), 4)
    if any(table.get(k) is not None and v is None for k, v in
           (("position", position), ("direction", direction), ("homogeneous", hom))) or (hom and hom[3] < 0):
        return {**table, "type": kind}  # a place that is not one: left for the scene check to report
    if hom is not None and hom[3] == 0:
        position, direction = None, hom[:3]
    elif hom is not None and hom[3] > 0:
        position = [c / hom[3] for c in hom[:3]]
    focal, eye = _numbers(focal, 3), _numbers(eye, 3)
    if focal is None or eye is None or focal == eye:  # a camera being edited: left for the scene check
        return {**table, "type": kind}
    towards_eye = [e - f for e, f in zip(eye, focal)]
    offset = [p - f for p, f in zip(position, focal)] if position is not None else None
    if offset is None or not any(offset):  # no place of its own: along its direction, or towards the eye
        position = None
        offset = direction if direction is not None and any(direction) else towards_eye
    length = math.sqrt(sum(c * c for c in offset))
    unit = [c / length for c in offset]
    if kind == "directional":
        new["direction"] = unit
        return new
    if position is None:
        distance = max(RETYPE_MIN_DISTANCE, math.sqrt(sum(c * c for c in towards_eye)))
        position = [f + distance * u for f, u in zip(focal, unit)]
    new["position"] = list(position)
    new["attenuation"] = table.get("attenuation", [1.0, 0.0, 0.0])
    if kind == "spot":
        new["direction"] = [f - p for f, p in zip(focal, new["position"])]  # aimed at the focal point
        new.update(SPOT_DEFAULTS)
    return new


def _numbers(value, size: int) -> list[float] | None:
    """``value`` as ``size`` finite floats, or None when it is not a list of them."""
    if not isinstance(value, (list, tuple)) or len(value) != size:
        return None
    if not all(isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in value):
        return None
    return [float(c) for c in value]


def retype_light(scene, index: int, kind: str):
    """The scene with light ``index`` turned into a ``kind`` light at the same place (see :func:`retyped_light_table`)."""
    if light_kind(scene.lights[index]) == kind:
        return scene
    return scene.replace(f"lights[{index}].type", kind)


def light_kind(light) -> str:
    """The file-format type of a core light: "spot", "point", "directional" or "ambient"."""
    return light_type(light)


def light_table(scene, index: int) -> dict:
    """Light ``index`` of ``scene`` as its ``[[lights]]`` table."""
    return field_value(scene, f"lights[{index}]")


# ---------------------------------------------------------------------------
# placing lights and the eye by azimuth, elevation and distance


@dataclass(frozen=True)
class Frame:
    """The axes azimuth and elevation are measured in.

    ``up`` is the vertical axis (the lesson camera's up), ``front`` the
    direction of azimuth 0 (towards the lesson's eye, flattened onto the
    horizontal plane) and ``right`` the direction of azimuth +90°.
    """

    up: tuple = (0.0, 1.0, 0.0)
    front: tuple = (0.0, 0.0, 1.0)
    right: tuple = (1.0, 0.0, 0.0)

    @classmethod
    def of_camera(cls, camera) -> "Frame":
        """The frame of a scene camera: vertical along ``up``, azimuth 0 towards the eye."""
        up = _unit(camera.up)
        towards_eye = [e - f for e, f in zip(camera.eye, camera.focal_point)]
        front = _unit(_reject(towards_eye, up))
        if front is None:  # looking straight along up: any horizontal direction
            trial = (0.0, 0.0, 1.0) if abs(up[2]) < 0.9 else (1.0, 0.0, 0.0)
            front = _unit(_reject(trial, up))
        right = _cross(up, front)
        return cls(up=up, front=front, right=right)


def _unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v) if n > 1e-12 else None


def _reject(v, axis):
    d = sum(a * b for a, b in zip(v, axis))
    return [a - d * b for a, b in zip(v, axis)]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def place_of(offset, frame: Frame) -> tuple[float, float, float]:
    """(azimuth°, elevation°, length) of an offset in ``frame``."""
    length = math.sqrt(sum(c * c for c in offset))
    if length == 0:
        return 0.0, 0.0, 0.0
    x = sum(a * b for a, b in zip(offset, frame.right)) / length
    y = sum(a * b for a, b in zip(offset, frame.up)) / length
    z = sum(a * b for a, b in zip(offset, frame.front)) / length
    return math.degrees(math.atan2(x, z)), math.degrees(math.asin(max(-1.0, min(1.0, y)))), length


def place_offset(azimuth: float, elevation: float, distance: float, frame: Frame) -> tuple[float, float, float]:
    """The offset for azimuth°, elevation° and distance in ``frame``."""
    a, e = math.radians(azimuth), math.radians(elevation)
    x, y, z = math.cos(e) * math.sin(a), math.sin(e), math.cos(e) * math.cos(a)
    return tuple(distance * (x * r + y * u + z * f) for r, u, f in zip(frame.right, frame.up, frame.front))


def light_place(light, focal, frame: Frame) -> tuple[float, float, float]:
    """(azimuth°, elevation°, distance) of a light around the focal point.

    A directional light's direction (towards the light) gives azimuth and
    elevation; its distance is reported as 0.
    """
    if light_kind(light) == "directional":
        az, el, _ = place_of(light.direction, frame)
        return az, el, 0.0
    return place_of([p - f for p, f in zip(light.position, focal)], frame)


def _aims_at(light, focal) -> bool:
    """Whether a spot's axis points from its position at the focal point."""
    to_focal = [f - p for p, f in zip(light.position, focal)]
    n1 = math.sqrt(sum(c * c for c in to_focal))
    n2 = math.sqrt(sum(c * c for c in light.direction))
    if n1 == 0 or n2 == 0:
        return False
    cos = sum(a * b for a, b in zip(to_focal, light.direction)) / (n1 * n2)
    return cos > 1 - 1e-6


def move_light(scene, index, frame, azimuth=None, elevation=None, distance=None):
    """The scene with light ``index`` moved to new azimuth/elevation/distance (None: keep).

    Raises
    ------
    SceneError
        For ``lights[i].distance`` <= 0 on a point light or spot.
    """
    light = scene.lights[index]
    focal = scene.camera.focal_point
    az, el, dist = light_place(light, focal, frame)
    az = az if azimuth is None else azimuth
    el = el if elevation is None else elevation
    dist = dist if distance is None else distance
    table = light_table(scene, index)
    table.pop("homogeneous", None)
    kind = light_kind(light)
    if kind == "directional":
        table.pop("position", None)
        table["type"] = "directional"
        table["direction"] = list(place_offset(az, el, 1.0, frame))
    else:
        if dist <= 0:
            raise SceneError("must be > 0", field=f"lights[{index}].distance", value=dist)
        offset = place_offset(az, el, dist, frame)
        if kind == "spot" and _aims_at(light, focal):
            # a spot aimed at the focal point stays aimed at it
            table["direction"] = [-o for o in offset]
        table["type"] = kind
        table["position"] = [f + o for f, o in zip(focal, offset)]
    return scene.replace(f"lights[{index}]", table)


def move_eye(scene, frame, azimuth=None, elevation=None, distance=None):
    """The scene with the eye moved around the focal point (None: keep that coordinate)."""
    camera = scene.camera
    offset = [e - f for e, f in zip(camera.eye, camera.focal_point)]
    az, el, dist = place_of(offset, frame)
    az = az if azimuth is None else azimuth
    el = el if elevation is None else elevation
    dist = dist if distance is None else distance
    eye = [f + o for f, o in zip(camera.focal_point, place_offset(az, el, dist, frame))]
    return scene.replace("camera.eye", eye)
