"""phonglab.scene: scene files, lessons, validation and the effect planner.

A scene travels one way: a TOML file (or a lesson's TOML front matter) is
read and checked once into frozen dataclasses (:class:`Scene`,
:class:`Lesson`); :func:`plan` decides which lighting effects the scene calls
for, and :func:`shade` runs the core on the scene's mesh points with that plan.
"""

from phonglab.scene.model import (
    GEOMETRY_KINDS,
    INTERPOLATIONS,
    MODELS,
    PARAMETRIC_KINDS,
    Camera,
    Experiment,
    Geometry,
    Lesson,
    Scene,
    SceneError,
    SceneErrors,
)

__all__ = [
    "Camera",
    "Experiment",
    "Geometry",
    "Lesson",
    "Scene",
    "SceneError",
    "SceneErrors",
    "GEOMETRY_KINDS",
    "INTERPOLATIONS",
    "MODELS",
    "PARAMETRIC_KINDS",
]
