"""Meshes for every geometry kind: triangles, unit outward normals, the unit-sphere fit, probes."""

from __future__ import annotations

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")

from phonglab.render.mesh import (  # noqa: E402
    build_mesh,
    face_centroids_normals,
    ray_hit,
    surface_point,
    triangles,
)
from phonglab.scene import Geometry, SceneError  # noqa: E402

PARAMETRIC = ["sphere", "torus", "plane", "cube", "cylinder", "supertoroid"]


@pytest.mark.parametrize("kind", PARAMETRIC)
@pytest.mark.parametrize("resolution", [8, 24])
def test_parametric_meshes_are_triangles_with_unit_normals_inside_unit_sphere(kind, resolution):
    mesh = build_mesh(Geometry(kind, resolution))
    normals = np.asarray(mesh.point_data["Normals"])
    lengths = np.linalg.norm(normals, axis=1)
    radius = np.linalg.norm(np.asarray(mesh.points), axis=1).max()
    assert mesh.is_all_triangles, f"{kind} res {resolution}: not all triangles"
    assert normals.shape == (mesh.n_points, 3), f"{kind}: normals shape {normals.shape}"
    assert np.allclose(lengths, 1.0, atol=1e-5), f"{kind}: normal lengths in [{lengths.min()}, {lengths.max()}]"
    assert radius <= 1.75, f"{kind}: mesh reaches radius {radius}"


def test_resolution_counts_segments_around():
    coarse, fine = build_mesh(Geometry("sphere", 8)), build_mesh(Geometry("sphere", 32))
    assert coarse.n_cells < fine.n_cells, f"{coarse.n_cells} cells at 8, {fine.n_cells} at 32"
    # sphere: n segments around, n/2 from pole to pole: 2 n (n/2 - 1) triangles
    assert coarse.n_cells == 2 * 8 * (4 - 1), f"sphere res 8 has {coarse.n_cells} triangles"


@pytest.mark.parametrize("kind", ["sphere", "cube", "cylinder"])
def test_closed_convex_shapes_have_outward_normals(kind):
    mesh = build_mesh(Geometry(kind, 16))
    points = np.asarray(mesh.points)
    normals = np.asarray(mesh.point_data["Normals"])
    outward = np.einsum("ij,ij->i", points, normals)
    assert (outward > 0).all(), f"{kind}: {np.sum(outward <= 0)} inward normals, min p·n {outward.min()}"
    centroids, face_normals = face_centroids_normals(mesh)
    face_out = np.einsum("ij,ij->i", centroids, face_normals)
    assert (face_out > 0).all(), f"{kind}: {np.sum(face_out <= 0)} inward face normals"


def test_sphere_normals_are_the_radial_direction():
    mesh = build_mesh(Geometry("sphere", 12))
    points = np.asarray(mesh.points, dtype=np.float64)
    radial = points / np.linalg.norm(points, axis=1, keepdims=True)
    err = np.abs(np.asarray(mesh.point_data["Normals"]) - radial).max()
    assert err < 1e-5, f"largest difference from radial normals {err}"


def test_cube_faces_keep_sharp_normals():
    mesh = build_mesh(Geometry("cube", 8))
    normals = np.asarray(mesh.point_data["Normals"])
    # every normal is an axis direction: split at the edges, not averaged
    assert np.allclose(np.sort(np.abs(normals), axis=1), [0, 0, 1], atol=1e-6), "cube normals are not axis-aligned"


def test_meshes_are_cached_per_geometry_and_copies_are_independent():
    g = Geometry("torus", 12)
    a, b = build_mesh(g), build_mesh(g)
    assert a is not b
    assert np.shares_memory(np.asarray(a.points), np.asarray(b.points)), "the cached points were not reused"
    a.point_data["extra"] = np.zeros(a.n_points)
    assert "extra" not in b.point_data, "an array added to one copy shows up in another"


def test_shipped_pyvista_mesh_is_centred_and_scaled_to_unit_sphere():
    mesh = build_mesh(Geometry("pyvista", name="ant"))
    points = np.asarray(mesh.points, dtype=np.float64)
    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    radius = np.linalg.norm(points - centre, axis=1).max()
    assert mesh.is_all_triangles
    assert np.allclose(centre, 0, atol=1e-5), f"centre {centre}"
    assert abs(radius - 1) < 1e-5, f"radius {radius}"
    lengths = np.linalg.norm(np.asarray(mesh.point_data["Normals"]), axis=1)
    assert np.allclose(lengths, 1, atol=1e-5), f"computed normals have lengths {lengths.min()}..{lengths.max()}"


def test_volume_mesh_gives_its_surface():
    mesh = build_mesh(Geometry("pyvista", name="hexbeam"))
    assert mesh.is_all_triangles and mesh.n_cells > 0


def test_file_mesh_is_read_and_reread_after_a_change(tmp_path):
    path = tmp_path / "box.ply"
    pv.Cube().triangulate().save(path)
    first = build_mesh(Geometry("file", path=str(path)))
    assert first.n_cells == 12, f"cube file gave {first.n_cells} triangles"
    pv.Sphere(theta_resolution=6, phi_resolution=6).save(path)
    import os

    os.utime(path, ns=(1, 2_000_000_000_000_000_000))  # a new modification time
    second = build_mesh(Geometry("file", path=str(path)))
    assert second.n_cells != 12, "the edited file was served from the cache"


def test_file_without_polygons_is_refused(tmp_path):
    path = tmp_path / "points.vtp"
    pv.PolyData(np.random.default_rng(0).random((10, 3))).save(path)
    with pytest.raises(SceneError, match="no surface"):
        build_mesh(Geometry("file", path=str(path)))


