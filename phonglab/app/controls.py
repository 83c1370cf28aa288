"""The page's controls: which widgets a scene gets, and which scene field each one edits.

Each widget is a :class:`~phonglab.app.control.Control` (its checks and how a
value is written are in :mod:`phonglab.app.control`). Most controls edit a scene field directly (``material.shininess``,
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
(α from 1 to 1000); dragging snaps to 0.01, one arrow key moves it by
:data:`SHININESS_KEY_STEP` (:mod:`phonglab.app.slider_access`).

Besides the widgets, :func:`field_mirrors` gives a state key per scene field
(``material__ks``, ``lights_1__position``) holding the field's value in its
file form; a value written there is checked like any other.

A tab keeps its controls in a :class:`ControlSet`: built once for a lesson and
again only when their set changes (a light of another type), read for every
new scene.
"""

from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass

from phonglab import core
from phonglab.app.control import Control, ControlError, hex_to_rgb, rgb_to_hex, slider_alpha, split_level
from phonglab.scene import PARAMETRIC_KINDS, Scene, SceneError, field_value, parse_path, scene_to_dict
from phonglab.scene.schema import SCENE_FIELDS

#: term view choices: value shown by the view -> label
TERMS = (("color", "All terms"), ("ambient", "Ambient"), ("diffuse", "Diffuse"), ("specular", "Specular"))
#: light types a light control can switch between (ambient lights keep their type); a point light's w = 1 and a
#: directional one's w = 0 are said in the items, which the narrow all-controls panel does not cut off
LIGHT_TYPES = (("point", "Point (w = 1)"), ("directional", "Directional (w = 0)"), ("spot", "Spot"))
MODELS = (("phong", "Phong"), ("blinn-phong", "Blinn-Phong"), ("cook-torrance", "Cook–Torrance"))
INTERPOLATIONS = (("flat", "Flat (per face)"), ("gouraud", "Gouraud (per vertex)"), ("pixel", "Per pixel"))
#: how the picture is encoded for the screen (the scene's ``display``)
DISPLAYS = (("srgb", "sRGB"), ("linear", "linear (raw)"))  # short: the chosen item fits the menu (lesson 12 says why raw)
#: the exposure slider's range: radiance × exposure before clipping (from 0.05: lesson 13's gold highlight needs it)
EXPOSURE_RANGE = (0.05, 4.0)
#: the shadow-ray offset slider, scene units: 0 shows acne, the upper end light leaking (a file allows up to 10)
SHADOW_BIAS_SLIDER = (0.0, 1.0)
#: one arrow key on it: 0.01, so 0.5 (leaking) is 50 presses away, not 500; dragging still snaps to 0.001
SHADOW_BIAS_KEY_STEP = 0.01
#: one arrow key on a light's intensity (0 to 5): 0.05, so 1 is 20 presses from 0, not 100; a drag snaps to 0.01
INTENSITY_KEY_STEP = 0.05
#: the shininess slider spans α = 10**0 .. 10**3
SHININESS_LOG_RANGE = (0.0, 3.0)
#: one arrow key on the shininess slider: 0.03 in log10 α, α × 1.07 (dragging still snaps to 0.01)
SHININESS_KEY_STEP = 0.03


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


def _field(path, label, kind, read_field=field_value, **kwargs) -> Control:
    """A control bound straight to a scene field, read with ``read_field(scene, path)``."""

    def read(scene, options):
        return read_field(scene, path)

    def write(scene, value, options):
        return scene.replace(path, value), options

    return Control(path=path, label=label, kind=kind, read=read, write=write, **kwargs)


#: the material's RGB coefficients with a level slider and a colour each: (field, symbol)
COEFFICIENTS = (("ka", "k_a"), ("kd", "k_d"), ("ks", "k_s"))


def _hue_key(path: str) -> str:
    """The tab's option that remembers the hue of coefficient ``path`` while its level is 0."""
    return f"hue:{path}"


def keep_hues(old, new, options) -> dict:
    """``options`` remembering the hue of each material coefficient ``new`` sets to 0 from a level above 0.

    An experiment that sets ``material.kd = 0`` (lesson 1's "Ambient only")
    otherwise left nothing to bring the colour back: the colour swatch turned
    white, and the k_d slider raised again gave a white material. The hue is
    what the swatch shows and the slider uses while the level is 0, as after
    a slider step to 0.
    """
    for name, _ in COEFFICIENTS:
        level, hue = split_level(getattr(old.material, name))
        if level > 0 and split_level(getattr(new.material, name))[0] == 0:
            options[_hue_key(f"material.{name}")] = hue
    return options


