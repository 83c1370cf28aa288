"""The page's controls: which widget edits which scene field, and how.

A :class:`Control` reads its widget's value from a scene (:meth:`Control.read`)
and writes a widget value back into a new scene (:meth:`Control.apply`). Every
value that arrives from the browser goes through :meth:`Control.apply`, which
checks its type and range first and then lets the scene check the result
(:meth:`phonglab.scene.Scene.replace`), so a refused value raises
:class:`ControlError` naming the control, the value and what is allowed, and
the previous scene stays.

Most controls edit a scene field directly (``material.shininess``,
``lights[1].attenuation[0]``, ``model``). A few present a field the way a
student thinks of it and are named like fields (see :mod:`phonglab.app.keys`):

* ``material.kd.level`` and ``material.kd.color``: an RGB coefficient as a
  strength (its largest channel, a slider) times a hue (a colour picker);
* ``lights[i].azimuth`` / ``elevation`` / ``distance``: a light's place
  around the scene's focal point, in degrees, in a :class:`Frame` taken from
  the lesson's camera (elevation above the plane across its up vector,
  azimuth 0 towards the eye, +90° to the right). For a directional light
  azimuth and elevation give the direction towards the light;
* ``camera.azimuth`` / ``elevation`` / ``distance``: the eye, the same way;
* ``lights[i].type``: point, directional or spot; the light keeps its place;
* ``view.term``: which term the mesh shows (a view option, not a scene field).

``material.shininess.log`` is the shininess slider: ``log10(α)`` from 0 to 3
(α from 1 to 1000).

Besides the widgets, :func:`field_mirrors` gives a state key per scene field
(``material__ks``, ``lights_1__position``) holding the field's value in its
file form; a value written there is checked like any other.
"""

from __future__ import annotations

import copy
import math
import numbers
import re
from dataclasses import dataclass, field
from typing import Any, Callable

from phonglab import core
from phonglab.app.keys import state_key
from phonglab.scene import SceneError
from phonglab.scene import field_value as _scene_field_value
from phonglab.scene.fieldpath import parse_path, scene_to_dict

#: the last scene read and its file form (reading every widget reuses one dict)
_last_dict: list = [None, None]


def field_value(scene, path: str):
    """The value at ``path`` in the scene's file form, as :func:`phonglab.scene.field_value`.

    Simple paths (names and indices that exist) are read from one cached
    dictionary per scene; anything else goes to the scene layer, which also
    produces its errors.
    """
    if _last_dict[0] is not scene:
        _last_dict[0], _last_dict[1] = scene, scene_to_dict(scene)
    node = _last_dict[1]
    try:
        for part in parse_path(path):
            node = node[part]
    except (KeyError, IndexError, TypeError, SceneError):
        return _scene_field_value(scene, path)
    return copy.deepcopy(node) if isinstance(node, (dict, list)) else node

#: term view choices: value shown by the view -> label
TERMS = (("color", "All terms"), ("ambient", "Ambient"), ("diffuse", "Diffuse"), ("specular", "Specular"))
#: light types a light control can switch between (ambient lights keep their type)
LIGHT_TYPES = (("point", "Point"), ("directional", "Directional"), ("spot", "Spot"))
MODELS = (("phong", "Phong"), ("blinn-phong", "Blinn-Phong"))
INTERPOLATIONS = (("flat", "Flat (per face)"), ("gouraud", "Gouraud (per vertex)"), ("pixel", "Per pixel"))
#: the shininess slider spans α = 10**0 .. 10**3
SHININESS_LOG_RANGE = (0.0, 3.0)

_HEX = re.compile(r"#[0-9a-fA-F]{6}")


class ControlError(ValueError):
    """A browser value was refused; the message says which control, the value and what is allowed."""


