"""The scene model: frozen dataclasses describing what phonglab shows.

A :class:`Scene` holds its objects (:class:`SceneObject`: a mesh, :class:`Geometry`,
placed in the scene, and its core ``Material``; the first one is also
``Scene.geometry`` and ``Scene.material``), a tuple of core lights, a
:class:`Camera` and the shading options. A
:class:`Lesson` wraps a scene with the text and controls of one lesson; an
:class:`Experiment` is one of its "try this" steps.

These dataclasses trust their inputs: values are checked once, at the
boundary, where a file or an edit becomes a scene
(:mod:`phonglab.scene.build`, the loader, :meth:`Scene.replace`); the parts
(:mod:`phonglab.scene.parts`) and the core objects check their own fields
when they are made. A bad field raises :class:`SceneError` naming the field
path, the bad value and what is allowed; the file loader adds the file name
and line to the same errors.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from phonglab import core
from phonglab.scene.editing import replace_field, replace_fields
from phonglab.scene.errors import SceneError, SceneErrors, did_you_mean, join_path, show_value
from phonglab.scene.objects import SceneObject
from phonglab.scene.parts import AreaLightSetup, Camera, Geometry
from phonglab.scene.schema import (
    AREA_METHODS,
    GEOMETRY_KINDS,
    INTERPOLATIONS,
    MODELS,
    PARAMETRIC_KINDS,
    RESOLUTION_RANGE,
    SCENE_DEFAULTS,
    SCENE_FIELDS,
)


@dataclass(frozen=True)
class Changes:
    """What differs between two scenes, and what showing the new one needs (:meth:`Scene.changes`).

    Attributes
    ----------
    fields : frozenset of str
        The top-level fields that differ.
    needs : frozenset of str
        What those changes need, from :data:`phonglab.scene.schema.NEEDS`:
        ``"mesh"``, ``"camera"``, ``"colours"``, ``"array"``, ``"probe"``,
        ``"default probe"``, ``"vectors"``, ``"markers"``, ``"eye"``.
    """

    fields: frozenset
    needs: frozenset

    def __contains__(self, need: str) -> bool:
        return need in self.needs

    def __bool__(self) -> bool:
        """True when showing the new scene needs anything (a new title needs nothing)."""
        return bool(self.needs)

    @property
    def colours_only(self) -> bool:
        """Only the mesh's colours change: nothing moves, no array changes place."""
        return self.needs <= {"colours"}


@dataclass(frozen=True)
class Scene:
    """Everything needed to shade and show one picture.

    Parameters
    ----------
    geometry : Geometry
        The (first) object's mesh.
    material : phonglab.core.Material
        The (first) object's material.
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
    display : str
        How the computed linear light is encoded for the screen and in
        exports: ``"srgb"`` (the IEC 61966-2-1 curve, the default) or
        ``"linear"`` (the raw values ×255, as 1990s fixed-function hardware
        did). See :mod:`phonglab.core.display`.
    exposure : float
        Radiance is multiplied by this (> 0) before it is clipped to [0, 1]
        and encoded; below 1 brings an over-exposed highlight back.
    objects : tuple of SceneObject
        Every object of the scene, the first one included: its geometry and
        material are always ``geometry`` and ``material`` (set those to change
        it). Empty for a scene written with one ``[geometry]`` and one
        ``[material]``; :attr:`all_objects` lists the objects either way.
    shadows : bool
        Cast a shadow ray from every shaded point to every point, spot and
        directional light: a light blocked by an object adds neither diffuse
        nor specular light there.
    shadow_bias : float
        Where a shadow ray starts: this far (scene units) from the surface
        point towards the light. Too small and a surface shadows itself
        (acne); too large and an object close to the point is passed over
        (light leaks under it).
    """

    geometry: Geometry
    material: core.Material
    lights: tuple
    camera: Camera
    model: str = SCENE_DEFAULTS["model"]
    interpolation: str = SCENE_DEFAULTS["interpolation"]
    two_sided: bool = SCENE_DEFAULTS["two_sided"]
    probe: tuple[float, float, float] | None = SCENE_DEFAULTS["probe"]
    title: str = SCENE_DEFAULTS["title"]
    source: str | None = None
    area_light: "AreaLightSetup | None" = None
    display: str = SCENE_DEFAULTS["display"]
    exposure: float = SCENE_DEFAULTS["exposure"]
    objects: tuple = ()
    shadows: bool = SCENE_DEFAULTS["shadows"]
    shadow_bias: float = SCENE_DEFAULTS["shadow_bias"]

    def __post_init__(self):
        object.__setattr__(self, "lights", tuple(self.lights))  # a list given in code is stored as a tuple
        objects = tuple(self.objects)
        if objects and (objects[0].geometry != self.geometry or objects[0].material != self.material):
            # the first object is the scene's geometry and material
            objects = (dataclasses.replace(objects[0], geometry=self.geometry, material=self.material),) + objects[1:]
        object.__setattr__(self, "objects", objects)

    @property
    def all_objects(self) -> tuple[SceneObject, ...]:
        """Every object, the first one included; one unnamed object for a scene without ``[[objects]]``."""
        return self.objects or (SceneObject("", self.geometry, self.material),)

    @staticmethod
    def changes(old: "Scene", new: "Scene") -> Changes:
        """Which top-level fields differ from ``old`` to ``new``, and what showing ``new`` needs.

        Read from one table, :data:`phonglab.scene.schema.SCENE_FIELDS`:
        e.g. a new material needs ``{"colours"}``, a new camera
        ``{"camera", "colours", "default probe", "vectors", "markers", "eye"}``.

        Examples
        --------
        >>> Scene.changes(scene, scene.replace("material.ks", 0.9)).needs  # doctest: +SKIP
        frozenset({'colours'})
        """
        fields = frozenset(f.name for f in SCENE_FIELDS if getattr(old, f.name) != getattr(new, f.name))
        needs = frozenset().union(*(f.needs_of(getattr(old, f.name), getattr(new, f.name))
                                    for f in SCENE_FIELDS if f.name in fields))
        return Changes(fields, needs)

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
        return replace_field(self, path, value)

    def replace_many(self, settings) -> "Scene":
        """A copy with every ``(path, value)`` in ``settings`` applied, then validated once.

        Use it for a lesson's experiment: the settings may pass through states
        that are invalid on their own (a point light becoming a spotlight,
        then getting its cone), as long as the end result is valid.
        """
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
        object.__setattr__(self, "settings", tuple((p, x) for p, x in self.settings))

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
    claims : tuple of phonglab.scene.claims.Claim
        Sentences of the lesson with the checks the test suite runs on its scene.
    check : CheckQuestion or None
        An answerable question the page marks (:mod:`phonglab.scene.check`).
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
    claims: tuple = ()
    check: object = None

    def __post_init__(self):
        object.__setattr__(self, "controls", tuple(self.controls))
        object.__setattr__(self, "experiments", tuple(self.experiments))


__all__ = [
    "AreaLightSetup",
    "Changes",
    "Camera",
    "Experiment",
    "Geometry",
    "Lesson",
    "Scene",
    "SceneObject",
    "SceneError",
    "SceneErrors",
    "AREA_METHODS",
    "GEOMETRY_KINDS",
    "PARAMETRIC_KINDS",
    "MODELS",
    "INTERPOLATIONS",
    "RESOLUTION_RANGE",
    "did_you_mean",
    "join_path",
    "show_value",
]
