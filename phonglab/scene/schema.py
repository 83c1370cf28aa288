"""The scene file format: which keys each table allows, kinds, ranges and defaults.

One table per part of a scene file (``[geometry]``, ``[material]``,
``[[lights]]``, ``[camera]``, ``[area_light]``, a lesson's extra keys). The
loader, the field-path editor and the lesson reader all read these tables,
so a key is allowed in a file exactly where a field path may name it.

Material and light values are checked by the core (``phonglab.core.Material``
and the lights) and nowhere else; :data:`CORE_FIELDS` only says which TOML
shape each such key takes and, where the file's words differ from the core's,
how the rule is phrased for a scene file.
"""

from __future__ import annotations

from phonglab import core
from phonglab.core.display import DISPLAY_ENCODINGS
from phonglab.core.model import MAX_EXPOSURE

# ---------------------------------------------------------------------------
# kinds, ranges and defaults

#: geometry kinds built from a formula, with a resolution
PARAMETRIC_KINDS = ("sphere", "torus", "plane", "cube", "cylinder", "supertoroid")
#: every geometry kind
GEOMETRY_KINDS = PARAMETRIC_KINDS + ("pyvista", "file")
#: reflection models the core implements
MODELS = core.MODELS
#: how colours are interpolated across a triangle
INTERPOLATIONS = ("flat", "gouraud", "pixel")
#: resolution bounds for parametric meshes (segments around)
RESOLUTION_RANGE = (3, 1024)
#: how an area light's contribution is evaluated (see phonglab.core.area_irradiance)
AREA_METHODS = core.AREA_METHODS
#: Monte Carlo samples per point of an area light
AREA_SAMPLES_RANGE = (1, 4096)
#: how linear light is encoded for the screen (see phonglab.core.display)
DISPLAYS = DISPLAY_ENCODINGS
#: the shadow ray's offset (scene units): it starts this far from the surface point, towards the light
SHADOW_BIAS_RANGE = (0.0, 10.0)

# ---------------------------------------------------------------------------
# the scene's fields: one entry each, and what a change of it needs

#: what a change can need, for whoever shows the scene (the view, the page)
NEEDS = {
    "mesh": "build the mesh again",
    "camera": "move the view's camera",
    "colours": "shade (and encode) the mesh's colours again",
    "array": "the colours move between per-face and per-vertex arrays: a browser needs the whole view again",
    "probe": "find the probe on the surface again",
    "default probe": "a scene without a probe: the default probe, under the eye, moves with the camera",
    "vectors": "the vectors at the probe (its arrows and numbers) change",
    "markers": "the light markers and the area light's panel move or change",
    "eye": "the eye marker moves",
}

_NO_DEFAULT = object()
#: what a plain field's value may be in a file: kind -> its arguments
VALUE_KINDS = {
    "text": (),
    "bool": (),
    "choice": ("the allowed words",),
    "number": ("low or None", "high or None", "whether low itself is refused"),
    "vector": (),
}