@dataclass(frozen=True)
class Control:
    """One widget on the page and the scene field behind it.

    Attributes
    ----------
    path : str
        The field path the widget edits (a scene field or one of the
        presentation fields listed in the module docstring).
    label : str
        The widget's label; may hold ``$...$`` maths.
    kind : str
        ``"slider"``, ``"color"``, ``"select"``, ``"switch"``, or ``"value"``
        (no widget: the state key mirrors a scene field in its file form).
    low, high, step : float
        Slider range and step (in widget units: ``log10 α`` for shininess).
    items : tuple of (value, title)
        Choices of a select.
    read : callable
        ``read(scene, view_options) -> widget value``.
    write : callable
        ``write(scene, widget value, view_options) -> (scene, view_options)``;
        the value has passed the type and range checks already.
    unit : str
        Shown after a slider's value ("°").
    fmt : str
        How the widget value is shown; ``"alpha"`` shows ``10**value``.
    """

    path: str
    label: str
    kind: str
    read: Callable
    write: Callable
    low: float = 0.0
    high: float = 1.0
    step: float = 0.01
    items: tuple = ()
    unit: str = ""
    fmt: str = "{:.2f}"
    group: str = ""

    @property
    def key(self) -> str:
        """The trame state key (:func:`phonglab.app.keys.state_key`)."""
        return state_key(self.path)

    def check(self, value):
        """The browser value as the widget's type, or :class:`ControlError`."""
        if self.kind == "slider":
            if not isinstance(value, numbers.Real) or isinstance(value, bool):
                raise ControlError(f"{self.path}: must be a number, got {_show(value)}")
            value = float(value)
            if not math.isfinite(value):
                raise ControlError(f"{self.path}: must be a finite number, got {_show(value)}")
            slack = 1e-9 * max(1.0, abs(self.high - self.low))
            if not (self.low - slack <= value <= self.high + slack):
                raise ControlError(
                    f"{self.path}: must be between {self.low:g} and {self.high:g}, got {_show(value)}"
                )
            return min(max(value, self.low), self.high)
        if self.kind == "switch":
            if not isinstance(value, bool):
                raise ControlError(f"{self.path}: must be true or false, got {_show(value)}")
            return value
        if self.kind == "select":
            allowed = [v for v, _ in self.items]
            if not isinstance(value, str) or value not in allowed:
                raise ControlError(f"{self.path}: must be one of {', '.join(allowed)}, got {_show(value)}")
            return value
        if self.kind == "value":
            return _check_plain(self.path, value)
        if self.kind == "color":
            if not isinstance(value, str) or not _HEX.fullmatch(value.strip()):
                raise ControlError(f"{self.path}: must be a colour #rrggbb, got {_show(value)}")
            return value.strip().lower()
        raise AssertionError(self.kind)

    def apply(self, scene, value, options: dict):
        """Check ``value`` and return ``(new scene, new view options)``.

        Raises
        ------
        ControlError
            The value's type or range is wrong, or the scene refuses the result.
        """
        value = self.check(value)
        try:
            return self.write(scene, value, dict(options))
        except SceneError as exc:
            raise ControlError(f"{self.path}: {_scene_reason(exc, self.path)}") from None
        except (ValueError, TypeError, ArithmeticError) as exc:  # core validation
            raise ControlError(f"{self.path}: {exc}") from None

    def same(self, a, b) -> bool:
        """Whether two widget values mean the same setting (sliders: within half a step)."""
        if self.kind == "slider":
            try:
                return abs(float(a) - float(b)) <= 0.5 * self.step
            except (TypeError, ValueError):
                return False
        return a == b

    def describe(self, scene, options) -> dict:
        """The widget as plain data for the page template."""
        spec = {
            "key": self.key,
            "path": self.path,
            "label": self.label,
            "kind": self.kind,
            "low": self.low,
            "high": self.high,
            "step": self.step,
            "items": [{"value": v, "title": t} for v, t in self.items],
            "unit": self.unit,
            "fmt": self.fmt,
            "group": self.group,
        }
        return spec


