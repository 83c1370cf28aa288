"""phonglab.scene: scene files, lessons, validation and the effect planner.

A scene travels one way: a TOML file (or a lesson's TOML front matter) is
read and checked once into frozen dataclasses (:class:`Scene`,
:class:`Lesson`); :func:`plan` decides which lighting effects the scene calls
for, and :func:`shade` runs the core on the scene's mesh points with that plan;
:func:`trace` gives the record of what the model used at a point (the readout's numbers).

The modules import one way, each only those listed before it::

    errors, schema -> claims -> checks -> meshsize -> paths -> limits -> objects -> parts -> build -> check
    -> fieldpath -> editing -> model -> loader -> lessons -> shadowplan -> planner

(``toml_lines`` stands alone.) ``Scene.replace`` is a method of ``model.Scene``
calling :mod:`~phonglab.scene.editing`, which works on any scene it is given.

This package imports NumPy and the core only: no PyVista, no VTK.
"""

from phonglab.scene.errors import SceneError, SceneErrors
from phonglab.scene.schema import GEOMETRY_KINDS, INTERPOLATIONS, MODELS, PARAMETRIC_KINDS
from phonglab.scene.paths import MESH_EXTENSIONS, PYVISTA_MESHES, pyvista_mesh_path
from phonglab.scene.model import Camera, Experiment, Geometry, Lesson, Scene, SceneObject
from phonglab.scene.fieldpath import field_value, parse_path, parse_setting, parse_value, scene_to_dict
from phonglab.scene.loader import lesson_files, load_scene, scene_from_dict
from phonglab.scene.lessons import Entry, catalog, list_lessons, load, load_entry, load_lesson
from phonglab.scene.planner import ScenePlan, plan, shade, trace, viewer

__all__ = [
    "Camera",
    "Entry",
    "Experiment",
    "Geometry",
    "Lesson",
    "Scene",
    "SceneObject",
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
    "catalog",
    "field_value",
    "lesson_files",
    "list_lessons",
    "load",
    "load_entry",
    "load_lesson",
    "load_scene",
    "parse_path",
    "parse_setting",
    "parse_value",
    "plan",
    "pyvista_mesh_path",
    "scene_from_dict",
    "scene_to_dict",
    "shade",
    "trace",
]