class SceneField:
    """One top-level field of a scene: its file key, default, what a change of it needs, its value controls.

    Parameters
    ----------
    name : str
        The field of :class:`~phonglab.scene.Scene` and the key of the scene file.
    needs : iterable of str
        What a change of the field needs (keys of :data:`NEEDS`).
    default : optional
        The value when a file leaves the key out; a field without a default
        is a table (built from the file by its own reader) or required.
    mirrors : tuple of str
        The field paths that get a value control of their own (the page's
        state keys for the file form, :func:`phonglab.app.controls.field_mirrors`).
    parts : mapping str -> iterable of str, optional
        For a field that lists items (``objects``): what a change of each
        attribute of an item needs. :meth:`Scene.changes` then adds up the
        needs of the attributes that differ (a new material of the second
        object needs only the colours), and ``needs`` when the items are
        added or removed.
    value : tuple, optional
        For a plain value with a default: what a file may give, as
        ``(kind, *arguments)`` of :data:`VALUE_KINDS` (``("choice",
        MODELS)``, ``("number", low, high, low_open)``, ``("bool",)``...);
        the loader checks the file's value with it and the file writer
        writes the field back (:func:`phonglab.scene.build.option_check`).
    """

    __slots__ = ("name", "needs", "default", "mirrors", "parts", "value")

    def __init__(self, name: str, needs=(), *, default=_NO_DEFAULT, mirrors=(), parts=None, value=None):
        parts = {key: frozenset(v) for key, v in (parts or {}).items()}
        unknown = (set(needs) | set().union(*parts.values())) - set(NEEDS)
        if unknown:
            raise ValueError(f"SceneField {name!r}: unknown needs {sorted(unknown)}; allowed: {', '.join(NEEDS)}")
        if (default is not _NO_DEFAULT) != (value is not None) or (value is not None and value[0] not in VALUE_KINDS):
            raise ValueError(f"SceneField {name!r}: a field with a default needs a value rule (one of "
                             f"{', '.join(VALUE_KINDS)}), a table field none; got {value!r}")
        self.name, self.needs, self.default, self.mirrors = name, frozenset(needs), default, tuple(mirrors)
        self.parts, self.value = parts, value

    def needs_of(self, old, new) -> frozenset:
        """What changing this field from ``old`` to ``new`` needs (the needs of the parts that differ)."""
        if not self.parts or len(old) != len(new):
            return self.needs
        return frozenset().union(*(needs for key, needs in self.parts.items()
                                   if any(getattr(a, key) != getattr(b, key) for a, b in zip(old, new))))

    @property
    def option(self) -> bool:
        """A plain value with a default (``model``, ``exposure``), not a table."""
        return self.default is not _NO_DEFAULT

    def __repr__(self) -> str:
        return f"SceneField({self.name!r}, needs={sorted(self.needs)})"


#: Every top-level field of a scene, in the order of the file format. A new field is one entry here (and
#: its attribute of Scene, whose default this gives); the file keys, the defaults, how a file's value is
#: checked and written back, what the view and the page redo on a change (Scene.changes) and the field's
#: value controls all follow from it.
SCENE_FIELDS = (
    SceneField("title", default="", value=("text",)),
    SceneField("model", {"colours"}, default="phong", mirrors=("model",), value=("choice", MODELS)),
    SceneField("interpolation", {"colours", "array"}, default="gouraud", mirrors=("interpolation",),
               value=("choice", INTERPOLATIONS)),
    SceneField("two_sided", {"colours", "vectors"}, default=False, mirrors=("two_sided",), value=("bool",)),
    SceneField("probe", {"probe", "vectors"}, default=None, mirrors=("probe",), value=("vector",)),
    SceneField("display", {"colours"}, default="srgb", mirrors=("display",), value=("choice", DISPLAYS)),
    SceneField("exposure", {"colours"}, default=1.0, mirrors=("exposure",), value=("number", 0, None, True)),
    SceneField("geometry", {"mesh", "colours", "probe", "vectors"}),
    SceneField("material", {"colours"}, mirrors=tuple(f"material.{k}" for k in
                                                      ("ka", "kd", "ks", "shininess", "emission", "roughness",
                                                       "metallic"))),
    # every object, the first one included (whose geometry and material are the two fields above)
    SceneField("objects", {"mesh", "colours", "probe", "vectors"},
               parts={"name": {"vectors"}, "geometry": {"mesh", "colours", "probe", "vectors"},
                      "material": {"colours"}}),
    SceneField("shadows", {"colours"}, default=False, mirrors=("shadows",), value=("bool",)),
    SceneField("shadow_bias", {"colours"}, default=1e-3, mirrors=("shadow_bias",),
               value=("number", *SHADOW_BIAS_RANGE, False)),
    SceneField("lights", {"colours", "vectors", "markers"}),
    SceneField("camera", {"camera", "colours", "default probe", "vectors", "markers", "eye"},
               mirrors=("camera.infinite_viewer",)),
    SceneField("area_light", {"colours", "markers"}),
)
#: field name -> its entry
SCENE_FIELD = {f.name: f for f in SCENE_FIELDS}
#: a scene's options when its file leaves them out
SCENE_DEFAULTS = {f.name: f.default for f in SCENE_FIELDS if f.option}

# ---------------------------------------------------------------------------
# which keys each table allows