def _check_plain(path, value, depth=0):
    """A file-form value (number, bool, string, list of those); ControlError otherwise.

    The scene checks the meaning; this only keeps odd objects out.
    """
    if isinstance(value, (bool, str)) or (isinstance(value, numbers.Real)):
        if isinstance(value, str) and len(value) > 200:
            raise ControlError(f"{path}: text too long ({len(value)} characters)")
        return value
    if isinstance(value, (list, tuple)) and depth == 0 and len(value) <= 4:
        return [_check_plain(path, v, 1) for v in value]
    if value is None and path == "probe":
        return None
    raise ControlError(f"{path}: must be a number, true/false, a text or a short list, got {_show(value)}")


def _show(value) -> str:
    if isinstance(value, str):
        return repr(value[:60])
    if isinstance(value, float) and math.isnan(value):
        return "NaN"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _scene_reason(exc: SceneError, path: str = "") -> str:
    """The part of a SceneError that helps a student: problem, value, hint.

    The error's field is left out when it is the control's own (or contains it).
    """
    errors = getattr(exc, "errors", None) or [exc]
    parts = []
    for e in errors:
        text = e.problem
        if e.field and not (path.startswith(e.field) or e.field.startswith(path)):
            text = f"{e.field}: {text}"
        if e.has_value:
            text += f", got {_show(e.value)}"
        if e.hint:
            text += f"; {e.hint}"
        parts.append(text)
    return "; ".join(parts)


# ---------------------------------------------------------------------------
# colour helpers


def rgb_to_hex(rgb) -> str:
    """``(r, g, b)`` in [0, 1] (clipped) as ``#rrggbb``."""
    return "#" + "".join(f"{int(round(min(max(c, 0.0), 1.0) * 255)):02x}" for c in rgb)


def hex_to_rgb(text: str) -> tuple[float, float, float]:
    """``#rrggbb`` as three floats in [0, 1]."""
    return tuple(int(text[i : i + 2], 16) / 255.0 for i in (1, 3, 5))


def split_level(rgb) -> tuple[float, tuple[float, float, float]]:
    """An RGB coefficient as (level, hue): level = largest channel, hue = rgb / level."""
    level = max(rgb)
    if level <= 0:
        return 0.0, (1.0, 1.0, 1.0)
    return level, tuple(c / level for c in rgb)


# ---------------------------------------------------------------------------
# light placement


from phonglab.scene.editing import (  # noqa: E402  (placement and retyping live in the scene layer)
    SPOT_DEFAULTS,
    Frame,
    light_place,
    move_light,
    place_of,
    place_offset,
)
from phonglab.scene.editing import light_kind as _light_kind  # noqa: E402
from phonglab.scene.editing import move_eye as _move_eye  # noqa: E402
from phonglab.scene.editing import retype_light  # noqa: E402


def _retype_light(scene, index, kind, frame):
    """The scene with light ``index`` turned into a ``kind`` light at the same place (the frame is not needed)."""
    return retype_light(scene, index, kind)


# ---------------------------------------------------------------------------
# building the controls of a scene


def _field(path, label, kind, **kwargs) -> Control:
    """A control bound straight to a scene field."""

    def read(scene, options):
        return field_value(scene, path)

    def write(scene, value, options):
        return scene.replace(path, value), options

    return Control(path=path, label=label, kind=kind, read=read, write=write, **kwargs)


