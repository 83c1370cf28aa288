"""Triangle meshes for a scene's :class:`~phonglab.scene.Geometry`, and points on them.

Every mesh :func:`build_mesh` returns is made of triangles only and carries
unit point normals in the point array ``"Normals"``. The parametric kinds are
sized to sit inside the unit sphere around the origin (the plane's corners
reach a little further), so that the default camera (eye at (0, 0, 4), 30°
view angle) frames each of them; meshes read from files are centred and
scaled to the same unit sphere. A geometry's ``center`` and ``scale`` place
the mesh in a scene (:func:`phonglab.render.objects.scene_mesh`), not here.

Directions point *away from the surface point*, as everywhere in phonglab.
"""

from __future__ import annotations

import functools
import os
import warnings

import weakref

import numpy as np
import pyvista as pv
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

from phonglab.render._vtk import quiet_vtk
from phonglab.scene import SceneError
from phonglab.scene.meshsize import check_mesh_size
# the sizes of the parametric shapes (world units) are the scene layer's: its planner bounds objects by them
from phonglab.scene.objects import (
    CUBE_SIDE,
    CYLINDER_HEIGHT,
    CYLINDER_RADIUS,
    PLANE_SIZE,
    RING_RADIUS,
    SPHERE_RADIUS,
    TUBE_RADIUS,
)
#: superquadric roundness of the supertoroid (1 = a torus, smaller = boxier)
SUPERTOROID_ROUNDNESS = 0.4
#: angle above which an edge of a read mesh stays sharp when normals are computed
FEATURE_ANGLE = 60.0


def build_mesh(geometry) -> pv.PolyData:
    """The triangle mesh of a geometry, with unit point normals.

    Parameters
    ----------
    geometry : phonglab.scene.Geometry
        ``kind`` picks the shape; ``resolution`` is the number of segments
        around for the parametric kinds; ``name`` picks a mesh shipped with
        PyVista (``kind="pyvista"``); ``path`` a mesh file (``kind="file"``).

    Returns
    -------
    pyvista.PolyData
        Triangles only, point normals in ``"Normals"`` (float32). Meshes are
        cached per geometry: the result is a shallow copy of the cached mesh,
        so add arrays freely but never write into its points or normals.

    Raises
    ------
    SceneError
        If a mesh file cannot be read or holds no surface.

    Notes
    -----
    Resolution ``n`` gives: a sphere with ``n`` segments around the vertical
    axis and ``n/2`` from pole to pole (poles on ±y); a torus and supertoroid
    with ``n`` segments around the ring and ``n/2`` around the tube (ring in
    the xy plane); an ``n × n`` plane in the xy plane facing +z; a cube with
    ``n/4`` segments along each edge; a y-axis cylinder with ``n`` sides.
    """
    if geometry.kind == "file":
        try:
            stamp = os.stat(geometry.path).st_mtime_ns
        except OSError as exc:
            raise SceneError(f"cannot read the mesh file: {exc.strerror}", field="geometry.path",
                             value=geometry.path) from None
        cached = _cached_mesh(geometry, stamp)
    else:
        cached = _cached_mesh(geometry, None)
    return cached.copy(deep=False)


@functools.lru_cache(maxsize=32)
def _cached_mesh(geometry, stamp) -> pv.PolyData:
    # stamp (the file's modification time) makes an edited file miss the cache
    if geometry.kind in ("pyvista", "file"):
        mesh = _fit_unit_sphere(_read_surface(geometry))
    else:
        mesh = _parametric(geometry.kind, int(geometry.resolution))
    return _finish(mesh)


