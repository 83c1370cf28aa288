"""phonglab.scene: scene files, lessons, validation and the effect planner.

A scene travels one way: a TOML file (or a lesson's TOML front matter) is
read and checked once into frozen dataclasses (:class:`Scene`,
:class:`Lesson`); :func:`plan` decides which lighting effects the scene calls
for, and :func:`shade` runs the core on the scene's mesh points with that plan.

This package imports NumPy and the core only: no PyVista, no VTK.
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
from phonglab.scene.paths import MESH_EXTENSIONS, PYVISTA_MESHES, mesh_file, pyvista_mesh_path
from phonglab.scene.loader import (
    lesson_files,
    list_lessons,
    load,
    load_lesson,
    load_scene,
    scene_from_dict,
)
from phonglab.scene.fieldpath import (
    field_value,
    parse_path,
    parse_setting,
    parse_value,
    scene_to_dict,
)
from phonglab.scene.planner import ScenePlan, plan, shade, viewer

__all__ = [
    "Camera",
    "Experiment",
    "Geometry",
    "Lesson",
    "Scene",
    "SceneError",
    "SceneErrors",
    "ScenePlan",
    "viewer",
    "GEOMETRY_KINDS",
    "INTERPOLATIONS",
    "MODELS",
    "PARAMETRIC_KINDS",
    "MESH_EXTENSIONS",
    "PYVISTA_MESHES",
    "field_value",
    "lesson_files",
    "list_lessons",
    "load",
    "load_lesson",
    "load_scene",
    "mesh_file",
    "parse_path",
    "parse_setting",
    "parse_value",
    "plan",
    "pyvista_mesh_path",
    "scene_from_dict",
    "scene_to_dict",
    "shade",
]