def _coefficient(name: str, symbol: str, group: str) -> list[Control]:
    """``material.NAME.level`` (slider) and ``material.NAME.color`` (hue picker)."""
    path = f"material.{name}"

    def level_read(scene, options):
        return split_level(getattr(scene.material, name))[0]

    def level_write(scene, value, options):
        _, hue = split_level(getattr(scene.material, name))
        hue = options.get(f"hue:{path}", hue)
        return scene.replace(path, [value * c for c in hue]), options

    def color_read(scene, options):
        level, hue = split_level(getattr(scene.material, name))
        return rgb_to_hex(options.get(f"hue:{path}", hue) if level == 0 else hue)

    def color_write(scene, value, options):
        level, _ = split_level(getattr(scene.material, name))
        _, hue = split_level(hex_to_rgb(value))
        options[f"hue:{path}"] = hue  # remembered while the level is 0
        return scene.replace(path, [level * c for c in hue]), options

    return [
        Control(path=f"{path}.level", label=f"${symbol}$", kind="slider", read=level_read, write=level_write,
                low=0.0, high=1.0, step=0.01, group=group),
        Control(path=f"{path}.color", label=f"${symbol}$ colour", kind="color", read=color_read,
                write=color_write, group=group),
    ]


def _shininess(group: str) -> Control:
    def read(scene, options):
        return math.log10(max(scene.material.shininess, 1e-300))

    def write(scene, value, options):
        return scene.replace("material.shininess", round(10.0**value, 6)), options

    low, high = SHININESS_LOG_RANGE
    return Control(path="material.shininess.log", label=r"shininess $\alpha$", kind="slider", read=read, write=write,
                   low=low, high=high, step=0.01, fmt="alpha", group=group)


def _light_controls(scene, index: int, frame: Frame) -> list[Control]:
    light = scene.lights[index]
    base = f"lights[{index}]"
    group = f"Light {index} ({_light_kind(light)})"
    controls: list[Control] = []
    if isinstance(light, core.AmbientLight):
        group = f"Ambient light {index}"
    else:
        def type_read(scene, options, index=index):
            return _light_kind(scene.lights[index])

        def type_write(scene, value, options, index=index):
            return _retype_light(scene, index, value, frame), options

        controls.append(Control(path=f"{base}.type", label="type (w = 1 point, w = 0 directional)", kind="select", read=type_read, write=type_write,
                                items=LIGHT_TYPES, group=group))

        def place(which):
            def read(scene, options, index=index):
                return light_place(scene.lights[index], scene.camera.focal_point, frame)[which]

            def write(scene, value, options, index=index):
                kwargs = {("azimuth", "elevation", "distance")[which]: value}
                return move_light(scene, index, frame, **kwargs), options

            return read, write

        for which, (name, label, low, high, step, unit) in enumerate(
            (("azimuth", "azimuth", -180.0, 180.0, 1.0, "°"),
             ("elevation", "elevation", -89.0, 89.0, 1.0, "°"),
             ("distance", "distance", 0.5, 12.0, 0.05, ""))
        ):
            if name == "distance" and isinstance(light, core.DirectionalLight):
                continue
            read, write = place(which)
            controls.append(Control(path=f"{base}.{name}", label=label, kind="slider", read=read, write=write,
                                    low=low, high=high, step=step, unit=unit,
                                    fmt="{:.0f}" if unit == "°" else "{:.2f}", group=group))
    # colour and intensity, every light
    controls.append(
        Control(
            path=f"{base}.color",
            label="colour",
            kind="color",
            read=lambda scene, options, index=index: rgb_to_hex(scene.lights[index].color),
            write=lambda scene, value, options, base=base: (scene.replace(f"{base}.color", list(hex_to_rgb(value))), options),
            group=group,
        )
    )
    controls.append(_field(f"{base}.intensity", "intensity", "slider", low=0.0, high=2.0, step=0.01, group=group))
    if isinstance(light, core.PointLight):  # point and spot
        for i, (name, high, step) in enumerate((("a (constant)", 2.0, 0.01), ("b (linear)", 1.0, 0.01),
                                                 ("c (quadratic)", 0.5, 0.005))):
            controls.append(_field(f"{base}.attenuation[{i}]", f"attenuation {name}", "slider",
                                   low=0.0, high=high, step=step, fmt="{:.3f}", group=group))
    if isinstance(light, core.SpotLight):
        def cutoff_read(scene, options, index=index):
            return min(scene.lights[index].cutoff, 90.0)

        def cutoff_write(scene, value, options, base=base):
            return scene.replace(f"{base}.cutoff", value), options

        def cone_read(scene, options, index=index):
            return scene.lights[index].cutoff == 180.0

        def cone_write(scene, value, options, base=base, index=index):
            key = f"cutoff:{base}"
            if value:  # remember the cone for when it comes back
                options[key] = min(scene.lights[index].cutoff, 90.0)
                return scene.replace(f"{base}.cutoff", 180.0), options
            return scene.replace(f"{base}.cutoff", options.get(key, SPOT_DEFAULTS["cutoff"])), options

        controls.append(Control(path=f"{base}.cutoff", label="cutoff", kind="slider", read=cutoff_read,
                                write=cutoff_write, low=1.0, high=90.0, step=1.0, unit="°", fmt="{:.0f}",
                                group=group))
        controls.append(Control(path=f"{base}.no_cone", label="no cone (cutoff 180°: a point light)",
                                kind="switch", read=cone_read, write=cone_write, group=group))
        controls.append(_field(f"{base}.exponent", "spot exponent", "slider", low=0.0, high=128.0, step=0.5,
                               fmt="{:.1f}", group=group))
    return controls


