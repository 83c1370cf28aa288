"""Framing and label geometry, and the camera check: plain geometry, tested without VTK."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from phonglab.render.camera import CameraState, check_camera, stands_at
from phonglab.render.framing import (
    FRAME_PAD,
    MAX_VIEW_ANGLE,
    fitted_view_angle,
    label_offsets,
    view_angle_for_tips,
)
from phonglab.scene import Camera

ROOT = Path(__file__).resolve().parents[1]


def test_the_geometry_modules_import_without_vtk_or_pyplot():
    code = ("import sys; import phonglab.render.framing, phonglab.render.camera, phonglab.render.options, "
            "phonglab.render._files, phonglab.render.errors; "
            "print(sorted(m for m in ('vtk', 'pyvista', 'matplotlib.pyplot') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "PYTHONPATH": str(ROOT)}, check=True).stdout.strip()
    assert out == "[]", f"importing the VTK-free modules loaded {out}"


def test_a_tip_on_the_axis_needs_the_angle_its_head_subtends_plus_the_border():
    # a ball of radius 0.1 at depth 4 straight ahead, square window, no letters
    radius, depth, side = 0.1, 4.0, 400
    angle = view_angle_for_tips((0, 0, depth), (0, 0, 0), (0, 1, 0), [(0.0, 0.0, 0.0)], tip_radius=radius,
                                width=side, height=side, reach=0.0)
    keep = 1.0 - FRAME_PAD * side / (side / 2)
    expected = math.degrees(2 * math.atan(math.tan(math.asin(radius / depth)) / keep))
    assert angle == pytest.approx(expected, rel=1e-12), (radius, depth, side, angle, expected)


def test_letters_beyond_the_tips_widen_the_angle_and_a_tip_behind_the_eye_gives_the_widest():
    args = dict(tip_radius=0.05, width=800, height=600)
    tips = [(1.0, 0.5, 0.0)]
    bare = view_angle_for_tips((0, 0, 4), (0, 0, 0), (0, 1, 0), tips, reach=0.0, **args)
    lettered = view_angle_for_tips((0, 0, 4), (0, 0, 0), (0, 1, 0), tips, reach=30.0, **args)
    assert bare < lettered < MAX_VIEW_ANGLE, (bare, lettered)
    behind = view_angle_for_tips((0, 0, 4), (0, 0, 0), (0, 1, 0), [(0.0, 0.0, 5.0)], reach=0.0, **args)
    assert behind == MAX_VIEW_ANGLE, behind


def test_fitted_view_angle_keeps_the_scenes_and_leaves_a_moved_camera_alone():
    scene_camera = Camera(eye=(0.0, 0.0, 4.0), view_angle=30.0)
    args = dict(tip_radius=0.05, width=400, height=300, reach=0.0)
    at_eye = (scene_camera.eye, scene_camera.focal_point, scene_camera.up)
    assert fitted_view_angle(scene_camera, *at_eye, [], **args) == 30.0
    assert fitted_view_angle(scene_camera, *at_eye, [(0.01, 0.0, 0.0)], **args) == 30.0, "a central tip widened it"
    wide = fitted_view_angle(scene_camera, *at_eye, [(3.0, 0.0, 0.0)], **args)
    assert wide > 30.0, wide
    moved = ((1.0, 0.0, 4.0), scene_camera.focal_point, scene_camera.up)
    assert fitted_view_angle(scene_camera, *moved, [(3.0, 0.0, 0.0)], **args) is None
    assert stands_at(np.add(scene_camera.eye, 1e-9), scene_camera.focal_point, scene_camera)


def test_label_offsets_stack_only_coinciding_arrows():
    up, side = (0, 0, 1), (1, 0, 0)
    near = (math.sin(math.radians(9.0)), 0, math.cos(math.radians(9.0)))
    far = (math.sin(math.radians(11.0)), 0, math.cos(math.radians(11.0)))
    assert label_offsets(list("NLR"), {"N": up, "L": near, "R": side}) == {"N": 0, "L": 1, "R": 0}
    assert label_offsets(list("NL"), {"N": up, "L": far}) == {"N": 0, "L": 0}


def test_check_camera_returns_floats_and_names_the_bad_field():
    state = check_camera((0, 0, 5), (0, 0, 0), (0, 2, 0), 30)
    assert state == CameraState((0.0, 0.0, 5.0), (0.0, 0.0, 0.0), (0.0, 2.0, 0.0), 30.0)
    assert all(isinstance(c, float) for c in state.eye + state.focal_point + state.up), state
    for kwargs, field in [({"up": (0, 0, -1e-3)}, "up"), ({"eye": (1, 2, math.inf)}, "eye"),
                          ({"view_angle": 180.0}, "view_angle"), ({"focal_point": (0, 0, 5)}, "focal_point")]:
        args = {"eye": (0, 0, 5), "focal_point": (0, 0, 0), "up": (0, 1, 0), "view_angle": 30.0, **kwargs}
        with pytest.raises(ValueError, match=f"^{field}:"):
            check_camera(**args)


#: the 3D view's size in the page at 1920x1080, 1366x768, 1280x800 and 1024x768 (tests/browser/test_responsive.py)
PAGE_VIEWS = [(1004, 665), (656, 358), (596, 376), (417, 331)]


def test_an_experiment_that_says_the_view_keeps_the_lamp_in_sight_does_at_every_laptop_size():
    """Lesson 10's "No shadows" put the lamp at x = 3.2: framing it needed 47-58 degrees, past the 45 allowed,
    so at 1920x1080, 1280x800 and 1024x768 the lamp was out of the picture that the text says keeps it."""
    pytest.importorskip("vtk")
    from phonglab.render.view import SceneView
    from phonglab.scene import load_lesson

    said = []
    for path in sorted((ROOT / "lessons").glob("[0-9]*.md")):
        lesson = load_lesson(path)
        for experiment in lesson.experiments:
            if "lamp in sight" not in experiment.text:
                continue
            scene = lesson.scene.replace_many(experiment.settings)
            for size in PAGE_VIEWS:
                view = SceneView(scene, size=size)
                try:
                    shown = [bool(g.actor.GetVisibility()) for g in view.glyph_actors.light_markers[1:]]
                finally:
                    view.close()
                said.append((path.stem, experiment.label, size, shown))
    assert said, "no experiment says it keeps the lamp in sight"
    hidden = [s for s in said if not all(s[3])]
    assert not hidden, f"lamp markers left out (lesson, experiment, view size, markers shown): {hidden}"