#: keys of a scene file's top level
SCENE_KEYS = tuple(f.name for f in SCENE_FIELDS)
#: further top-level keys of a lesson's front matter
LESSON_KEYS = ("number", "goal", "controls", "experiments", "question", "answer", "mistake", "claims", "check")
GEOMETRY_KEYS = ("kind", "resolution", "name", "path", "center", "scale")
#: an ``[[objects]]`` table: one object of a scene with several
OBJECT_KEYS = ("name", "geometry", "material")
MATERIAL_KEYS = ("ka", "kd", "ks", "shininess", "emission", "opacity", "roughness", "metallic")
MATERIAL_REQUIRED = ("ka", "kd", "ks", "shininess")
CAMERA_KEYS = ("eye", "focal_point", "up", "view_angle", "infinite_viewer")
#: the [area_light] table: the core AreaLight's fields, then how it is evaluated
AREA_LIGHT_KEYS = ("position", "edge_u", "edge_v", "color", "intensity", "method", "samples")
EXPERIMENT_KEYS = ("label", "text", "set")
#: a lesson's [check] table (phonglab.scene.check): multiple choice or a number
CHECK_CHOICE_KEYS = ("question", "choices", "correct", "feedback")
CHECK_NUMERIC_KEYS = ("question", "numeric", "tolerance", "feedback_low", "feedback_high", "feedback_right")
CHECK_KEYS = ("question", "choices", "correct", "feedback", "numeric", "tolerance", "feedback_low", "feedback_high",
              "feedback_right")
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
#: light types whose position may be given as homogeneous = [x, y, z, w]
HOMOGENEOUS_TYPES = ("point", "directional")
#: light type -> core class
LIGHT_CLASSES = {
    "ambient": core.AmbientLight,
    "point": core.PointLight,
    "directional": core.DirectionalLight,
    "spot": core.SpotLight,
}

# ---------------------------------------------------------------------------
# material, light and area-light values: shape in the file, rule in the file's words

RGB_RULE = "must be a finite number >= 0 or a list of 3 of them (RGB)"
VECTOR_RULE = "must be a list of 3 finite numbers"
NUMBER_RULE = "must be a finite number >= 0"
HOMOGENEOUS_RULE = (
    "must be a list of 4 finite numbers [x, y, z, w] with w >= 0 (w = 0 directional, w = 1 point)"
)
#: what a value of each shape must be when no rule is given (shown for a value of the wrong TOML type)
SHAPE_RULES = {
    "number": "must be a finite number",
    "rgb": RGB_RULE,
    "vector": VECTOR_RULE,
    "homogeneous": HOMOGENEOUS_RULE,
}
#: key -> (shape of its TOML value, rule in the file's words or None for the core's own words).
#: The core decides which values are allowed; the rule only phrases its refusal for a file. A value
#: above the core's upper limit is refused in the core's words (:func:`limit_rule`), which name the limit.
CORE_FIELDS = {
    "ka": ("rgb", RGB_RULE),
    "kd": ("rgb", RGB_RULE),
    "ks": ("rgb", RGB_RULE),
    "emission": ("rgb", RGB_RULE),
    "color": ("rgb", RGB_RULE),
    "diffuse": ("rgb", RGB_RULE),
    "specular": ("rgb", RGB_RULE),
    "shininess": ("number", NUMBER_RULE),
    "intensity": ("number", NUMBER_RULE),
    "exponent": ("number", NUMBER_RULE),
    "opacity": ("number", "must be a finite number in [0, 1]"),
    "roughness": ("number", "must be a finite number in [0, 1]"),
    "metallic": ("number", "must be a finite number in [0, 1]"),
    "position": ("vector", VECTOR_RULE),
    "direction": ("vector", VECTOR_RULE + ", not all zero"),
    "attenuation": ("vector", None),  # the core states the a + b·d + c·d² > 0 rule
    "cutoff": ("number", None),  # the core states the half-angle rule
    "edge_u": ("vector", None),  # the core states "not all zero" and "not parallel"
    "edge_v": ("vector", None),
    "homogeneous": ("homogeneous", HOMOGENEOUS_RULE),
}


def limit_rule(allowed: str) -> str:
    """The core's refusal of a value above its upper limit (``InvalidValue.limit`` set), in a file's words."""
    return allowed.replace("an RGB triple of them", "a list of 3 of them (RGB)")