def _parametric(kind: str, n: int) -> pv.PolyData:
    """A formula-built shape at resolution ``n``."""
    half = max(3, n // 2)
    if kind == "sphere":
        # VTK counts latitude *points* pole to pole: half + 1 of them make half segments
        return pv.Sphere(radius=SPHERE_RADIUS, direction=(0, 1, 0), theta_resolution=n, phi_resolution=half + 1)
    if kind == "torus":
        return pv.ParametricTorus(
            ringradius=RING_RADIUS, crosssectionradius=TUBE_RADIUS, u_res=n, v_res=half, w_res=1
        )
    if kind == "supertoroid":
        return pv.ParametricSuperToroid(
            ringradius=RING_RADIUS,
            crosssectionradius=TUBE_RADIUS,
            n1=SUPERTOROID_ROUNDNESS,
            n2=SUPERTOROID_ROUNDNESS,
            u_res=n,
            v_res=half,
            w_res=1,
        )
    if kind == "plane":
        return pv.Plane(direction=(0, 0, 1), i_size=PLANE_SIZE, j_size=PLANE_SIZE, i_resolution=n, j_resolution=n)
    if kind == "cube":
        h = CUBE_SIDE / 2
        return pv.Box(bounds=(-h, h, -h, h, -h, h), level=max(0, n // 4 - 1), quads=True)
    if kind == "cylinder":
        return pv.Cylinder(
            direction=(0, 1, 0), radius=CYLINDER_RADIUS, height=CYLINDER_HEIGHT, resolution=n, capping=True
        )
    raise SceneError("has no mesh builder", field="geometry.kind", value=kind)  # pragma: no cover


def _read_surface(geometry) -> pv.PolyData:
    """The surface of a shipped or user mesh file, as PolyData."""
    if geometry.kind == "pyvista":
        from phonglab.scene.paths import pyvista_mesh_path

        try:
            path = str(pyvista_mesh_path(geometry.name))
        except SceneError as exc:
            raise exc.located(field="geometry") from None
        field, value = "geometry.name", geometry.name
    else:
        path, field, value = geometry.path, "geometry.path", geometry.path
        try:
            check_mesh_size(path)  # again: the file may have changed since the scene was loaded
        except SceneError as exc:
            raise exc.located(field="geometry") from None
    try:
        with warnings.catch_warnings(), quiet_vtk():
            warnings.simplefilter("ignore")  # the reader's own complaint; ours follows
            data = pv.read(path)
    except Exception as exc:  # readers raise many kinds; the message names the file
        reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0][:200]
        raise SceneError(f"cannot be read as a mesh ({reason})", field=field, value=value) from None
    if isinstance(data, pv.MultiBlock):
        data = data.combine()
    if not isinstance(data, pv.PolyData):
        data = data.extract_surface(algorithm="dataset_surface")
    return _checked_surface(data, field, value)


def _checked_surface(data, field: str, value) -> pv.PolyData:
    """The polygons of ``data`` as a clean triangle mesh, its points and faces checked.

    Refused: a point that is not finite, a face naming a point the file does
    not have, and a mesh with no triangle of non-zero size left after
    merging duplicate points.
    """
    # every corner of every polygon and strip must name a point of the file, before any filter runs
    for cells in (data.GetPolys(), data.GetStrips()):
        ids = vtk_to_numpy(cells.GetConnectivityArray()) if cells is not None else np.zeros(0)
        if ids.size and (ids.min() < 0 or ids.max() >= data.n_points):
            raise SceneError(f"has a face naming a vertex it does not have (it has {data.n_points} vertices)",
                             field=field, value=value)
    # keep the polygons only (strips become triangles): lines and vertices are not shaded
    data = data.triangulate()
    points = np.asarray(data.points)
    if points.size and not np.isfinite(points).all():
        bad = int(np.flatnonzero(~np.isfinite(points).all(axis=1))[0])
        raise SceneError(f"has a vertex that is not a finite number (vertex {bad}: {points[bad].tolist()})",
                         field=field, value=value)
    faces = np.asarray(data.faces) if data.n_faces else np.zeros(0, dtype=int)
    data = pv.PolyData(data.points, faces=faces) if faces.size else pv.PolyData()
    if data.n_cells == 0:
        raise SceneError("holds no surface (no polygons) to shade", field=field, value=value)
    with quiet_vtk():
        data = data.clean()
    # merging duplicate points turns a zero-size triangle into a line or a point: keep the polygons
    data = data.triangulate()
    polys = np.asarray(data.faces) if data.n_faces else np.zeros(0, dtype=int)
    if polys.size == 0:
        raise SceneError("holds no surface to shade: every triangle has zero area", field=field, value=value)
    return pv.PolyData(data.points, faces=polys)


def _fit_unit_sphere(mesh: pv.PolyData) -> pv.PolyData:
    """Centre a mesh on the origin and scale it to fit the unit sphere."""
    points = np.asarray(mesh.points, dtype=np.float64)
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(points - centre, axis=1).max())
    mesh = mesh.copy()
    mesh.points = (points - centre) / (radius if radius > 0 else 1.0)
    return mesh


def _finish(mesh: pv.PolyData) -> pv.PolyData:
    """Triangulate, keep only unit float32 point normals."""
    mesh = mesh.triangulate()
    normals = mesh.point_data.get("Normals")
    if normals is None:
        closed = mesh.n_open_edges == 0
        mesh = mesh.compute_normals(
            cell_normals=False,
            point_normals=True,
            split_vertices=True,
            feature_angle=FEATURE_ANGLE,
            consistent_normals=True,
            auto_orient_normals=closed,
        )
        normals = mesh.point_data["Normals"]
    out = pv.PolyData(np.asarray(mesh.points, dtype=np.float32), faces=mesh.faces)
    n = np.asarray(normals, dtype=np.float64)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(length > 0, n / np.where(length > 0, length, 1.0), 0.0)
    out.point_data["Normals"] = n.astype(np.float32)
    out.point_data.active_normals_name = "Normals"
    return out


def triangles(mesh: pv.PolyData) -> np.ndarray:
    """The (n_triangles, 3) point ids of a triangle mesh."""
    return np.asarray(mesh.faces).reshape(-1, 4)[:, 1:]


def face_centroids_normals(mesh: pv.PolyData) -> tuple[np.ndarray, np.ndarray]:
    """Centroid and unit normal of every triangle.

    The geometric normal ``(b - a) × (c - a)`` is flipped where it disagrees
    with the mean of the triangle's point normals, so faces point the same
    way as the smooth normals whatever the winding of the file.

    Returns
    -------
    centroids, normals : ndarray, shape (n_triangles, 3), float32
    """
    tri = triangles(mesh)
    p = np.asarray(mesh.points, dtype=np.float64)[tri]
    centroids = p.mean(axis=1)
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    smooth = np.asarray(mesh.point_data["Normals"], dtype=np.float64)[tri].sum(axis=1)
    face = np.where((np.einsum("ij,ij->i", face, smooth) < 0)[:, None], -face, face)
    length = np.linalg.norm(face, axis=1, keepdims=True)
    # a degenerate triangle (zero area) falls back to its smooth normal
    use_smooth = length[:, 0] <= 0
    face[use_smooth] = smooth[use_smooth]
    length = np.linalg.norm(face, axis=1, keepdims=True)
    face = face / np.where(length > 0, length, 1.0)
    return centroids.astype(np.float32), face.astype(np.float32)


#: (what, id(mesh)) -> (a weak reference to the mesh, the MTimes of its points and triangles, the value);
#: an entry goes when its mesh does (PolyData is not hashable, so not a WeakKeyDictionary)
_PER_MESH: dict[tuple, tuple] = {}


def _per_mesh(mesh: pv.PolyData, what: str, make):
    """``make(mesh)``, made once per mesh and again only when its points or triangles change (not its colours)."""
    stamp = (mesh.GetPoints().GetMTime(), mesh.GetPolys().GetMTime())
    key = (what, id(mesh))
    cached = _PER_MESH.get(key)
    if cached is not None and cached[0]() is mesh and cached[1] == stamp:
        return cached[2]
    value = make(mesh)
    if cached is None or cached[0]() is not mesh:
        weakref.finalize(mesh, _PER_MESH.pop, key, None)
    _PER_MESH[key] = (weakref.ref(mesh), stamp, value)
    return value


def _locator(mesh: pv.PolyData) -> vtk.vtkStaticCellLocator:
    """The mesh's cell locator, built once and rebuilt only when its points or triangles change.

    New colours (point data) keep it: a turn of the view casts rays on the same mesh every time.
    """

    def build(mesh):
        locator = vtk.vtkStaticCellLocator()
        locator.SetDataSet(mesh)
        locator.BuildLocator()
        return locator

    return _per_mesh(mesh, "locator", build)


def closed_outward(mesh: pv.PolyData) -> bool:
    """Whether the triangle mesh bounds a solid with every face wound outwards (counter-clockwise seen from outside).

    Then a face turned away from an eye outside the solid is always behind
    another face, and leaving it out changes no pixel. Exact and
    conservative: every edge must be run once in each direction by two
    triangles (closed, manifold, consistently wound), and the signed volume
    must be positive. A mesh whose faces do not share their points (a cube
    with sharp normals) does not qualify. Kept per mesh until its points or
    triangles change.
    """
    return _per_mesh(mesh, "closed outward", _closed_outward)


def _closed_outward(mesh: pv.PolyData) -> bool:
    tri = triangles(mesh).astype(np.int64)
    if not len(tri) or mesh.n_cells != len(tri):
        return False
    n = np.int64(mesh.n_points)
    starts, ends = tri.ravel(), np.roll(tri, -1, axis=1).ravel()  # the edges a->b of every triangle
    forward, backward = np.sort(starts * n + ends), np.sort(ends * n + starts)
    if not (np.all(forward[1:] != forward[:-1]) and np.array_equal(forward, backward)):
        return False
    p = np.asarray(mesh.points, dtype=np.float64)[tri]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum()) > 0.0


