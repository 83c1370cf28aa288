"""The mesh of a whole scene: every object's mesh, placed, in one PolyData that knows which object is which.

Each object's mesh is built at scale 1 around the origin
(:func:`~phonglab.render.mesh.build_mesh`), scaled by its geometry's
``scale`` and moved to its ``center``; normals are kept (the scale is the
same along every axis and positive). A scene of several objects gets one
mesh holding them all, with the object of every point and every triangle in
the arrays ``"ObjectId"`` (point and cell data), so one VTK actor shows them
and the core shades each object's points with that object's material
(:mod:`~phonglab.render.shading`). A scene of one object at the origin and
scale 1 gets exactly the mesh it always had, with no such array.

Directions point *away from the surface point*, as everywhere in phonglab.
"""

from __future__ import annotations

import functools
import os

import numpy as np
import pyvista as pv

from phonglab.render.glyphs import bounding_radius
from phonglab.render.mesh import build_mesh, closest_cell, triangles

#: the point and cell array naming each point's and each triangle's object (0 = the first)
OBJECT_ARRAY = "ObjectId"


def scene_mesh(scene) -> pv.PolyData:
    """One triangle mesh of every object of ``scene``, placed, with unit point normals in ``"Normals"``.

    Returns
    -------
    pyvista.PolyData
        A shallow copy of a cached mesh (add arrays freely; never write into
        its points, normals or ids). With several objects, ``"ObjectId"``
        (int32) in its point and cell data says which object each point and
        triangle belongs to, in the order of ``scene.all_objects``.

    Raises
    ------
    SceneError
        If a mesh file cannot be read or holds no surface.
    """
    geometries = tuple(o.geometry for o in scene.all_objects)
    if len(geometries) == 1 and _unplaced(geometries[0]):
        return build_mesh(geometries[0])
    return _cached(*mesh_key(scene)).copy(deep=False)


def mesh_key(scene) -> tuple:
    """What :func:`scene_mesh` depends on: the objects' geometries and their mesh files' modification times."""
    geometries = tuple(o.geometry for o in scene.all_objects)
    return geometries, tuple(_stamp(g) for g in geometries)


def _unplaced(geometry) -> bool:
    return not any(geometry.center) and geometry.scale == 1.0


def _stamp(geometry):
    # a mesh file's modification time: an edited file misses the cache (build_mesh reads it again)
    if geometry.kind != "file":
        return None
    try:
        return os.stat(geometry.path).st_mtime_ns
    except OSError:
        return None  # build_mesh reports it


@functools.lru_cache(maxsize=8)
def _cached(geometries, stamps) -> pv.PolyData:
    points, normals, faces, point_ids, cell_ids = [], [], [], [], []
    offset = 0
    for index, geometry in enumerate(geometries):
        mesh = build_mesh(geometry)
        p = np.asarray(mesh.points, dtype=np.float64) * geometry.scale + np.asarray(geometry.center)
        tri = triangles(mesh).astype(np.int64) + offset
        points.append(p.astype(np.float32))
        normals.append(np.asarray(mesh.point_data["Normals"], dtype=np.float32))
        faces.append(np.hstack([np.full((len(tri), 1), 3, np.int64), tri]).ravel())
        point_ids.append(np.full(mesh.n_points, index, np.int32))
        cell_ids.append(np.full(len(tri), index, np.int32))
        offset += mesh.n_points
    out = pv.PolyData(np.concatenate(points), faces=np.concatenate(faces))
    out.point_data["Normals"] = np.concatenate(normals)
    out.point_data.active_normals_name = "Normals"
    if len(geometries) > 1:
        out.point_data[OBJECT_ARRAY] = np.concatenate(point_ids)
        out.cell_data[OBJECT_ARRAY] = np.concatenate(cell_ids)
    return out


def point_objects(mesh: pv.PolyData) -> np.ndarray | None:
    """The object of every point of a :func:`scene_mesh` (None: one object)."""
    ids = mesh.point_data.get(OBJECT_ARRAY)
    return None if ids is None else np.asarray(ids)


def cell_objects(mesh: pv.PolyData) -> np.ndarray | None:
    """The object of every triangle of a :func:`scene_mesh` (None: one object)."""
    ids = mesh.cell_data.get(OBJECT_ARRAY)
    return None if ids is None else np.asarray(ids)


def object_at(mesh: pv.PolyData, point) -> int:
    """The object whose surface is nearest ``point`` (a probe on the surface: the object it lies on)."""
    ids = cell_objects(mesh)
    return 0 if ids is None else int(ids[closest_cell(mesh, point)])


def object_count(mesh: pv.PolyData) -> int:
    """How many objects a :func:`scene_mesh` holds."""
    ids = cell_objects(mesh)
    return 1 if ids is None or not len(ids) else int(ids.max()) + 1


def object_points(mesh: pv.PolyData, index: int) -> np.ndarray:
    """The points of one object of a :func:`scene_mesh`, shape (n, 3)."""
    ids = point_objects(mesh)
    points = np.asarray(mesh.points)
    return points if ids is None else points[ids == index]


def object_triangles(mesh: pv.PolyData, index: int) -> np.ndarray:
    """The corners of one object's triangles, shape (n, 3, 3), float32 (what a ray caster is given)."""
    ids = cell_objects(mesh)
    tri = triangles(mesh)
    if ids is not None:
        tri = tri[ids == index]
    return np.asarray(mesh.points, dtype=np.float32)[tri]


def smallest_radius(mesh: pv.PolyData) -> float:
    """The bounding radius of the smallest object (the arrows are sized to it, not to a wide floor)."""
    ids = point_objects(mesh)
    if ids is None:
        return bounding_radius(mesh)
    return min(bounding_radius(pv.PolyData(object_points(mesh, i))) for i in range(object_count(mesh)))


__all__ = ["scene_mesh", "mesh_key", "object_at", "point_objects", "cell_objects", "object_count", "object_points",
           "object_triangles", "smallest_radius", "OBJECT_ARRAY"]