def light_type(light) -> str:
    """The file-format type name of a core light ("spot", "point", ...)."""
    for name in ("spot", "point", "directional", "ambient"):  # SpotLight is a PointLight: test it first
        if isinstance(light, LIGHT_CLASSES[name]):
            return name
    raise TypeError(f"not a phonglab light: {light!r}")


def table_light_type(table: dict) -> str | None:
    """The type of a ``[[lights]]`` table: its ``type``, else what ``homogeneous``'s w says."""
    kind = table.get("type")
    if kind is None and "homogeneous" in table:
        hom = table["homogeneous"]
        return "directional" if isinstance(hom, (list, tuple)) and len(hom) == 4 and hom[3] == 0 else "point"
    return kind

# ---------------------------------------------------------------------------
# a lesson's executable claims: [[claims]] tables

#: keys of a ``[[claims]]`` table
CLAIM_KEYS = ("says", "about", "check", "false_when", "experiment", "set")
CLAIM_REQUIRED = ("says", "about", "check", "false_when")
#: what a claim speaks of: the model's (linear) numbers, or the picture the page shows
CLAIM_ABOUT = ("model", "picture")
#: keys of a claim's ``false_when`` table: how to make its sentence false
FALSE_WHEN_KEYS = ("set", "replace")
#: the longest check expression, in characters and in syntax-tree nodes
CLAIM_MAX_CHARS = 400
CLAIM_MAX_NODES = 80
#: what ``probe(QUANTITY)`` and ``peak``/``mean`` may measure
PROBE_QUANTITIES = ("nl", "rv", "nh", "distance", "attenuation", "spot",
                    "ambient", "diffuse", "specular", "emission", "color",
                    # Cook–Torrance's: n·v, v·h, the distribution D, the visibility V, Fresnel's F (a colour)
                    "nv", "vh", "D", "V", "F")
