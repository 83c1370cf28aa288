"""A plan made by the caller (``scene_plan=``) is the one the view's shading uses, and gives the same colours."""

from __future__ import annotations

import numpy as np
import pytest

vtk = pytest.importorskip("vtk")

from phonglab.bench import scenes  # noqa: E402
from phonglab.render import shading  # noqa: E402
from phonglab.render.view import SceneView  # noqa: E402
from phonglab.scene import Camera  # noqa: E402
from phonglab.scene.planner import plan  # noqa: E402

SIZE = (160, 120)


def red_sphere(**changes):
    scene = scenes.red_sphere(16, camera=Camera(), probe=(0.35, 0.45, 0.82))
    for path, value in changes.items():
        scene = scene.replace(path.replace("__", "."), value)
    return scene


@pytest.mark.parametrize("interpolation", ["flat", "gouraud"])
def test_update_with_the_apps_plan_gives_the_colours_of_a_fresh_view(interpolation):
    first = red_sphere(interpolation=interpolation)
    moved = first.replace("camera.eye", [1.5, 0.5, 3.0]).replace("material.shininess", 7.0)
    view, fresh = SceneView(first, size=SIZE), SceneView(moved, size=SIZE)
    try:
        view.update(moved, scene_plan=plan(moved))
        shown, expected = view.colour_array().values, fresh.colour_array().values
        assert np.array_equal(shown, expected), (interpolation, np.abs(shown.astype(int) - expected).max())
    finally:
        view.close()
        fresh.close()


def test_the_plan_given_is_the_one_used():
    # the core checks a plan against the material it shades: one made for k_s = 0 is refused for a shiny
    # scene, so the refusal shows the plan given reached the core instead of one planned there
    from phonglab.core.model import InvalidValue

    shiny = red_sphere(interpolation="gouraud")
    other = plan(shiny.replace("material.ks", 0.0))
    view = SceneView(shiny, size=SIZE)
    try:
        with pytest.raises(InvalidValue, match="plan"):
            view.update(shiny.replace("material.shininess", 12.0), scene_plan=other)
        with pytest.raises(InvalidValue, match="plan"):
            shading.face_colors(shiny, view.mesh, scene_plan=other)
    finally:
        view.close()


def test_a_plan_stays_with_its_scene_only():
    # after an update with a plan, a change of term re-shades the same scene with it; an update
    # without a plan plans again for the new scene (a stale plan would be refused by the core)
    first = red_sphere(interpolation="gouraud")
    view = SceneView(first, size=SIZE)
    try:
        dull = first.replace("material.shininess", 12.0)
        view.update(dull, scene_plan=plan(dull))
        view.set_term("specular")
        assert np.array_equal(view.colour_array().values,
                              shading.vertex_colors(dull, view.mesh, ("specular",))["specular"])
        matte = dull.replace("material.ks", 0.0)
        view.update(matte)
        view.set_term("color")
        expected = shading.vertex_colors(matte, view.mesh)["color"]
        assert np.array_equal(view.colour_array().values, expected), "the old scene's plan was used"
    finally:
        view.close()


def test_pixel_colors_with_the_plan_equal_those_without():
    scene = red_sphere(interpolation="pixel")
    view = SceneView(scene, size=SIZE)
    try:
        gbuffer = view.gbuffer()
        given = shading.pixel_colors(scene, gbuffer, view.background, scene_plan=plan(scene))["color"]
        own = shading.pixel_colors(scene, gbuffer, view.background)["color"]
        assert np.array_equal(given, own), np.abs(given.astype(int) - own).max()
    finally:
        view.close()
