"""The scene model: frozen dataclasses describing what phonglab shows.

A :class:`Scene` holds one mesh (:class:`Geometry`), one core ``Material``,
a tuple of core lights, a :class:`Camera` and the shading options. A
:class:`Lesson` wraps a scene with the text and controls of one lesson.

Every dataclass checks its fields on construction and stores them in a
canonical form (vectors as tuples of three floats). A bad field raises
:class:`SceneError` naming the field path, the bad value and what is allowed;
the file loader adds the file name and line to the same errors.
"""

from __future__ import annotations

import difflib
import math
import numbers
from dataclasses import dataclass
from typing import Any

from phonglab import core

#: geometry kinds built from a formula, with a resolution
PARAMETRIC_KINDS = ("sphere", "torus", "plane", "cube", "cylinder", "supertoroid")
#: every geometry kind
GEOMETRY_KINDS = PARAMETRIC_KINDS + ("pyvista", "file")
#: reflection models the core implements
MODELS = ("phong", "blinn-phong")
#: how colours are interpolated across a triangle
INTERPOLATIONS = ("flat", "gouraud", "pixel")
#: resolution bounds for parametric meshes (segments around)
RESOLUTION_RANGE = (3, 1024)


class SceneError(ValueError):
    """A scene or lesson field is wrong.

    The message reads ``FILE:LINE: field.path: problem, got VALUE; hint``;
    the parts that are unknown are left out.

    Parameters
    ----------
    problem : str
        What is wrong, phrased as what is allowed ("must be a finite number >= 0").
    field : str, optional
        The field path ("material.shininess", "lights[1].position").
    value : object, optional
        The bad value; shown TOML-style after "got".
    hint : str, optional
        A suggestion ("did you mean \"shininess\"?").
    file : str, optional
        The file the value came from.
    line : int, optional
        The 1-based line of the value in that file.
    """

    _NO_VALUE = object()

    def __init__(self, problem, *, field=None, value=_NO_VALUE, hint=None, file=None, line=None):
        self.problem = problem
        self.field = field
        self.value = value
        self.hint = hint
        self.file = file
        self.line = line
        super().__init__(self._text())

    @property
    def has_value(self) -> bool:
        """Whether the error carries a bad value."""
        return self.value is not SceneError._NO_VALUE

    def _text(self) -> str:
        where = ""
        if self.file:
            where = f"{self.file}:{self.line}: " if self.line else f"{self.file}: "
        text = where + (f"{self.field}: " if self.field else "") + self.problem
        if self.has_value:
            text += f", got {show_value(self.value)}"
        if self.hint:
            text += f"; {self.hint}"
        return text

    def located(self, *, file=None, line=None, field=None) -> "SceneError":
        """A copy with the file, line or a field prefix filled in.

        Parameters
        ----------
        file, line : optional
            Used only where this error has none yet.
        field : str, optional
            A field path prepended to this error's own ("lights[1]" + "position").
        """
        path = self.field
        if field:
            path = join_path(field, self.field) if self.field else field
        return SceneError(
            self.problem,
            field=path,
            value=self.value,
            hint=self.hint,
            file=self.file or file,
            line=self.line or line,
        )


class SceneErrors(SceneError):
    """Several :class:`SceneError` at once, one per line of the message.

    Parameters
    ----------
    errors : list of SceneError
        At least one error; the first one's parts fill this error's attributes.
    """

    def __init__(self, errors):
        self.errors = list(errors)
        if not self.errors:
            raise ValueError("SceneErrors needs at least one error")
        first = self.errors[0]
        ValueError.__init__(self, "\n".join(str(e) for e in self.errors))
        self.problem, self.field, self.value = first.problem, first.field, first.value
        self.hint, self.file, self.line = first.hint, first.file, first.line

    def __iter__(self):
        return iter(self.errors)

    def __len__(self):
        return len(self.errors)

    def located(self, *, file=None, line=None, field=None) -> "SceneErrors":
        return SceneErrors([e.located(file=file, line=line, field=field) for e in self.errors])