def _coefficient(name: str, symbol: str, group: str) -> list[Control]:
    """``material.NAME.level`` (slider) and ``material.NAME.color`` (hue picker)."""
    path = f"material.{name}"

    def level_read(scene, options):
        return split_level(getattr(scene.material, name))[0]

    def level_write(scene, value, options):
        _, hue = split_level(getattr(scene.material, name))
        hue = options.get(_hue_key(path), hue)
        return scene.replace(path, [value * c for c in hue]), options

    def color_read(scene, options):
        level, hue = split_level(getattr(scene.material, name))
        return rgb_to_hex(options.get(_hue_key(path), hue) if level == 0 else hue)

    def color_write(scene, value, options):
        level, _ = split_level(getattr(scene.material, name))
        _, hue = split_level(hex_to_rgb(value))
        options[_hue_key(path)] = hue  # remembered while the level is 0
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
        return scene.replace("material.shininess", slider_alpha(value)), options

    low, high = SHININESS_LOG_RANGE
    return Control(path="material.shininess.log", label=r"shininess $\alpha$", kind="slider", read=read, write=write,
                   low=low, high=high, step=0.01, fmt="alpha", group=group, key_step=SHININESS_KEY_STEP,
                   models=core.PHONG_MODELS)


def _light_controls(scene, index: int, frame: Frame, read_field) -> list[Control]:
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

        controls.append(Control(path=f"{base}.type", label="light type", kind="select", read=type_read, write=type_write,
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
    # up to 5: lesson 7's lamp under inverse-square fall-off needs 5 to light its floor
    controls.append(_field(f"{base}.intensity", "intensity", "slider", read_field, low=0.0, high=5.0, step=0.01,
                           group=group, key_step=INTENSITY_KEY_STEP))
    if isinstance(light, core.PointLight):  # point and spot
        # c reaches 1: the physical inverse square (0, 0, 1) of lesson 7
        for i, (name, high, step) in enumerate((("a (constant)", 2.0, 0.01), ("b (linear)", 1.0, 0.01),
                                                 ("c (quadratic)", 1.0, 0.005))):
            controls.append(_field(f"{base}.attenuation[{i}]", f"attenuation {name}", "slider", read_field,
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
        controls.append(_field(f"{base}.exponent", "spot exponent", "slider", read_field, low=0.0, high=128.0, step=0.5,
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


def _geometry_controls(scene, read_field) -> list[Control]:
    if scene.geometry.kind not in PARAMETRIC_KINDS:
        return []

    def read(scene, options):
        return float(scene.geometry.resolution)

    def write(scene, value, options):
        return scene.replace("geometry.resolution", int(round(value))), options

    return [
        _field("geometry.kind", "shape", "select", read_field, items=tuple((k, k.capitalize()) for k in PARAMETRIC_KINDS),
               group="Shape"),
        Control(path="geometry.resolution", label="resolution (segments around)", kind="slider", read=read,
                write=write, low=4.0, high=256.0, step=1.0, fmt="{:.0f}", group="Shape"),
    ]


def scene_controls(scene, frame: Frame | None = None, *, read_field=field_value) -> list[Control]:
    """Every control for ``scene``, grouped: material, lights, eye, shape, shading, view.

    ``frame`` sets the axes of azimuth and elevation (default: the scene camera's);
    ``read_field(scene, path)`` reads a field's file form (default:
    :func:`phonglab.scene.field_value`).
    """
    frame = frame or Frame.of_camera(scene.camera)
    controls = []
    for name, symbol in COEFFICIENTS:
        controls += _coefficient(name, symbol, "Material")
    controls.append(_shininess("Material"))
    # Cook–Torrance's lobe: roughness (α_GGX = roughness²) and how metallic the surface is
    controls.append(_field("material.roughness", "roughness", "slider", read_field, low=0.0, high=1.0, step=0.01,
                           group="Material", models=("cook-torrance",)))
    controls.append(_field("material.metallic", "metallic", "slider", read_field, low=0.0, high=1.0, step=0.01,
                           group="Material", models=("cook-torrance",)))
    for index in range(len(scene.lights)):
        controls += _light_controls(scene, index, frame, read_field)
    controls += _eye_controls(frame)
    controls += _geometry_controls(scene, read_field)
    controls.append(_field("model", "model", "select", read_field, items=MODELS, group="Shading"))
    controls.append(_field("interpolation", "interpolation", "select", read_field, items=INTERPOLATIONS,
                           group="Shading"))
    controls.append(_field("two_sided", "two-sided lighting", "switch", read_field, group="Shading"))
    controls.append(_field("camera.infinite_viewer", "infinite viewer", "switch", read_field, group="Shading"))
    controls += _shadow_controls(read_field)
    controls += _display_controls(read_field)
    controls.append(_term())
    return controls


def _shadow_controls(read_field) -> list[Control]:
    """The shadow switch (the scene's ``shadows``) and the shadow ray's offset (``shadow_bias``, scene units)."""
    return [
        _field("shadows", "shadows", "switch", read_field, group="Shadows"),
        Control(path="shadow_bias", label="shadow-ray offset (bias)", kind="slider",
                read=lambda scene, options: float(scene.shadow_bias),
                write=lambda scene, value, options: (scene.replace("shadow_bias", value), options),
                low=SHADOW_BIAS_SLIDER[0], high=SHADOW_BIAS_SLIDER[1], step=0.001, fmt="{:.3f}", group="Shadows",
                key_step=SHADOW_BIAS_KEY_STEP),
    ]


def _display_controls(read_field) -> list[Control]:
    """The display encoding (sRGB or linear) and the exposure, as the scene's ``display`` and ``exposure``."""
    return [
        _field("display", "encoding", "select", read_field, items=DISPLAYS, group="Display"),
        Control(path="exposure", label="exposure (× radiance)", kind="slider",
                read=lambda scene, options: float(scene.exposure),
                write=lambda scene, value, options: (scene.replace("exposure", value), options),
                low=EXPOSURE_RANGE[0], high=EXPOSURE_RANGE[1], step=0.05, group="Display"),
    ]


def cone_switch(path: str) -> str | None:
    """The "no cone" switch that goes with the spot cutoff slider ``path`` (``lights[1].cutoff``), else None."""
    m = re.fullmatch(r"(lights\[\d+\])\.cutoff", path)
    return f"{m.group(1)}.no_cone" if m else None


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
    cone = cone_switch(path)
    if cone:
        return (path, cone)
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


def field_mirrors(scene, *, read_field=field_value) -> list[Control]:
    """A value control per editable scene field: the field's file form under its own key.

    Where a widget edits the same key (``model``, ``lights[1].cutoff``), the
    widget's control is the one to use: see :func:`controls_by_key`.
    """
    paths = [path for f in SCENE_FIELDS for path in f.mirrors]  # the scene's own (the file format's table)
    for index, light in enumerate(scene.lights):
        base = f"lights[{index}]"
        paths += [f"{base}.color", f"{base}.intensity"]
        if isinstance(light, core.DirectionalLight):
            paths.append(f"{base}.direction")
        elif not isinstance(light, core.AmbientLight):
            paths += [f"{base}.position", f"{base}.attenuation"]
            if isinstance(light, core.SpotLight):
                paths += [f"{base}.direction", f"{base}.cutoff", f"{base}.exponent"]
    return [_field(path, path, "value", read_field, group="fields") for path in paths]


def controls_by_key(scene, frame: Frame | None = None, *, read_field=field_value,
                    widgets: list[Control] | None = None) -> dict:
    """State key -> control for every widget and field mirror of ``scene`` (widgets win).

    ``widgets`` are the scene's widgets when already built by :func:`scene_controls`.
    """
    out = {c.key: c for c in field_mirrors(scene, read_field=read_field)}
    if widgets is None:
        widgets = scene_controls(scene, frame, read_field=read_field)
    out.update({c.key: c for c in widgets})
    return out


def _view_switch(path: str, label: str, option: str) -> Control:
    """A switch that sets a view option (``options[option]``), not a scene field."""
    return Control(
        path=path,
        label=label,
        kind="switch",
        read=lambda scene, options: bool(options.get(option, False)),
        write=lambda scene, value, options: (scene, {**options, option: value}),
        group="View",
    )


#: the switch that shows a lesson's common mistake in the view (a view option, not a scene field)
MISTAKE_SWITCH = _view_switch("view.mistake", "show the mistake", "mistake")
#: the switch that shows the scene under Phong and under Cook–Torrance below the view (a view option)
COMPARE_SWITCH = _view_switch("view.compare", "Phong beside Cook–Torrance", "compare")
#: the switch that hides the arrows at the probe, to see the surface under them (a view option)
ARROWS_SWITCH = _view_switch("view.arrows_hidden", "hide the arrows", "arrows_hidden")


#: a control that reads the view options, not the scene: read again for every scene
_OPTIONS = frozenset(("view options",))


def fields_read(path: str) -> frozenset:
    """The scene's top-level fields a control at ``path`` reads its value from.

    A field's own (``material.ks.level`` reads ``material``); a light's place
    is measured around the camera's focal point, so a light's controls read
    ``camera`` too; a view option (``view.term``) reads no scene field.
    """
    top = re.match(r"[A-Za-z_]*", path).group(0)
    if top == "view":
        return _OPTIONS
    return frozenset(("lights", "camera")) if top == "lights" else frozenset((top,))


def controls_shape(scene) -> tuple:
    """What decides which controls a scene gets: its light types and whether its shape is parametric."""
    return tuple(_light_kind(light) for light in scene.lights), scene.geometry.kind in PARAMETRIC_KINDS


class ControlSet:
    """The controls of one tab's lesson: built when their set changes, read for every new scene.

    Parameters
    ----------
    frame : Frame
        The axes of azimuth and elevation (from the lesson's camera).
    lesson_paths : sequence of str
        The lesson's ``controls``: the widgets it shows first (:func:`lesson_controls`).
    extra : dict
        State key -> control for controls the scene does not decide (the
        mistake switch).

    Attributes
    ----------
    widgets : list of Control
        Every widget, in page order.
    chosen : list of Control
        The lesson's widgets, in its order.
    by_key : dict
        State key -> control, for widgets, field mirrors and ``extra``.

    Notes
    -----
    Reading the widgets of a scene reads many fields of its file form; the set
    makes that form once per scene (and only for this tab). A new scene whose
    view options are unchanged has only the controls of the fields that
    changed (:meth:`Scene.changes`, :func:`fields_read`) read again: a
    shininess slider reads one control, not a hundred.
    """

    def __init__(self, frame: Frame, lesson_paths=(), extra: dict | None = None):
        self.frame = frame
        self.lesson_paths = tuple(lesson_paths)
        self.extra = dict(extra or {})
        self.widgets: list[Control] = []
        self.chosen: list[Control] = []
        self.by_key: dict = dict(self.extra)
        self._shape = None
        self._form = (None, None)  # (scene, its file form)
        self._read = None  # (scene, view options, values) of the last values()
        self._readers: dict = {}  # changed fields -> the keys whose controls read them (or read the options)

    def update(self, scene) -> bool:
        """Make the set fit ``scene``; True when it was (re)built, False when it already fitted."""
        shape = controls_shape(scene)
        if shape == self._shape:
            return False
        self.widgets = scene_controls(scene, self.frame, read_field=self.read_field)
        self.chosen = lesson_controls(self.widgets, self.lesson_paths)
        self.by_key = controls_by_key(scene, read_field=self.read_field, widgets=self.widgets)
        self.by_key.update(self.extra)
        self._shape = shape
        self._read = None
        self._readers = {}
        return True

    def values(self, scene, options: dict) -> dict:
        """State key -> widget value of every control for ``scene`` (a new dict)."""
        last = self._read
        if last is None or last[1] != options or last[2].keys() != self.by_key.keys():
            values = {key: control.read(scene, options) for key, control in self.by_key.items()}
        else:
            # the same options: what the scene's changed fields feed is all that can differ
            changed = Scene.changes(last[0], scene).fields if last[0] is not scene else frozenset()
            values = dict(last[2])
            for key in self._reading(changed):
                values[key] = self.by_key[key].read(scene, options)
        self._read = (scene, dict(options), values)
        return dict(values)

    def _reading(self, changed: frozenset) -> tuple:
        """The keys whose controls read any of the ``changed`` fields, or the view options."""
        keys = self._readers.get(changed)
        if keys is None:
            keys = self._readers[changed] = tuple(
                key for key, control in self.by_key.items()
                if (fields := fields_read(control.path)) is _OPTIONS or not fields.isdisjoint(changed))
        return keys

    def file_form(self, scene) -> dict:
        """:func:`~phonglab.scene.scene_to_dict` of ``scene``, made once for the last scene asked (do not change it)."""
        if self._form[0] is not scene:
            self._form = (scene, scene_to_dict(scene))
        return self._form[1]

    def read_field(self, scene, path: str):
        """The value at ``path`` in the scene's file form, as :func:`phonglab.scene.field_value`.

        Simple paths (names and indices that exist) are read from the file
        form of the last scene read; anything else goes to the scene layer,
        which also produces its errors.
        """
        node = self.file_form(scene)
        try:
            for part in parse_path(path):
                node = node[part]
        except (KeyError, IndexError, TypeError, SceneError):
            return field_value(scene, path)
        return copy.deepcopy(node) if isinstance(node, (dict, list)) else node


