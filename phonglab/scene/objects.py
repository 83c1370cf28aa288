"""A scene's objects: each one a named mesh with its own material, placed by a centre and a scale.

A scene file gives its objects either as one ``[geometry]`` and one
``[material]`` (one object, with no name) or as ``[[objects]]`` tables, each
with ``name``, ``geometry`` and ``material``. A :class:`SceneObject` is one of
them; ``Scene.objects`` lists them all (:mod:`phonglab.scene.model`).

Also here, because the planner needs them without building a mesh:

* the sizes of the shapes built from a formula (:data:`SPHERE_RADIUS` ...),
  which :mod:`phonglab.render.mesh` builds them with, and the box each one
  fits in at scale 1 (:data:`SHAPE_BOXES`), so :func:`object_box` bounds an
  object's mesh from its geometry alone;
* which shapes cannot shadow themselves (:data:`CONVEX_KINDS`: convex
  solids and the flat plane);
* how many triangles a geometry's mesh will have (:func:`triangle_count`),
  so a scene's total is bounded before any mesh is built.
"""

from __future__ import annotations

from dataclasses import dataclass

from phonglab import core
from phonglab.scene.errors import SceneError
from phonglab.scene.limits import mesh_vertex_count
from phonglab.scene.meshsize import mesh_counts
from phonglab.scene.schema import MAX_OBJECTS, MAX_SCENE_TRIANGLES

# ---------------------------------------------------------------------------
# the shapes built from a formula, at scale 1 (world units)

SPHERE_RADIUS = 1.0
RING_RADIUS = 0.72
TUBE_RADIUS = 0.3
#: the plane's side: it spans [-1.2, 1.2]² in z = 0, facing +z
PLANE_SIZE = 2.4
CUBE_SIDE = 1.3
CYLINDER_RADIUS = 0.65
CYLINDER_HEIGHT = 1.5

_RING = RING_RADIUS + TUBE_RADIUS
#: kind -> the half-extents (x, y, z) of the box around the origin its mesh fits in at scale 1. Meshes
#: read from files (and PyVista's) are centred and scaled to the unit sphere, so they fit the unit cube.
SHAPE_BOXES = {
    "sphere": (SPHERE_RADIUS,) * 3,
    "torus": (_RING, _RING, TUBE_RADIUS),
    "supertoroid": (_RING, _RING, TUBE_RADIUS),
    "plane": (PLANE_SIZE / 2, PLANE_SIZE / 2, 0.0),
    "cube": (CUBE_SIDE / 2,) * 3,
    "cylinder": (CYLINDER_RADIUS, CYLINDER_HEIGHT / 2, CYLINDER_RADIUS),
    "pyvista": (1.0, 1.0, 1.0),
    "file": (1.0, 1.0, 1.0),
}
#: kinds whose mesh cannot shadow itself: convex solids (sphere, cube, capped cylinder) and the flat plane
CONVEX_KINDS = ("sphere", "cube", "cylinder", "plane")

#: the largest scale of an object, and the smallest
SCALE_RANGE = (1e-3, 1e3)


@dataclass(frozen=True)
class SceneObject:
    """One object of a scene: a mesh, placed, with its material.

    Parameters
    ----------
    name : str
        How the page names it ("in shadow (blocked by the ball)"); ``""`` for
        the one object of a file written with ``[geometry]`` and ``[material]``.
    geometry : phonglab.scene.Geometry
        The mesh, with its ``center`` and ``scale``.
    material : phonglab.core.Material
    """

    name: str
    geometry: object
    material: core.Material

    @property
    def label(self) -> str:
        """Its name, or its kind of shape when it has none ("sphere")."""
        return self.name or (self.geometry.name if self.geometry.kind == "pyvista" else self.geometry.kind)


def object_box(geometry) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """``(lo, hi)``: a box the geometry's placed mesh lies in (its shape's box, scaled and moved).

    Conservative: every vertex of the mesh :func:`phonglab.render.mesh.build_mesh`
    makes, scaled by ``scale`` about the origin and moved by ``center``, lies
    inside it.
    """
    half = SHAPE_BOXES[geometry.kind]
    s = float(geometry.scale)
    lo = tuple(c - s * h for c, h in zip(geometry.center, half))
    hi = tuple(c + s * h for c, h in zip(geometry.center, half))
    return lo, hi


def cannot_shadow_itself(geometry) -> bool:
    """True for a shape that cannot shadow itself (:data:`CONVEX_KINDS`); a mesh from a file may."""
    return geometry.kind in CONVEX_KINDS


def triangle_count(geometry) -> int | None:
    """About how many triangles the geometry's mesh has (None when a file does not say).

    A closed surface of ``V`` vertices has about ``2V`` triangles; a mesh file
    says how many it has in its header.
    """
    if geometry.kind == "file" and geometry.path:
        return mesh_counts(geometry.path)[1]
    vertices = mesh_vertex_count(geometry)
    return None if vertices is None else 2 * vertices


def check_object_count(count: int, path: str = "objects") -> None:
    """Refuse more than :data:`MAX_OBJECTS` objects (before any is built)."""
    if count > MAX_OBJECTS:
        raise SceneError(f"has {count} objects, at most {MAX_OBJECTS} allowed", field=path)
    if count == 0:
        raise SceneError("must list at least one object", field=path, value=[])


def check_total_triangles(geometries, path: str = "objects") -> None:
    """Refuse objects whose meshes together pass :data:`MAX_SCENE_TRIANGLES` (before any mesh is built)."""
    counts = [triangle_count(g) or 0 for g in geometries]
    total = sum(counts)
    if total > MAX_SCENE_TRIANGLES:
        largest = max(range(len(counts)), key=counts.__getitem__)
        raise SceneError(f"the objects' meshes have about {total:,} triangles together, at most "
                         f"{MAX_SCENE_TRIANGLES:,} allowed", field=path,
                         hint=f"lower objects[{largest}].geometry.resolution (about {counts[largest]:,} triangles)")


__all__ = ["SceneObject", "object_box", "cannot_shadow_itself", "triangle_count", "check_object_count",
           "check_total_triangles", "SHAPE_BOXES", "CONVEX_KINDS", "MAX_OBJECTS", "MAX_SCENE_TRIANGLES",
           "SCALE_RANGE"]
