"""A turn of the view costs the browser and the server only what changed.

The colour push carries trame-vtk's hash of the colour array (so the drag's
end synchronisation finds the bytes the browser already has), a camera event
that moved nothing refreshes nothing, and a turn plans its scene once.
"""

from __future__ import annotations

import numpy as np
import pytest

from phonglab.bench.scenes import lesson, red_sphere_tables

from app_support import browser_camera

SPHERE = lesson(
    """
number = 4
title = "Sphere"
controls = ["material.shininess"]
probe = [0.3, 0.4, 0.866]
""",
    red_sphere_tables(16),
    "# Sphere\n",
)



@pytest.fixture
def app(lesson_app):
    return lesson_app("04-sphere.md", SPHERE, "test-turn-sync")


def test_the_colour_push_carries_the_hash_trame_vtk_gives_the_array(app):
    from trame_vtk.modules.vtk.serializers.utils import hash_data_array

    for degrees in (20, -15):
        app.on_camera(browser_camera(app.scene, degrees))
        push = app.state.view_colors
        array = app.view.mesh.GetPointData().GetArray(push["name"])
        assert push["hash"] == hash_data_array(array), (degrees, push["hash"])
        assert push["data"] == app.view.colour_array().values.tobytes()


def test_a_camera_event_that_moved_nothing_synchronises_nothing(app, monkeypatch):
    syncs = []
    monkeypatch.setattr(app.html_view, "update", lambda *a, **k: syncs.append(app.scene.camera))
    turned = browser_camera(app.scene, 25)
    app.on_camera(turned)
    assert len(syncs) == 1, syncs  # the drag's end: arrows and markers
    app.on_camera(turned)  # a click: the same camera again
    app.on_camera_move(turned)
    assert len(syncs) == 1, f"a camera already shown was synchronised again: {syncs}"
    # a drag: its frames re-shade, its end (the same camera as the last frame) synchronises once
    later = browser_camera(app.scene, 10)
    app.on_camera_move(later)
    assert len(syncs) == 1, syncs
    app.on_camera(later)
    assert len(syncs) == 2 and syncs[-1].eye == pytest.approx(later["position"]), syncs


def test_a_turn_plans_its_scene_once(app, monkeypatch):
    import phonglab.app.lesson_app as lesson_app
    import phonglab.scene.planner as planner

    planned = []
    real = planner.plan

    def counting(scene):
        planned.append(scene)
        return real(scene)

    monkeypatch.setattr(planner, "plan", counting)
    monkeypatch.setattr(lesson_app, "plan", counting)
    turned = browser_camera(app.scene, 30)
    app.on_camera(turned)
    # the view's shading and the planner verdict share one plan (the readout plans its per-light parts)
    times = sum(scene is app.scene for scene in planned)
    assert times == 1, f"the turned scene was planned {times} times (eye {app.scene.camera.eye})"


def _apply(base: bytes, push: dict) -> bytes:
    """What the browser does with a push: the whole array, or the base with the changed rows replaced."""
    if "data" in push:
        return push["data"]
    rows = np.frombuffer(push["rows"], dtype=np.uint32)
    out = np.frombuffer(base, dtype=np.uint8).reshape(-1, 3).copy()
    out[rows] = np.frombuffer(push["values"], dtype=np.uint8).reshape(-1, 3)
    return out.tobytes()


def test_a_turn_sends_only_the_rows_that_changed_once_the_browser_shows_the_last_push(app):
    from phonglab.app import client

    app.on_camera_move(browser_camera(app.scene, 10))
    first = app.state.view_colors
    assert "data" in first, "the first push must be whole: the browser has no pushed colours yet"
    # the browser has not said what it shows: the next push is whole too
    app.on_camera_move(browser_camera(app.scene, 5))
    assert "data" in app.state.view_colors, sorted(app.state.view_colors)
    shown = app.state.view_colors
    app.state[client.SHOWN_KEY] = shown["hash"]  # what phonglab.js sets once it applied that push
    app.on_camera_move(browser_camera(app.scene, 4))
    change = app.state.view_colors
    colours = app.view.colour_array().values
    assert "data" not in change and change["base"] == shown["hash"], sorted(change)
    rows = np.frombuffer(change["rows"], dtype=np.uint32)
    assert 0 < len(rows) < len(colours) // 4, f"{len(rows)} of {len(colours)} rows sent"
    assert _apply(shown["data"], change) == colours.tobytes(), "the change does not rebuild the new colours"
    assert change["hash"] != shown["hash"]
    # a browser that could not apply it says so (None): the next push is whole again
    app.state[client.SHOWN_KEY] = None
    app.on_camera_move(browser_camera(app.scene, 3))
    assert "data" in app.state.view_colors


def test_color_change_falls_back_to_the_whole_array():
    from phonglab.app.client import color_change

    base = np.zeros((10, 3), np.uint8)
    payload = {"dataset": "d", "name": "rgb", "location": "point", "hash": "new", "data": b"x" * 30}
    previous = {"dataset": "d", "name": "rgb", "location": "point", "hash": "old"}
    most = base.copy()
    most[:8] = 200  # most rows changed: the whole array is as cheap
    assert color_change(payload, previous, most, base) is payload
    assert color_change(payload, None, most, base) is payload
    assert color_change(payload, {**previous, "location": "cell"}, most, base) is payload
    assert color_change(payload, previous, np.zeros((11, 3), np.uint8), base) is payload
    one = base.copy()
    one[4] = (1, 2, 3)
    change = color_change(payload, previous, one, base)
    assert np.frombuffer(change["rows"], np.uint32).tolist() == [4] and change["values"] == bytes([1, 2, 3]), change
    assert change["base"] == "old" and change["hash"] == "new" and "data" not in change, change


def test_a_click_in_a_lesson_whose_up_leans_is_not_a_turn(lesson_app):
    # lesson 7's camera.up, [0, 0, 1], leans on its view direction; vtk.js reports after a click the camera it
    # shows with the up made perpendicular and the view angle the server fitted: the same picture, not a turn
    from pathlib import Path

    from phonglab.app import address

    text = (Path(__file__).resolve().parent.parent / "lessons" / "07-light-sources.md").read_text(encoding="utf-8")
    app = lesson_app("07-light-sources.md", text, "test-click-lean")
    before, shown = app.scene, app.view.camera_state()
    d = np.subtract(shown.focal_point, shown.eye)
    up = np.subtract(shown.up, np.dot(shown.up, d) / np.dot(d, d) * d)
    clicked = {"position": list(shown.eye), "focalPoint": list(shown.focal_point),
               "viewUp": (up / np.linalg.norm(up)).tolist(), "viewAngle": shown.view_angle}
    assert not np.allclose(clicked["viewUp"], before.camera.up), (clicked, before.camera)  # the case at hand
    app._apply_camera(clicked, final=True)
    app._refresh_panels()
    query = app.state[address.QUERY_KEY]
    assert app.scene is before, (clicked, before.camera, app.scene.camera)
    assert "view.turned" not in query and "camera." not in query, (clicked, query)
    # a real turn still is one
    app._apply_camera(browser_camera(app.scene, 20), final=True)
    app._refresh_panels()
    assert "view.turned=true" in app.state[address.QUERY_KEY], app.state[address.QUERY_KEY]