def test_unreadable_file_is_refused_naming_the_path(tmp_path):
    path = tmp_path / "broken.ply"
    path.write_text("this is not a ply file\n")
    with pytest.raises(SceneError) as info:
        build_mesh(Geometry("file", path=str(path)))
    assert "geometry.path" in str(info.value) and "broken.ply" in str(info.value), str(info.value)


def test_a_long_path_keeps_its_file_name_in_the_error(tmp_path):
    folder = tmp_path / ("deep-folder-" * 8)
    folder.mkdir()
    path = folder / "broken.ply"
    path.write_text("this is not a ply file\n")
    with pytest.raises(SceneError) as info:
        build_mesh(Geometry("file", path=str(path)))
    message = str(info.value)
    assert "broken.ply" in message and "characters)" in message and len(message) < 200, message


def test_surface_point_projects_onto_the_mesh_with_blended_normal():
    mesh = build_mesh(Geometry("sphere", 48))
    point, normal = surface_point(mesh, (0.35, 0.45, 0.82))
    target = np.array([0.35, 0.45, 0.82]) / np.linalg.norm([0.35, 0.45, 0.82])
    assert abs(np.linalg.norm(point) - 1) < 0.01, f"probe {point} is off the sphere"
    assert abs(np.linalg.norm(normal) - 1) < 1e-12
    assert normal @ target > 0.9999, f"normal {normal} vs radial {target}"


def test_ray_hit_finds_the_front_surface_and_misses_the_torus_hole():
    sphere = build_mesh(Geometry("sphere", 32))
    point, normal = ray_hit(sphere, (0, 0, 4), (0, 0, 0))
    assert point[2] > 0.99 and normal[2] > 0.99, f"hit {point}, normal {normal}"
    torus = build_mesh(Geometry("torus", 32))
    assert ray_hit(torus, (0, 0, 4), (0, 0, 0)) is None, "a ray through the torus hole hit something"


def test_triangles_index_the_points():
    mesh = build_mesh(Geometry("cube", 4))
    tri = triangles(mesh)
    assert tri.shape == (mesh.n_cells, 3) and tri.max() < mesh.n_points


def test_the_cell_locator_is_built_once_per_mesh_and_again_when_its_points_move():
    # a turn of the view casts a ray to every arrow tip: the 100k-vertex sphere's locator must not be rebuilt each time
    import numpy as np
    import pyvista as pv

    from phonglab.render import mesh as meshes

    sphere = pv.Sphere(theta_resolution=24, phi_resolution=16).triangulate()
    first = meshes._locator(sphere)
    sphere.point_data["colors"] = np.zeros((sphere.n_points, 3), dtype=np.uint8)  # new colours keep it
    assert meshes._locator(sphere) is first
    hit = meshes.ray_hit(sphere, (0, 0, 5), (0, 0, 0))[0]
    sphere.points = sphere.points * 2.0  # moved points: a new locator, and the hit moves with them
    assert meshes._locator(sphere) is not first
    moved = meshes.ray_hit(sphere, (0, 0, 5), (0, 0, 0))[0]
    assert np.allclose(moved, 2 * hit), (hit, moved)


def test_a_hit_triangle_is_looked_up_alone_and_agrees_with_the_face_list(monkeypatch):
    # a ray's normal needs one triangle's points; exporting all 200k faces for it cost ~4 ms a ray
    import numpy as np

    from phonglab.render import mesh as meshes

    for kind in ("sphere", "cube", "torus"):
        mesh = build_mesh(Geometry(kind, 16))
        tri = triangles(mesh)
        for cell in (0, mesh.n_cells // 3, mesh.n_cells - 1):
            assert np.array_equal(meshes._triangle(mesh, cell), tri[cell]), (kind, cell, meshes._triangle(mesh, cell),
                                                                            tri[cell])
    mesh = build_mesh(Geometry("sphere", 16))
    monkeypatch.setattr(meshes, "triangles", lambda m: (_ for _ in ()).throw(AssertionError("all faces exported")))
    point, normal = meshes.ray_hit(mesh, (0, 0, 4), (0, 0, 0))
    assert point[2] > 0.99 and normal[2] > 0.99, (point, normal)


def test_closed_outward_holds_for_solids_wound_outwards_only():
    # culling the faces turned away is safe only for these: each edge run once each way, positive volume
    import numpy as np
    import pyvista as pv

    from phonglab.render.mesh import closed_outward

    sphere = build_mesh(Geometry("sphere", 24))
    assert closed_outward(sphere) and closed_outward(build_mesh(Geometry("torus", 24)))
    assert not closed_outward(build_mesh(Geometry("cube", 4)))  # faces with their own points: not closed
    assert not closed_outward(build_mesh(Geometry("plane", 8)))
    tri = triangles(sphere)
    inwards = pv.PolyData(np.asarray(sphere.points), faces=np.column_stack([np.full(len(tri), 3), tri[:, ::-1]]))
    assert not closed_outward(inwards), "a sphere wound inwards passed"
    holed = pv.PolyData(np.asarray(sphere.points), faces=np.column_stack([np.full(len(tri) - 1, 3), tri[1:]]))
    assert not closed_outward(holed), "a sphere with a triangle missing passed"
    mixed = tri.copy()
    mixed[5] = mixed[5, ::-1]
    assert not closed_outward(pv.PolyData(np.asarray(sphere.points), faces=np.column_stack([np.full(len(tri), 3),
                                                                                              mixed]))), \
        "a sphere with one face wound the other way passed"
