"""Every lesson's page in every interpolation mode, through the app controller (no browser).

For each lesson of ``lessons/`` and each mode (flat, Gouraud, per pixel):

- the picture is encoded for the display: the view's colours with the
  scene's ``display = "srgb"`` are the sRGB curve of the same scene's raw
  (``"linear"``) colours, so a mid-tone is brighter than raw x255 (a raw
  picture fails: 128 is not sRGB's 188 for a 50 % grey);
- the readout follows the eye: after the view turns 30 degrees about the
  focal point, n·l, r·v and n·h on the page and the V arrow are the core's
  for the new eye (:func:`phonglab.core.vectors`), and V changed.

The browser side of the same claims is tested on lesson 4 in
tests/browser/test_turn_view.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from phonglab import core
from phonglab.app import accuracy_panel
from phonglab.app.lesson_app import LessonApp
from phonglab.core.display import srgb_decode
from phonglab.scene.planner import viewer

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
NUMBERS = sorted(int(p.name[:2]) for p in LESSONS.glob("[0-9][0-9]-*.md"))
MODES = ("flat", "gouraud", "pixel")
#: the view's size: small, the checks are per pixel
SIZE = {"size": {"width": 160, "height": 120}}
#: raw values checked against the sRGB picture: mid-tones, where the two encodings differ most
MID = (13, 242)
#: 8-bit rounding of both pictures, through the sRGB curve's steepest slope (2.3 at white), in raw units
ROUNDING = 2


@pytest.fixture(scope="module")
def app():
    from trame.app import get_server

    with pytest.MonkeyPatch.context() as patch:
        # the accuracy lesson's panel measures in worker processes: not what this file tests
        patch.setattr(accuracy_panel.AccuracyPanel, "open", lambda self, entry, scene: None)
        patch.setattr(accuracy_panel.AccuracyPanel, "follow", lambda self, scene: None)
        application = LessonApp(get_server("test-every-lesson", client_type="vue3"), target=LESSONS)
        application._on_view_size(view_size=SIZE)
        yield application
        application.close()


def control(app, key, value) -> None:
    """Set a control as the browser would, and run the panel refresh the app may have put off."""
    app._on_control(key, value)
    app._later.run_waiting()  # a refresh the app put off for a running event loop


def open_in_mode(app, number, mode):
    index = next(i for i, e in enumerate(app.entries) if e.number == number)
    app.open_lesson(index)
    assert app.entry.ok, app.entry.errors
    control(app, "interpolation", mode)
    assert app.scene.interpolation == mode and app.state.pixel_mode == (mode == "pixel"), (number, mode)


def picture(app) -> np.ndarray:
    """The colours the page shows for the mesh: per point or cell, or the per-pixel image (mesh only)."""
    if app.scene.interpolation == "pixel":
        return app.view.pixel_image().reshape(-1, 3).astype(int)
    return np.asarray(app.view.colour_array().values, dtype=int)


def check_srgb(app, number, mode):
    """The picture with ``display = "srgb"`` is the sRGB curve of the picture with ``"linear"``."""
    control(app, "display", "srgb")
    srgb = picture(app)
    control(app, "display", "linear")
    raw = picture(app)
    control(app, "display", app.entry.scene.display)
    background = np.rint(np.asarray(app.view.background) * 255).astype(int)
    surface = np.any(srgb != background, axis=-1) | np.any(raw != background, axis=-1)
    mid = surface[:, None] & (raw >= MID[0]) & (raw <= MID[1])
    assert mid.sum() >= 20, f"lesson {number} ({mode}): only {mid.sum()} mid-tone values to check"
    # decoding the sRGB picture gives back the raw one, to the rounding of 8 bits
    decoded = np.rint(srgb_decode(srgb / 255.0) * 255).astype(int)
    off = np.abs(decoded - raw) > ROUNDING
    assert not np.any(off & mid), (
        f"lesson {number} ({mode}): {np.sum(off & mid)} of {mid.sum()} values are not sRGB-encoded, e.g. "
        f"raw {raw[np.any(off & mid, axis=-1)][:3].tolist()} shown as {srgb[np.any(off & mid, axis=-1)][:3].tolist()}")


def _turned(scene, degrees):
    """The browser's camera after turning ``degrees`` about the view's up axis through the focal point."""
    c = scene.camera
    up = np.asarray(c.up, float) / np.linalg.norm(c.up)
    offset = np.subtract(c.eye, c.focal_point)
    a = np.radians(degrees)
    # Rodrigues' rotation of the eye's offset about the up axis
    turned = offset * np.cos(a) + np.cross(up, offset) * np.sin(a) + up * np.dot(up, offset) * (1 - np.cos(a))
    return {"position": (np.add(c.focal_point, turned)).tolist(), "focalPoint": list(c.focal_point),
            "viewUp": list(c.up), "viewAngle": c.view_angle}


def check_turn(app, number, mode):
    """After the view turns, the readout's dots and V are the core's for the new eye."""
    v_before = np.array(app.view.probe_vectors.v) if app.view.probe_vectors is not None else None
    camera = _turned(app.scene, 30)
    app.on_camera(camera)
    scene = app.scene
    assert scene.camera.eye == pytest.approx(camera["position"]), (number, mode, scene.camera)
    point, normal = app.view.probe
    index = app.view.light_index
    if index is None:  # no directed light: no dots, but V still follows the eye
        return
    expected = core.vectors(point, normal, light=scene.lights[index], two_sided=scene.two_sided, **viewer(scene))
    shown = {d["name"]: float(d["value"]) for d in app.state.readout["dots"]}
    where = f"lesson {number} ({mode}), eye {scene.camera.eye}, probe {point}"
    # Cook–Torrance records no mirror vector: its dots are n·l, n·v, n·h and v·h
    cosines = (("n·l", expected.nl), ("n·h", expected.nh)) + (
        (("r·v", expected.rv),) if scene.model in core.PHONG_MODELS else ())
    for name, value in cosines:
        assert shown[name] == pytest.approx(value, abs=5e-4), (where, name, shown, value)
    assert np.allclose(app.view.probe_vectors.v, expected.v, atol=1e-9), (where, app.view.probe_vectors.v)
    assert not np.allclose(v_before, expected.v, atol=1e-3), f"V did not move: {where}"


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("number", NUMBERS)
def test_the_picture_is_srgb_encoded_and_the_readout_follows_the_eye(app, number, mode):
    open_in_mode(app, number, mode)
    check_srgb(app, number, mode)
    check_turn(app, number, mode)