def surface_point(mesh: pv.PolyData, point) -> tuple[np.ndarray, np.ndarray]:
    """The mesh point closest to ``point`` and the smooth normal there.

    The normal is the barycentric blend of the triangle's point normals,
    normalised: the normal that pixel shading uses at that spot.

    Returns
    -------
    point, normal : ndarray, shape (3,), float64
    """
    locator = _locator(mesh)
    closest = [0.0, 0.0, 0.0]
    cell_id, sub_id, dist2 = vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
    locator.FindClosestPoint([float(c) for c in point], closest, cell_id, sub_id, dist2)
    return _blend_normal(mesh, int(cell_id), np.asarray(closest))


def closest_cell(mesh: pv.PolyData, point) -> int:
    """The id of the triangle nearest ``point`` (the one :func:`surface_point` lands on)."""
    closest = [0.0, 0.0, 0.0]
    cell_id, sub_id, dist2 = vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
    _locator(mesh).FindClosestPoint([float(c) for c in point], closest, cell_id, sub_id, dist2)
    return int(cell_id)


def ray_hit(mesh: pv.PolyData, origin, target) -> tuple[np.ndarray, np.ndarray] | None:
    """The first mesh point on the segment from ``origin`` through ``target``.

    The segment is extended past ``target`` to twice its length.

    Returns
    -------
    (point, normal) or None
        None when the ray misses the mesh.
    """
    origin = np.asarray(origin, dtype=np.float64)
    end = origin + 2.0 * (np.asarray(target, dtype=np.float64) - origin)
    locator = _locator(mesh)
    t, x, pcoords = vtk.reference(0.0), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    sub_id, cell_id = vtk.reference(0), vtk.reference(0)
    cell = vtk.vtkGenericCell()
    hit = locator.IntersectWithLine(list(origin), list(end), 1e-9, t, x, pcoords, sub_id, cell_id, cell)
    if not hit:
        return None
    return _blend_normal(mesh, int(cell_id), np.asarray(x))


