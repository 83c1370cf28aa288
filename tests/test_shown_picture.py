"""The picture claims' displayed picture: the page's own screenshot, the same for a reused view as for a new one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
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