def show_value(value: Any) -> str:
    """Render a value as it would be written in TOML (``true``, ``"text"``, ``[1, 2]``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "nothing"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e16:
        return str(int(value)) if value != 0 or math.copysign(1, value) > 0 else "-0"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {show_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(show_value(v) for v in value) + "]"
    if hasattr(value, "tolist"):  # NumPy scalars and arrays
        return show_value(value.tolist())
    return str(value)


def join_path(parent: str, child: str) -> str:
    """Join two field paths: ``join_path("lights[1]", "position")`` is ``lights[1].position``."""
    if not parent:
        return child
    if not child:
        return parent
    return parent + child if child.startswith("[") else f"{parent}.{child}"


def did_you_mean(word: str, allowed) -> str | None:
    """A ``did you mean "x"?`` hint for a near miss among ``allowed``, else None."""
    close = difflib.get_close_matches(str(word), [str(a) for a in allowed], n=1, cutoff=0.6)
    return f'did you mean "{close[0]}"?' if close else None


# ---------------------------------------------------------------------------
# field checks shared by the dataclasses and the file loader


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def check_number(path, value, *, low=None, high=None, low_open=False, high_open=False) -> float:
    """A finite real number within optional bounds, as float; SceneError otherwise."""
    rule = "must be a finite number"
    if low is not None and high is not None:
        rule += f" in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    elif low is not None:
        rule += f" {'>' if low_open else '>='} {low:g}"
    elif high is not None:
        rule += f" {'<' if high_open else '<='} {high:g}"
    if not _is_number(value) or not math.isfinite(value):
        raise SceneError(rule, field=path, value=value)
    x = float(value)
    if low is not None and (x < low or (low_open and x == low)):
        raise SceneError(rule, field=path, value=value)
    if high is not None and (x > high or (high_open and x == high)):
        raise SceneError(rule, field=path, value=value)
    return x


def check_int(path, value, *, low=None, high=None) -> int:
    """A whole number within optional closed bounds; SceneError otherwise."""
    rule = "must be a whole number"
    if low is not None and high is not None:
        rule += f" from {low} to {high}"
    elif low is not None:
        rule += f" >= {low}"
    ok = _is_number(value) and math.isfinite(value) and float(value).is_integer()
    if ok and low is not None and value < low:
        ok = False
    if ok and high is not None and value > high:
        ok = False
    if not ok:
        raise SceneError(rule, field=path, value=value)
    return int(value)


def check_vector(path, value, *, nonzero=False) -> tuple[float, float, float]:
    """A list of three finite numbers, as a tuple of floats; SceneError otherwise."""
    rule = "must be a list of 3 finite numbers" + (", not all zero" if nonzero else "")
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise SceneError(rule, field=path, value=value)
    if len(value) != 3:
        raise SceneError(rule, field=path, value=value, hint=f"{len(value)} given")
    if not all(_is_number(v) and math.isfinite(v) for v in value):
        raise SceneError(rule, field=path, value=value)
    out = tuple(float(v) for v in value)
    if nonzero and not any(out):
        raise SceneError(rule, field=path, value=value)
    return out


def check_choice(path, value, allowed) -> str:
    """One of the ``allowed`` strings; SceneError with a did-you-mean otherwise."""
    if not isinstance(value, str) or value not in allowed:
        rule = "must be one of " + ", ".join(f'"{a}"' for a in allowed)
        raise SceneError(rule, field=path, value=value, hint=did_you_mean(value, allowed))
    return value


def check_bool(path, value) -> bool:
    """``true`` or ``false``; SceneError otherwise (1 and "yes" are refused)."""
    if not isinstance(value, bool):
        raise SceneError("must be true or false", field=path, value=value)
    return value


def check_text(path, value) -> str:
    """A string; SceneError otherwise."""
    if not isinstance(value, str):
        raise SceneError("must be a text string", field=path, value=value)
    return value


def _collect(checks) -> None:
    """Run ``(name, check)`` pairs, raising every SceneError at once."""
    errors = []
    for check in checks:
        try:
            check()
        except SceneErrors as exc:
            errors.extend(exc.errors)
        except SceneError as exc:
            errors.append(exc)
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise SceneErrors(errors)


def _setter(obj, name, check):
    """A thunk that checks ``obj.name`` and stores the canonical value back."""

    def run():
        object.__setattr__(obj, name, check(getattr(obj, name)))

    return run


# ---------------------------------------------------------------------------
# the dataclasses


@dataclass(frozen=True)
class Geometry:
    """The mesh a scene shows.

    Parameters
    ----------
    kind : str
        One of ``"sphere"``, ``"torus"``, ``"plane"``, ``"cube"``, ``"cylinder"``,
        ``"supertoroid"`` (built from a formula), ``"pyvista"`` (a mesh shipped
        inside the pyvista package, chosen by ``name``) or ``"file"`` (any mesh
        PyVista can read, at ``path``).
    resolution : int
        Segments around, for the parametric kinds; ignored for meshes.
    name : str or None
        For ``kind="pyvista"``: which shipped mesh (see
        :data:`phonglab.scene.paths.PYVISTA_MESHES`).
    path : str or None
        For ``kind="file"``: the mesh file. The loader resolves a relative path
        against the scene file's folder, then ``assets/`` and stores it absolute.
    """

    kind: str
    resolution: int = 48
    name: str | None = None
    path: str | None = None

    def __post_init__(self):
        from phonglab.scene import paths

        _collect(
            [
                _setter(self, "kind", lambda v: check_choice("kind", v, GEOMETRY_KINDS)),
                _setter(
                    self, "resolution", lambda v: check_int("resolution", v, low=RESOLUTION_RANGE[0], high=RESOLUTION_RANGE[1])
                ),
            ]
        )
        # name for shipped meshes, an existing readable file for kind="file"
        name, path = paths.check_geometry_source(self.kind, self.name, self.path)
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "path", path)


@dataclass(frozen=True)
class Camera:
    """Where the scene is seen from.

    Parameters
    ----------
    eye, focal_point, up : tuple of 3 floats
        VTK's camera position, the point it looks at, and its up direction.
    view_angle : float
        VTK's vertical view angle in degrees, in (0, 180).
    infinite_viewer : bool
        If true, lighting uses the constant view direction
        :math:`v = (e - f)/\\lVert e - f \\rVert` instead of the direction from
        each point to the eye.
    """

    eye: tuple[float, float, float] = (0.0, 0.0, 4.0)
    focal_point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    view_angle: float = 30.0
    infinite_viewer: bool = False

    def __post_init__(self):
        _collect(
            [
                _setter(self, "eye", lambda v: check_vector("eye", v)),
                _setter(self, "focal_point", lambda v: check_vector("focal_point", v)),
                _setter(self, "up", lambda v: check_vector("up", v, nonzero=True)),
                _setter(
                    self,
                    "view_angle",
                    lambda v: check_number("view_angle", v, low=0, high=180, low_open=True, high_open=True),
                ),
                _setter(self, "infinite_viewer", lambda v: check_bool("infinite_viewer", v)),
            ]
        )
        d = [e - f for e, f in zip(self.eye, self.focal_point)]
        if not any(d):
            raise SceneError("must differ from camera.focal_point", field="eye", value=self.eye)
        # up must not be parallel to the viewing direction
        cross = (
            d[1] * self.up[2] - d[2] * self.up[1],
            d[2] * self.up[0] - d[0] * self.up[2],
            d[0] * self.up[1] - d[1] * self.up[0],
        )
        norm_d = math.sqrt(sum(c * c for c in d))
        norm_u = math.sqrt(sum(c * c for c in self.up))
        if math.sqrt(sum(c * c for c in cross)) <= 1e-9 * norm_d * norm_u:
            raise SceneError(
                "must not be parallel to the viewing direction eye - focal_point", field="up", value=self.up
            )

    @property
    def view_direction(self) -> tuple[float, float, float]:
        """The unit vector from the focal point towards the eye."""
        d = [e - f for e, f in zip(self.eye, self.focal_point)]
        n = math.sqrt(sum(c * c for c in d))
        return (d[0] / n, d[1] / n, d[2] / n)


#: how an area light's contribution is evaluated (see phonglab.core.area_irradiance)
AREA_METHODS = core.AREA_METHODS


@dataclass(frozen=True)
class AreaLightSetup:
    """A scene's area light and how its integral is evaluated.

    Parameters
    ----------
    light : phonglab.core.AreaLight
    method : str
        ``"exact"`` (Lambert's closed form), ``"point"`` (a point light at its
        centre), ``"uniform"`` or ``"stratified"`` (Monte Carlo).
    samples : int
        Monte Carlo samples per point, 1 to 4096; a fixed seed keeps the
        picture still while sliders move.
    """

    light: core.AreaLight
    method: str = "exact"
    samples: int = 64

    def __post_init__(self):
        _collect(
            [
                _setter(self, "method", lambda v: check_choice("area_light.method", v, AREA_METHODS)),
                _setter(self, "samples", lambda v: check_int("area_light.samples", v, low=1, high=4096)),
            ]
        )


@dataclass(frozen=True)
class Scene:
    """Everything needed to shade and show one picture.

    Parameters
    ----------
    geometry : Geometry
    material : phonglab.core.Material
    lights : tuple of core lights
        ``AmbientLight``, ``PointLight``, ``DirectionalLight``, ``SpotLight``.
    camera : Camera
    model : str
        ``"phong"`` or ``"blinn-phong"``.
    interpolation : str
        ``"flat"`` (one colour per triangle), ``"gouraud"`` (colours computed at
        the vertices, interpolated) or ``"pixel"`` (normals interpolated, one
        shade per pixel).
    two_sided : bool
        Negate normals facing away from the eye before shading.
    probe : tuple of 3 floats or None
        Where the vectors N, L, R, V, H are drawn; None lets the renderer pick
        the surface point nearest the eye direction.
    title : str
    source : str or None
        The file the scene came from, used in error messages.
    area_light : AreaLightSetup or None
        An optional rectangular area light (diffuse only), with how its
        integral over the light is evaluated.
    """

    geometry: Geometry
    material: core.Material
    lights: tuple
    camera: Camera
    model: str = "phong"
    interpolation: str = "gouraud"
    two_sided: bool = False
    probe: tuple[float, float, float] | None = None
    title: str = ""
    source: str | None = None
    area_light: "AreaLightSetup | None" = None

    def __post_init__(self):
        def check_lights(value):
            if not isinstance(value, (list, tuple)):
                raise SceneError("must be a list of lights", field="lights", value=value)
            kinds = tuple(getattr(core, n) for n in ("AmbientLight", "PointLight", "DirectionalLight", "SpotLight"))
            for i, light in enumerate(value):
                if not isinstance(light, kinds):
                    raise SceneError(
                        "must be a core light (AmbientLight, PointLight, DirectionalLight, SpotLight)",
                        field=f"lights[{i}]",
                        value=repr(light),
                    )
            return tuple(value)

        def check_type(name, cls):
            def check(value):
                if not isinstance(value, cls):
                    raise SceneError(f"must be a {cls.__name__}", field=name, value=repr(value))
                return value

            return check

        _collect(
            [
                _setter(self, "geometry", check_type("geometry", Geometry)),
                _setter(self, "material", check_type("material", core.Material)),
                _setter(self, "lights", check_lights),
                _setter(self, "camera", check_type("camera", Camera)),
                _setter(self, "model", lambda v: check_choice("model", v, MODELS)),
                _setter(self, "interpolation", lambda v: check_choice("interpolation", v, INTERPOLATIONS)),
                _setter(self, "two_sided", lambda v: check_bool("two_sided", v)),
                _setter(self, "probe", lambda v: None if v is None else check_vector("probe", v)),
                _setter(self, "title", lambda v: check_text("title", v)),
                _setter(self, "area_light",
                        lambda v: None if v is None else check_type("area_light", AreaLightSetup)(v)),
            ]
        )

    def replace(self, path: str, value) -> "Scene":
        """A copy with the field at ``path`` set to ``value``, validated.

        Parameters
        ----------
        path : str
            A field path as written in scene files: ``"material.ks"``,
            ``"lights[1].position"``, ``"camera.eye"``, ``"geometry.resolution"``,
            ``"model"``, ``"lights[0].homogeneous"``.
        value : object
            The new value, as it would appear in TOML (numbers, lists of three
            numbers, strings, booleans).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            Naming the path, the value and what is allowed, when the path does
            not exist or the value is not allowed there.

        Examples
        --------
        >>> scene = scene.replace("material.shininess", 100)  # doctest: +SKIP
        """
        from phonglab.scene.fieldpath import replace_field

        return replace_field(self, path, value)

    def replace_many(self, settings) -> "Scene":
        """A copy with every ``(path, value)`` in ``settings`` applied, then validated once.

        Use it for a lesson's experiment: the settings may pass through states
        that are invalid on their own (a point light becoming a spotlight,
        then getting its cone), as long as the end result is valid.
        """
        from phonglab.scene.fieldpath import replace_fields

        return replace_fields(self, settings)


@dataclass(frozen=True)
class Experiment:
    """One "try this" step of a lesson.

    Parameters
    ----------
    label : str
        Short button text.
    text : str
        What to look for, in Markdown.
    settings : tuple of (str, object)
        Field paths and values to apply with :meth:`Scene.replace`.
    """

    label: str
    text: str
    settings: tuple = ()

    def __post_init__(self):
        _collect(
            [
                _setter(self, "label", lambda v: check_text("label", v)),
                _setter(self, "text", lambda v: check_text("text", v)),
                _setter(self, "settings", lambda v: tuple((str(p), x) for p, x in v)),
            ]
        )

    def apply(self, scene: Scene) -> Scene:
        """The scene with this experiment's settings applied in order."""
        for path, value in self.settings:
            scene = scene.replace(path, value)
        return scene