def _triangle(mesh: pv.PolyData, cell_id: int) -> np.ndarray:
    """The point ids of one triangle, asked of VTK (not by exporting every face, ~4 ms on 200k triangles)."""
    ids = vtk.vtkIdList()
    mesh.GetCellPoints(int(cell_id), ids)
    return np.array([ids.GetId(i) for i in range(ids.GetNumberOfIds())], dtype=np.int64)


def _blend_normal(mesh, cell_id: int, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    ids = _triangle(mesh, cell_id)
    a, b, c = np.asarray(mesh.points, dtype=np.float64)[ids]
    # barycentric weights of x in triangle abc
    v0, v1, v2 = b - a, c - a, x - a
    d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
    d20, d21 = v2 @ v0, v2 @ v1
    denom = d00 * d11 - d01 * d01
    if denom <= 0:
        w = np.full(3, 1.0 / 3.0)
    else:
        wb = (d11 * d20 - d01 * d21) / denom
        wc = (d00 * d21 - d01 * d20) / denom
        w = np.clip(np.array([1.0 - wb - wc, wb, wc]), 0.0, 1.0)
        w /= w.sum()
    normal = w @ np.asarray(mesh.point_data["Normals"], dtype=np.float64)[ids]
    length = np.linalg.norm(normal)
    if length <= 0:
        normal = np.cross(v0, v1)
        length = np.linalg.norm(normal)
    return x.astype(np.float64), normal / (length if length > 0 else 1.0)
