"""The three interpolation modes on a coarse sphere: flat faces, Gouraud's missed highlight, per-pixel shading.

All renders are offscreen, 200 x 150 pixels, without supersampling, so a
pixel's value is exactly what the mode computed there.
"""

from __future__ import annotations

import numpy as np
import pytest

vtk = pytest.importorskip("vtk")

import phonglab as pl  # noqa: E402
from phonglab.core.display import display_bytes, display_values, srgb_decode  # noqa: E402
from phonglab.render._vtk import set_camera  # noqa: E402
from phonglab.render.gbuffer import GBufferRenderer  # noqa: E402
from phonglab.render.mesh import build_mesh, face_centroids_normals  # noqa: E402
from phonglab.render.view import SceneView  # noqa: E402
from phonglab.scene import Camera, Geometry, Scene  # noqa: E402
from phonglab.scene import shade as scene_shade  # noqa: E402

SIZE = (200, 150)
KS = 0.9
SHININESS = 60.0


def highlight_scene(interpolation: str, resolution: int = 8) -> Scene:
    """A coarse sphere whose mirror highlight falls in the middle of a triangle.

    Specular only (ka = kd = 0), one white directional light, an infinite
    viewer along +z: the analytic peak is ks, reached where n = h. The light
    is placed so that h is the direction of a front triangle's centroid,
    as far as it gets from that triangle's vertex normals.
    """
    geometry = Geometry("sphere", resolution)
    mesh = build_mesh(geometry)
    centroids, _ = face_centroids_normals(mesh)
    v = np.array([0.0, 0.0, 1.0])
    c = centroids / np.linalg.norm(centroids, axis=1, keepdims=True)
    # the front triangle closest to facing the viewer, off the silhouette
    front = np.flatnonzero(c @ v > 0.5)
    h = c[front[np.argmax(c[front] @ v)]]
    light = 2 * (h @ v) * h - v  # reflect v about h: then r = v where n = h
    return Scene(
        geometry=geometry,
        material=pl.Material(ka=0.0, kd=0.0, ks=KS, shininess=SHININESS),
        lights=(pl.DirectionalLight(direction=tuple(light)),),
        camera=Camera(infinite_viewer=True),
        interpolation=interpolation,
    )


def analytic_peak(scene: Scene) -> float:
    """The brightest value the smooth sphere reaches, by the core on a dense set of exact normals."""
    theta, phi = np.meshgrid(np.linspace(0, np.pi, 721), np.linspace(0, 2 * np.pi, 1441), indexing="ij")
    n = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1).reshape(-1, 3)
    visible = n[:, 2] > 0
    color = scene_shade(scene, n[visible], n[visible]).color
    return float(color.max())


def encoded(linear: float) -> float:
    """A linear value as the display value in [0, 1] the picture holds (sRGB, clipped)."""
    return float(display_values(linear))


def render(scene: Scene) -> np.ndarray:
    view = SceneView(scene, size=SIZE, vectors=None, labels=False, markers=False, background=(0, 0, 0))
    try:
        return view.screenshot(annotate=False)
    finally:
        view.close()


def test_analytic_peak_of_the_highlight_scene_is_ks():
    peak = analytic_peak(highlight_scene("pixel"))
    assert abs(peak - KS) < 1e-3, f"dense sampling of the exact sphere peaks at {peak}, expected ks = {KS}"