def _term() -> Control:
    def read(scene, options):
        return options.get("term", "color")

    def write(scene, value, options):
        options["term"] = value
        return scene, options

    return Control(path="view.term", label="show", kind="select", read=read, write=write, items=TERMS,
                   group="View")


def _eye_controls(frame: Frame) -> list[Control]:
    controls = []
    for which, (name, low, high, step, unit) in enumerate(
        (("azimuth", -180.0, 180.0, 1.0, "°"), ("elevation", -89.0, 89.0, 1.0, "°"), ("distance", 1.5, 20.0, 0.05, ""))
    ):
        def read(scene, options, which=which):
            offset = [e - f for e, f in zip(scene.camera.eye, scene.camera.focal_point)]
            return place_of(offset, frame)[which]

        def write(scene, value, options, name=name):
            return _move_eye(scene, frame, **{name: value}), options

        controls.append(Control(path=f"camera.{name}", label=f"eye {name}", kind="slider", read=read, write=write,
                                low=low, high=high, step=step, unit=unit,
                                fmt="{:.0f}" if unit else "{:.2f}", group="Eye"))
    return controls


def _geometry_controls(scene) -> list[Control]:
    from phonglab.scene import PARAMETRIC_KINDS

    if scene.geometry.kind not in PARAMETRIC_KINDS:
        return []

    def read(scene, options):
        return float(scene.geometry.resolution)

    def write(scene, value, options):
        return scene.replace("geometry.resolution", int(round(value))), options

    return [
        _field("geometry.kind", "shape", "select", items=tuple((k, k.capitalize()) for k in PARAMETRIC_KINDS),
               group="Shape"),
        Control(path="geometry.resolution", label="resolution (segments around)", kind="slider", read=read,
                write=write, low=4.0, high=256.0, step=1.0, fmt="{:.0f}", group="Shape"),
    ]


def scene_controls(scene, frame: Frame | None = None) -> list[Control]:
    """Every control for ``scene``, grouped: material, lights, eye, shape, shading, view.

    ``frame`` sets the axes of azimuth and elevation (default: the scene camera's).
    """
    frame = frame or Frame.of_camera(scene.camera)
    controls = []
    for name, symbol in (("ka", "k_a"), ("kd", "k_d"), ("ks", "k_s")):
        controls += _coefficient(name, symbol, "Material")
    controls.append(_shininess("Material"))
    for index in range(len(scene.lights)):
        controls += _light_controls(scene, index, frame)
    controls += _eye_controls(frame)
    controls += _geometry_controls(scene)
    controls.append(_field("model", "model", "select", items=MODELS, group="Shading"))
    controls.append(_field("interpolation", "interpolation", "select", items=INTERPOLATIONS, group="Shading"))
    controls.append(_field("two_sided", "two-sided lighting", "switch", group="Shading"))
    controls.append(_field("camera.infinite_viewer", "infinite viewer", "switch", group="Shading"))
    controls.append(_term())
    return controls


