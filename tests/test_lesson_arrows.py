"""Every lesson's default probe shows its five arrows: seen from the side, in the view, clear of the buttons.

Pure geometry, no browser: the probe, the vectors and the arrows' length as
the app's view computes them (:mod:`phonglab.render.probe`,
:mod:`phonglab.render.glyphs`), the view angle the view fits
(:func:`phonglab.render.framing.fitted_view_angle`), and a pinhole
projection of VTK's camera onto the page's view at 1280 × 800 (the size the
browser tests use). The buttons' boxes were measured on that page.

V points at the eye, and the view's camera *is* the eye: V is always seen
end-on (its arrow head shows as a disc). So V is checked for being in view
and clear of the buttons; N, L, R and H must each stand at least
:data:`MIN_SIDEWAYS` off the line of sight.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from phonglab.render import framing, glyphs
from phonglab.render.mesh import build_mesh
from phonglab.render.probe import directed_light_index, locate_probe, probe_vectors
from phonglab.scene import load_lesson

LESSONS = sorted((Path(__file__).resolve().parents[1] / "lessons").glob("[0-9][0-9]-*.md"))
#: the 3D view on a 1280 × 800 page (CSS pixels)
VIEW = (563, 469)
#: the page's buttons and captions over the view, as (left, top, right, bottom) in view pixels:
#: the legend chips (top left), the term and pick toggles (top right), the hint (bottom right)
BUTTONS = {
    "legend": (10, 10, 232, 34),
    "toggles": (294, 8, 553, 86),
    "hint": (205, 443, 551, 461),
}
#: free pixels kept around a tip (its head and its letter)
TIP_CLEARANCE = 14
#: an arrow's on-screen length, as a fraction of its length seen side-on, at least (sin 17°)
MIN_SIDEWAYS = 0.3


def _project(camera, view_angle, point, size=VIEW):
    """A world point on the view: (x, y) pixels from the top left, and its depth; VTK's perspective camera."""
    eye, focal, up = (np.asarray(v, float) for v in (camera.eye, camera.focal_point, camera.up))
    forward = (focal - eye) / np.linalg.norm(focal - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    width, height = size
    # the view angle spans the shorter side (SceneView: the height of a wide window)
    focal_px = (min(width, height) / 2) / math.tan(math.radians(view_angle) / 2)
    d = np.asarray(point, float) - eye
    depth = d @ forward
    return (width / 2 + focal_px * (d @ right) / depth, height / 2 - focal_px * (d @ true_up) / depth), depth


def arrows_on_screen(scene, size=VIEW):
    """letter -> (base, tip, side-on length) in view pixels, for the scene's probe as the app draws it."""
    mesh = build_mesh(scene.geometry)
    point, normal = locate_probe(mesh, scene)
    _, directions = probe_vectors(scene, point, normal, directed_light_index(scene.lights))
    length = glyphs.arrow_length(mesh)
    tips = {letter: point + d * length for letter, d in directions.items()}
    letters = list(directions)
    angle = framing.fitted_view_angle(scene.camera, scene.camera.eye, scene.camera.focal_point, scene.camera.up,
                                      list(tips.values()), tip_radius=glyphs.TIP_RADIUS, width=size[0],
                                      height=size[1], reach=framing.label_reach(size[1], letters))
    base, depth = _project(scene.camera, angle, point, size)
    focal_px = (min(size) / 2) / math.tan(math.radians(angle) / 2)
    out = {}
    for letter, tip in tips.items():
        out[letter] = (base, _project(scene.camera, angle, tip, size)[0], focal_px * length / depth)
    return out


def problems(scene, size=VIEW) -> list[str]:
    """What keeps the scene's arrows from being read, as sentences (empty: all five readable)."""
    found = []
    arrows = arrows_on_screen(scene, size)
    if set(arrows) != set("NLRVH"):
        found.append(f"arrows drawn: {sorted(arrows)}, not all five")
    for letter, (base, tip, side_on) in arrows.items():
        shown = math.dist(base, tip)
        if letter != "V" and shown < MIN_SIDEWAYS * side_on:
            found.append(f"{letter} is seen nearly end-on: {shown:.0f} px of {side_on:.0f} px side-on")
        x, y = tip
        c = TIP_CLEARANCE
        if not (c <= x <= size[0] - c and c <= y <= size[1] - c):
            found.append(f"{letter}'s tip ({x:.0f}, {y:.0f}) is outside the view {size}")
        for name, (left, top, right, bottom) in BUTTONS.items():
            if left - c <= x <= right + c and top - c <= y <= bottom + c:
                found.append(f"{letter}'s tip ({x:.0f}, {y:.0f}) is under the {name} ({left}, {top}, {right}, {bottom})")
    return found


@pytest.mark.parametrize("path", LESSONS, ids=lambda p: p.stem)
def test_every_lessons_probe_shows_five_readable_arrows(path):
    scene = load_lesson(path).scene
    found = problems(scene)
    assert not found, f"{path.name}: probe {scene.probe}, camera eye {scene.camera.eye}: " + "; ".join(found)


def test_the_check_catches_an_arrow_pointing_at_the_camera_and_one_under_the_buttons():
    scene = load_lesson(LESSONS[3]).scene
    # the point of the sphere facing the eye: N points straight at the camera
    facing = np.subtract(scene.camera.eye, scene.camera.focal_point)
    facing = facing / np.linalg.norm(facing)
    found = problems(scene.replace("probe", facing.tolist()))
    assert any(p.startswith("N is seen nearly end-on") for p in found), found
    # the upper right of the sphere: its arrows reach under the toggles (lesson 4's old probe)
    found = problems(scene.replace("probe", [0.62, 0.55, 0.56]))
    assert any("under the toggles" in p for p in found), found


def test_the_arrows_follow_the_first_light_that_shines():
    """Lesson 7's sun: the spotlight switched off (intensity 0), the arrows showed its L and its n·l of 0."""
    lesson = load_lesson(next(p for p in LESSONS if p.stem == "07-light-sources"))
    sun = next(e for e in lesson.experiments if "w = 0" in e.label)
    lights = sun.apply(lesson.scene).lights
    assert directed_light_index(lesson.scene.lights) == 1, "the lesson's own scene: its spotlight, light 1"
    assert not np.any(lights[1].diffuse_rgb) and np.any(lights[2].diffuse_rgb), [l.diffuse_rgb for l in lights]
    assert directed_light_index(lights) == 2, "the spotlight is off: the arrows are the sun's"
    assert directed_light_index(lights, choice=1) == 1, "a light chosen by hand stays chosen"