@pytest.mark.parametrize("interpolation", ["flat", "gouraud", "pixel"])
def test_highlight_peak_found_by_pixel_mode_and_missed_by_gouraud(interpolation):
    scene = highlight_scene(interpolation)
    peak = analytic_peak(scene)
    image = render(scene)
    # the picture is sRGB-encoded: compare in display values, and in linear light where the lobe's fraction counts
    brightest = image.max() / 255
    linear = float(srgb_decode(brightest))
    mesh = build_mesh(scene.geometry)
    vertex_best = float(scene_shade(scene, np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"])).color.max())
    report = (f"{interpolation}: brightest pixel {brightest:.3f} (linear {linear:.3f}), analytic peak {peak:.3f}, "
              f"best vertex {vertex_best:.3f} (sphere resolution {scene.geometry.resolution}, {SIZE})")
    if interpolation == "pixel":
        # found: within a few percent of the analytic peak (pixel sampling of a shininess-60 lobe)
        assert linear >= 0.93 * peak, report
        assert brightest <= encoded(peak) + 1 / 255, report
    elif interpolation == "gouraud":
        # missed: colours interpolate between vertices, none of which sees the highlight
        assert linear <= 0.5 * peak, report
        assert brightest <= encoded(vertex_best) + 1 / 255, report
    else:
        # flat: the brightest face is the brightest centroid the core shaded, no more
        centroids, normals = face_centroids_normals(mesh)
        face_best = float(np.clip(scene_shade(scene, centroids, normals).color, 0, 1).max())
        assert abs(brightest - encoded(face_best)) <= 1 / 255, report + f", best face {face_best:.3f}"


def face_id_image(scene: Scene) -> np.ndarray:
    """The same view with every triangle painted a unique colour (its index + 1)."""
    view = SceneView(scene, size=SIZE, vectors=None, labels=False, markers=False, background=(0, 0, 0))
    try:
        ids = np.arange(1, view.mesh.n_cells + 1)
        codes = np.stack([ids & 255, (ids >> 8) & 255, (ids >> 16) & 255], axis=1).astype(np.uint8)
        view.mesh.cell_data["rgb"][...] = codes
        view.mesh.GetCellData().GetArray("rgb").Modified()
        image = view.screenshot(annotate=False).astype(np.int64)
    finally:
        view.close()
    return image[..., 0] + (image[..., 1] << 8) + (image[..., 2] << 16) - 1  # -1 = background


def test_flat_mode_paints_one_colour_per_face():
    scene = Scene(
        geometry=Geometry("sphere", 10),
        material=pl.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=20),
        lights=(pl.AmbientLight(intensity=0.2), pl.PointLight(position=(2, 2.5, 3))),
        camera=Camera(),
        interpolation="flat",
    )
    image = render(scene)
    face = face_id_image(scene)
    mesh = build_mesh(scene.geometry)
    centroids, normals = face_centroids_normals(mesh)
    expected = display_bytes(scene_shade(scene, centroids, normals).color)
    seen = np.unique(face[face >= 0])
    assert len(seen) > 20, f"only {len(seen)} faces visible"
    for f in seen:
        colours = np.unique(image[face == f], axis=0)
        assert len(colours) == 1, f"face {f} shows {len(colours)} colours: {colours[:4].tolist()}"
        assert (colours[0] == expected[f]).all(), f"face {f}: drawn {colours[0]}, core at centroid {expected[f]}"


def test_gouraud_vertex_colours_are_the_core_at_the_vertices():
    scene = highlight_scene("gouraud", resolution=12)
    view = SceneView(scene, size=SIZE, vectors=None, labels=False, markers=False)
    try:
        drawn = np.asarray(view.mesh.point_data["rgb"])
        mesh = view.mesh
        core = scene_shade(scene, np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"])).color
        expected = display_bytes(core)
    finally:
        view.close()
    assert (drawn == expected).all(), f"{np.sum(drawn != expected)} vertex channels differ from the core"


def test_gbuffer_holds_interpolated_surface_positions_and_unit_normals():
    geometry = Geometry("sphere", 16)
    mesh = build_mesh(geometry)
    camera = vtk.vtkCamera()
    set_camera(camera, Camera())
    renderer = GBufferRenderer()
    try:
        g = renderer.render(mesh, camera, SIZE)
    finally:
        renderer.close()
    covered = g.mask.sum()
    radius = np.linalg.norm(g.positions[g.mask], axis=1)
    lengths = np.linalg.norm(g.normals[g.mask], axis=1)
    facing = np.einsum("ij,ij->i", g.normals[g.mask], g.positions[g.mask] / radius[:, None])
    assert g.mask.shape == (SIZE[1], SIZE[0])
    assert 0.3 * g.mask.size < covered < 0.9 * g.mask.size, f"{covered} of {g.mask.size} pixels covered"
    # positions lie on the flat triangles: between the inscribed polyhedron and the sphere
    assert radius.max() <= 1.0 + 1e-4 and radius.min() > 0.95, f"|p| in [{radius.min()}, {radius.max()}]"
    assert np.allclose(lengths, 1, atol=1e-5), f"normal lengths in [{lengths.min()}, {lengths.max()}]"
    assert facing.min() > 0.99, f"an interpolated normal is {np.degrees(np.arccos(facing.min())):.1f}° off radial"
    # the top-left corner is background; the centre is the sphere's front point
    assert not g.mask[0, 0] and g.mask[SIZE[1] // 2, SIZE[0] // 2]
    centre = g.positions[SIZE[1] // 2, SIZE[0] // 2]
    assert centre[2] > 0.95, f"centre pixel sees {centre}"


def test_pixel_image_is_the_core_on_the_gbuffer():
    scene = highlight_scene("pixel", resolution=12)
    view = SceneView(scene, size=SIZE, vectors=None, labels=False, markers=False, background=(0.2, 0.4, 0.6))
    try:
        image = view.pixel_image()
        g = view.gbuffer()
    finally:
        view.close()
    core = scene_shade(scene, g.positions[g.mask], g.normals[g.mask]).color
    expected = display_bytes(core)  # encoded for the display (sRGB by default)
    assert (image[g.mask] == expected).all(), "pixel colours differ from the core on the G-buffer"
    assert (image[~g.mask] == [51, 102, 153]).all(), "uncovered pixels are not the background"