@dataclass(frozen=True)
class Lesson:
    """A lesson: a scene plus the text, controls and experiments around it.

    Parameters
    ----------
    path : str
        The Markdown file.
    number : int
        Position in the lesson list.
    title, goal : str
        Heading and one-sentence aim.
    scene : Scene
        The starting scene.
    body : str
        Markdown with ``$...$`` and ``$$...$$`` maths.
    controls : tuple of str
        Field paths of the controls the lesson shows.
    experiments : tuple of Experiment
    question, answer : str
        A check-your-understanding question and its answer.
    mistake : str or None
        Name of a "common mistake" variant to show, if any.
    """

    path: str
    number: int
    title: str
    goal: str
    scene: Scene
    body: str
    controls: tuple = ()
    experiments: tuple = ()
    question: str = ""
    answer: str = ""
    mistake: str | None = None

    def __post_init__(self):
        object.__setattr__(self, "controls", tuple(self.controls))
        object.__setattr__(self, "experiments", tuple(self.experiments))


__all__ = [
    "Camera",
    "Experiment",
    "Geometry",
    "Lesson",
    "Scene",
    "SceneError",
    "SceneErrors",
    "GEOMETRY_KINDS",
    "PARAMETRIC_KINDS",
    "MODELS",
    "INTERPOLATIONS",
]