#: a lesson's control path -> the paths of the widgets that edit it
def widgets_for(path: str) -> tuple[str, ...]:
    """The control paths a lesson's ``controls`` entry stands for.

    ``material.kd`` gives its level slider and colour; ``lights[1].position``
    gives azimuth, elevation and distance; ``lights[1].attenuation`` its three
    coefficients; other paths stand for themselves.
    """
    if path == "material.shininess":
        return ("material.shininess.log",)
    m = re.fullmatch(r"material\.(ka|kd|ks)", path)
    if m:
        return (f"{path}.level", f"{path}.color")
    m = re.fullmatch(r"(lights\[\d+\])\.(position|direction)", path)
    if m:
        return tuple(f"{m.group(1)}.{p}" for p in ("azimuth", "elevation", "distance"))
    m = re.fullmatch(r"(lights\[\d+\])\.homogeneous", path)
    if m:
        return tuple(f"{m.group(1)}.{p}" for p in ("type", "azimuth", "elevation", "distance"))
    if path == "camera.eye":
        return ("camera.azimuth", "camera.elevation", "camera.distance")
    m = re.fullmatch(r"(lights\[\d+\])\.cutoff", path)
    if m:
        return (path, f"{m.group(1)}.no_cone")
    m = re.fullmatch(r"(lights\[\d+\])\.attenuation", path)
    if m:
        return tuple(f"{m.group(1)}.attenuation[{i}]" for i in range(3))
    return (path,)


def lesson_controls(controls: list[Control], paths) -> list[Control]:
    """The controls a lesson asks for, in its order (paths without a widget are left out)."""
    by_path = {c.path: c for c in controls}
    chosen, seen = [], set()
    for path in paths:
        for widget in widgets_for(path):
            if widget in by_path and widget not in seen:
                chosen.append(by_path[widget])
                seen.add(widget)
    return chosen


def field_mirrors(scene) -> list[Control]:
    """A value control per editable scene field: the field's file form under its own key.

    Where a widget edits the same key (``model``, ``lights[1].cutoff``), the
    widget's control is the one to use: see :func:`controls_by_key`.
    """
    paths = ["material.ka", "material.kd", "material.ks", "material.shininess", "material.emission",
             "model", "interpolation", "two_sided", "camera.infinite_viewer", "probe"]
    for index, light in enumerate(scene.lights):
        base = f"lights[{index}]"
        paths += [f"{base}.color", f"{base}.intensity"]
        if isinstance(light, core.DirectionalLight):
            paths.append(f"{base}.direction")
        elif not isinstance(light, core.AmbientLight):
            paths += [f"{base}.position", f"{base}.attenuation"]
            if isinstance(light, core.SpotLight):
                paths += [f"{base}.direction", f"{base}.cutoff", f"{base}.exponent"]
    return [_field(path, path, "value", group="fields") for path in paths]


def controls_by_key(scene, frame: Frame | None = None) -> dict:
    """State key -> control for every widget and field mirror of ``scene`` (widgets win)."""
    out = {c.key: c for c in field_mirrors(scene)}
    out.update({c.key: c for c in scene_controls(scene, frame)})
    return out


def format_value(control: Control, value) -> str:
    """A slider value as the page shows it (α for the log slider)."""
    if control.fmt == "alpha":
        alpha = 10.0**value
        return f"{alpha:.0f}" if alpha >= 10 else f"{alpha:.2f}"
    return control.fmt.format(value) + control.unit
