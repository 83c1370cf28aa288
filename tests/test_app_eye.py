"""Turning the view moves the eye: the browser's camera becomes the scene's, the core re-shades for it."""

from __future__ import annotations

import asyncio

import numpy as np

from phonglab.core.display import display_bytes
import pytest

import phonglab as pl
from phonglab.app import eye
from phonglab.bench.scenes import lesson, red_sphere, red_sphere_tables
from phonglab.scene import SceneError

from app_support import browser_camera

SPHERE = lesson(
    """
number = 4
title = "Sphere"
controls = ["material.shininess", "camera.eye"]
probe = [0.3, 0.4, 0.866]
""",
    red_sphere_tables(24),
    "# Sphere\n",
)


@pytest.fixture
def app(lesson_app):
    return lesson_app("04-sphere.md", SPHERE, "test-eye")


def test_scene_camera_takes_the_browsers_camera_and_keeps_infinite_viewer():
    scene = red_sphere(12).replace("camera.infinite_viewer", True)
    turned = eye.scene_camera(scene, browser_camera(scene, 30))
    assert turned.camera.eye == pytest.approx(browser_camera(scene, 30)["position"]), turned.camera
    assert turned.camera.infinite_viewer is True
    assert eye.scene_camera(scene, browser_camera(scene, 0)) is scene


@pytest.mark.parametrize("camera, error", [
    ([1, 2, 3], ValueError),
    ({"position": [0, 0, "far"], "focalPoint": [0, 0, 0], "viewUp": [0, 1, 0]}, ValueError),
    ({"position": [0, 0, 1], "focalPoint": [0, 0, float("inf")], "viewUp": [0, 1, 0]}, ValueError),
    ({"position": [0, 0, 4], "focalPoint": [0, 0, 0], "viewUp": [0, 1, 0], "viewAngle": "wide"}, ValueError),
    ({"position": [0, 0, 0], "focalPoint": [0, 0, 0], "viewUp": [0, 1, 0]}, SceneError),  # eye on the focal point
    ({"position": [0, 0, 4], "focalPoint": [0, 0, 0], "viewUp": [0, 0, 1]}, SceneError),  # up along the sight line
])
def test_a_bad_browser_camera_is_refused(camera, error):
    with pytest.raises(error):
        eye.scene_camera(red_sphere(12), camera)


def test_latest_drops_stale_cameras_and_keeps_final():
    seen = []
    latest = eye.Latest(lambda camera, final: seen.append((camera, final)))

    async def drag():
        for step in range(5):
            latest.offer(step, final=False)
        latest.offer(5, final=True)
        latest.offer(6, final=False)  # a late intermediate camera does not undo the drag's end
        await asyncio.sleep(0)
        await asyncio.sleep(0)

    asyncio.run(drag())
    assert seen == [(6, True)], seen
    assert (latest.offered, latest.applied) == (7, 1)


def test_turning_the_view_reshades_for_the_new_eye(app):
    before = app.scene
    colours = app.view.colour_array().values.copy()
    rv = {d["name"]: d["value"] for d in app.state.readout["dots"]}["r·v"]
    camera = browser_camera(before, 40)
    app.on_camera(camera)
    scene = app.scene
    assert scene.camera.eye == pytest.approx(camera["position"]), scene.camera
    # the mesh shows the core's colours for the new eye, not the old ones
    expected = pl.shade(app.view.mesh.points, app.view.mesh.point_data["Normals"], eye=scene.camera.eye,
                        material=scene.material, lights=scene.lights)
    assert not np.array_equal(app.view.colour_array().values, colours), "colours baked for the old eye"
    shown = np.asarray(app.view.colour_array().values, dtype=int)
    encoded = display_bytes(expected.color, encoding=scene.display, exposure=scene.exposure).astype(int)
    assert np.abs(shown - encoded).max() <= 1, f"colours are not the core's for eye {scene.camera.eye}"
    # the pushed colours are the view's
    assert app.state.view_colors["data"] == app.view.colour_array().values.tobytes()
    # the readout and V follow the eye
    point, normal = app.view.probe
    v = pl.vectors(point, normal, eye=scene.camera.eye, light=scene.lights[app.view.light_index])
    shown = {d["name"]: float(d["value"]) for d in app.state.readout["dots"]}
    assert shown["r·v"] == pytest.approx(v.rv, abs=5e-4), (shown, v.rv, rv)
    assert float(rv) != pytest.approx(shown["r·v"], abs=1e-3), "r·v stayed when the eye moved"
    assert np.allclose(app.view.probe_vectors.v, v.v), (app.view.probe_vectors.v, v.v)
    # the eye controls follow the camera; the window shows the browser's camera as sent
    assert app.state["camera__azimuth"] == pytest.approx(40.0, abs=0.01), app.state["camera__azimuth"]
    vtk_camera = app.view.renderer.GetActiveCamera()
    assert vtk_camera.GetPosition() == pytest.approx(camera["position"])
    assert vtk_camera.GetViewAngle() == pytest.approx(camera["viewAngle"])


def test_moving_the_eye_slider_moves_the_camera_and_a_new_lesson_restores_it(app):
    app.on_camera(browser_camera(app.scene, 25))
    app._on_control("camera__azimuth", -10.0)
    expected = browser_camera(app.entry.scene, -10)["position"]
    assert app.scene.camera.eye == pytest.approx(expected, abs=1e-6), app.scene.camera
    assert app.view.renderer.GetActiveCamera().GetPosition() == pytest.approx(expected, abs=1e-6)
    app.reset_lesson()
    assert app.scene.camera == app.entry.scene.camera


def test_the_page_gets_every_arrows_tip_for_its_letters_and_they_follow_the_eye(app):
    def tips():
        return {t["letter"]: (np.array(t["base"]), np.array(t["tip"]), t["color"]) for t in app.state.arrow_tips}

    assert set(tips()) == set("NLRVH"), app.state.arrow_tips
    colours = {entry["letter"]: entry["color"] for entry in app.state.legend}
    app.on_camera(browser_camera(app.scene, 35))
    shown = tips()
    point, _ = app.view.probe
    for letter, direction in (("V", app.view.probe_vectors.v), ("N", app.view.probe_vectors.n)):
        base, tip, colour = shown[letter]
        assert np.allclose(base, point, atol=1e-6) and colour == colours[letter], (letter, shown[letter])
        assert np.allclose(tip, point + direction * app.view.arrow_length, atol=1e-5), (letter, tip, direction)
