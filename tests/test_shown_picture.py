"""The picture claims' displayed picture: the page's own screenshot, the same for a reused view as for a new one."""

from __future__ import annotations

from pathlib import Path

import pytest

from phonglab.render.gbuffer import GBufferRenderer
from phonglab.render.view import SceneView
from phonglab.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SPHERE = ROOT / "assets" / "scenes" / "sphere.toml"


def _camera(scene):
    """A VTK camera for the scene, as a view without arrows sets it (clipping range fitted to the mesh alone)."""
    view = SceneView(scene, size=(96, 72), vectors="", labels=False, vtk_text=False, markers=False)
    view.render()
    return view


def test_a_reused_gbuffer_renderer_follows_the_new_camera():
    # the second camera's clipping range, fitted to the same mesh, equals what the copy brings along: the
    # renderer must still take the new camera's matrices
    front = load_scene(SPHERE)
    first, second = _camera(front), _camera(front.replace("camera.eye", (0.0, -2.6, 4.6)))
    try:
        reused = GBufferRenderer()
        reused.render(second.mesh, first.renderer.GetActiveCamera(), (96, 72))
        again = reused.render(second.mesh, second.renderer.GetActiveCamera(), (96, 72))
        fresh = GBufferRenderer().render(second.mesh, second.renderer.GetActiveCamera(), (96, 72))
        differ = int((again.mask != fresh.mask).sum())
        assert differ == 0, f"{differ} pixels of the reused renderer's coverage differ from a new renderer's"
    finally:
        first.close()
        second.close()


@pytest.mark.parametrize("settings", [
    {},  # Gouraud: VTK blends the encoded vertex colours
    {"interpolation": "pixel", "display": "linear", "exposure": 2.0},
    {"interpolation": "pixel", "material.opacity": 0.5},  # blended over the far side and the background
    {"interpolation": "flat", "camera.eye": (2.0, 1.0, 3.0)},
], ids=["gouraud", "pixel-linear-exposure", "translucent", "flat-moved-eye"])
def test_the_picture_shown_is_the_pages_screenshot(settings):
    # one view reused for every scene must give what a new view of the scene gives: the page's own picture
    from phonglab.accuracy.shown import SHOWN_SIZE, shown

    scene = load_scene(SPHERE).replace_many(list(settings.items()))
    picture = shown(scene)
    view = SceneView(scene, size=SHOWN_SIZE, vectors="", labels=False, vtk_text=False, markers=False)
    try:
        page = view.screenshot(annotate=False)
        covered = view.gbuffer().mask
    finally:
        view.close()
    differ = int((picture.image != page).any(axis=-1).sum())
    assert differ == 0, f"{settings}: {differ} pixels differ from a new view's screenshot"
    assert (picture.mask == covered).all(), settings
    background = (picture.image[picture.mask] == page[0, 0]).all(axis=-1).sum()
    assert background == 0, f"{settings}: {background} covered pixels show the background colour"
    assert shown(scene) is picture, "the picture of a scene is made once per run"


def test_the_probe_pixel_is_where_the_probe_is_seen():
    from phonglab.accuracy.shown import shown

    scene = load_scene(SPHERE).replace_many([("interpolation", "pixel"), ("probe", (0.3, 0.3, 0.9))])
    moved = scene.replace("probe", (-0.3, -0.3, 0.9))
    (row, col), (row2, col2) = shown(scene).probe, shown(moved).probe
    # up and right on the sphere is up (smaller row) and right (larger column) in the picture
    assert row < row2 and col > col2, ((row, col), (row2, col2))
    hidden = scene.replace("probe", (0.0, 0.0, -1.0))  # the far side: not seen
    assert shown(hidden).probe is None