IMAGE_TERMS = ("ambient", "diffuse", "specular", "emission", "color")
CHANNELS = ("r", "g", "b", "max")
#: the pictures the page shows: the sum, or one term (its term buttons)
SHOWN_TERMS = ("color", "ambient", "diffuse", "specular")
ERROR_MEASURES = ("rmse", "max_error", "highlight_rmse", "peak_error", "shades")
#: function name -> (argument kinds, meaning). A kind is "number" (any number
#: expression) or a tuple of allowed words; a trailing "?" kind is optional.
CLAIM_FUNCTIONS = {
    "pow": (("number", "number"), "x to the power y"),
    "abs": (("number",), "absolute value"),
    "sqrt": (("number",), "square root"),
    "min": (("number", "number"), "the smaller of two numbers"),
    "max": (("number", "number"), "the larger of two numbers"),
    "cosd": (("number",), "cosine of an angle in degrees"),
    "acosd": (("number",), "angle in degrees whose cosine is x"),
    "probe": ((PROBE_QUANTITIES, CHANNELS + ("?",)),
              "a value at the lesson's probe point for the first directed light (colours: channel r, g, b or "
              "the largest, max)"),
    "peak": ((IMAGE_TERMS, CHANNELS + ("?",)), "the largest value of a term over the picture as the page shades it"),
    "low": ((IMAGE_TERMS, CHANNELS + ("?",)), "the smallest value of a term over the picture"),
    "mean": ((IMAGE_TERMS, CHANNELS + ("?",)), "the mean of a term over the pixels the surface covers"),
    "stretch": ((), "height over width, in pixels, of the highlight: the pixels whose specular term is at least "
                    "half its peak"),
    "rim": ((), "the dimmest lit pixel's diffuse term over the brightest one's: what is left at the edge of the "
                "lit region (a hard edge keeps much, a soft one nearly nothing)"),
    "lit_fraction": ((), "the fraction of the covered pixels a directed light reaches (diffuse > 0)"),
    "vertices": (("number?",), "the mesh's vertex count (at a given resolution, if one is given)"),
    "lit_cap": ((), "degrees from the first directed light's direction, seen from the object's centre, "
                    "to the farthest lit vertex (90 for a directional light on a sphere)"),
    "error": ((("flat", "gouraud", "pixel"), "number", ERROR_MEASURES),
              "an interpolation method's error against the exact sphere, at a resolution, for this scene"),
    "area_error": ((("point", "uniform", "stratified"), "number"),
                   "relative RMS error of a finite light's estimate against the exact form, with N samples per "
                   "point (the accuracy study's panel and floor, RMS over 4 seeds)"),
    "area_ratio": ((), "point-light approximation over the exact area-light irradiance, directly under the "
                       "panel's centre"),
    "blocked": ((), "1 when the straight line from the probe to the first directed light crosses a surface "
                    "(the point is in its shadow; the model looks only with shadows = true), else 0"),
    "sum_gap": ((CHANNELS + ("?",),), "the largest difference, over the picture's pixels, between the colour and "
                                      "the sum of its terms (the model's numbers)"),
    "albedo": ((("cook-torrance", "phong", "phong-normalised"), "number", "number"),
               "the white furnace: the fraction of the light arriving from every direction that a white surface "
               "of this model sends back towards an eye this many degrees off the normal, for a lobe width "
               "(roughness for Cook–Torrance, α for Phong)"),
    # the picture the page shows: 8-bit levels 0 to 255 of the pixels the surface covers
    "shown_mean": ((SHOWN_TERMS, CHANNELS + ("?",)), "the mean level of the picture shown"),
    "shown_median": ((SHOWN_TERMS, CHANNELS + ("?",)), "the median level of the picture shown"),
    "shown_peak": ((SHOWN_TERMS, CHANNELS + ("?",)), "the highest level of the picture shown"),
    "shown_low": ((SHOWN_TERMS, CHANNELS + ("?",)), "the lowest level of the picture shown"),
    "shown_fraction": ((SHOWN_TERMS, "number", "number", CHANNELS + ("?",)),
                       "the fraction of the covered pixels whose level lies from lo to hi"),
    "shown_levels": ((SHOWN_TERMS, CHANNELS + ("?",)), "how many different levels the picture shows"),
    "shown_probe": ((SHOWN_TERMS, CHANNELS + ("?",)), "the level of the pixel the probe is seen through"),
    "shown_sum_gap": ((CHANNELS + ("?",),), "the mean difference, in levels, between the picture of the colour "
                                            "and the sum of the pictures of its terms (clipped to 255)"),
}
#: the functions that measure the picture shown: a picture claim calls one, a model claim none
PICTURE_FUNCTIONS = tuple(name for name in CLAIM_FUNCTIONS if name.startswith("shown_"))


# limits: sized for teaching scenes, checked before any expensive step

#: largest mesh file read, in bytes (a 1M-triangle binary PLY is about 25 MB, ASCII about 60 MB)
MAX_MESH_BYTES = 128 * 1024 * 1024
#: most vertices a mesh file may hold (the Stanford dragon has 437,645)
MAX_MESH_VERTICES = 1_000_000
#: most triangles a mesh file may hold (the Stanford dragon has 871,414)
MAX_MESH_TRIANGLES = 2_000_000
#: most lights in a scene (OpenGL's fixed pipeline had 8)
MAX_LIGHTS = 16
#: largest display exposure (see phonglab.core.model: with it, every shaded value stays finite in float32)
EXPOSURE_LIMIT = MAX_EXPOSURE
#: most objects in one scene ([[objects]])
MAX_OBJECTS = 16
#: most triangles all of a scene's objects may have together: as many as one mesh file may hold
MAX_SCENE_TRIANGLES = MAX_MESH_TRIANGLES
#: largest |coordinate| of a position, direction, eye, focal point or up vector, in scene units
#: (the meshes fit the unit sphere; beyond this, distances squared overflow float32)
MAX_COORDINATE = 1e6
#: most area-light Monte Carlo evaluations for one picture: samples × shaded vertices
MAX_AREA_SAMPLE_POINTS = 50_000_000
#: largest scene or lesson file, in bytes
MAX_SCENE_FILE_BYTES = 1024 * 1024
#: deepest nesting of [ ] and { } in a scene file, lesson front matter or --set value
MAX_NESTING = 16
#: longest value text given on the command line (--set, --sweep), in characters
MAX_VALUE_CHARS = 10_000
