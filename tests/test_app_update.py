"""What a slider update leaves in a tab's state: what reading every control gives, though only changes are compared.

A slider step re-reads only the controls of the scene fields that changed and
compares only those (and any key the browser wrote) with the state, and sends
the arrows' legend and tips again only when a change can move them; these
tests check the state against every control and the arrows read afresh,
after steps of every kind and after a browser value the app had to ignore.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from app_support import open_app

LESSONS = Path(__file__).resolve().parent.parent / "lessons"


@pytest.fixture
def app(tmp_path):
    application = open_app(tmp_path, "04-specular.md", (LESSONS / "04-specular.md").read_text(encoding="utf-8"),
                           "test-update")
    yield application
    application.close()


def stale(app) -> dict:
    """State key -> (state value, control value) for every control whose state does not hold its value."""
    out = {}
    for key, control in app.controls.by_key.items():
        value = control.read(app.scene, app.options)
        if not control.same(app.state[key], value):
            out[key] = (app.state[key], value)
    return out


def glyphs(app) -> tuple:
    """The arrows' legend and tips as the view gives them now (what the state must hold)."""
    from phonglab.app import client

    legend = [{"letter": l, "meaning": m, "color": c} for l, m, c in app.view.legend()]
    return legend, client.arrow_tips(app.view.arrow_tips(), legend, hidden=app.view.hidden_letters())


def move(app, key, value) -> None:
    """A browser's write of ``key``, and the change handler trame runs for it (no server runs here)."""
    app.state[key] = value
    app._watcher(key)()


@pytest.mark.parametrize("key, value", [
    ("material__shininess__log", 2.2), ("material__ks__level", 0.25), ("material__kd__color", "#3366cc"),
    ("lights_1__azimuth", 40.0), ("lights_1__distance", 6.0), ("camera__azimuth", 30.0), ("interpolation", "flat"),
    ("lights_1__type", "spot"), ("view__term", "specular"), ("exposure", 0.5), ("model", "blinn-phong"),
])
def test_after_a_step_every_control_in_the_state_holds_its_value(app, key, value):
    assert not stale(app), stale(app)
    before = (app.scene, dict(app.options))
    move(app, key, value)
    assert (app.scene, app.options) != before, f"{key} = {value!r} changed nothing: {app.state.notice}"
    assert not stale(app), (key, value, stale(app))
    assert (app.state.legend, app.state.arrow_tips) == glyphs(app), (key, value)  # sent again only when they move


def test_a_browser_value_the_app_ignored_is_put_back_by_the_next_update(app):
    key = "material__ks__level"
    kept = app.state[key]
    app._busy = True  # a change being applied: the browser's value is not applied
    move(app, key, 0.05)
    app._busy = False
    assert app.state[key] == 0.05 and app.scene.material.ks != (0.05, 0.05, 0.05)
    move(app, "material__shininess__log", 2.0)  # another control's update
    assert app.controls.by_key[key].same(app.state[key], kept), (app.state[key], kept)
    assert not stale(app), stale(app)


STEPS = [
    ("material__shininess__log", 2.2), ("material__shininess__log", 1.3), ("material__shininess__log", 2.2),
    ("material__ks__level", 0.25), ("material__kd__color", "#3366cc"), ("lights_1__azimuth", 40.0),
    ("camera__azimuth", 30.0), ("interpolation", "flat"), ("lights_1__type", "spot"), ("view__term", "specular"),
    ("exposure", 0.5), ("model", "blinn-phong"), ("material__shininess__log", 1.3), ("lights_1__type", "point"),
]


def fresh_query(app) -> str:
    """The address of the view on screen, written by a new ViewAddress and ControlSet (nothing remembered)."""
    from phonglab.app import address
    from phonglab.app.controls import ControlSet

    controls = ControlSet(app.controls.frame, app.controls.lesson_paths, app.controls.extra)
    controls.update(app.scene)
    return address.ViewAddress().query(app.entry, app.scene, dict(app.options), controls)


def test_after_steps_of_every_kind_the_address_is_the_one_written_afresh(app):
    from phonglab.app import address

    for key, value in STEPS:
        move(app, key, value)
        assert app.state[address.QUERY_KEY] == fresh_query(app), (key, value)
