"""An address brings back the view on screen: every experiment of every lesson, a turn, a pick, Reset.

Tab A applies what a student does; its address is opened in tab B, a fresh
tab (its own :class:`~phonglab.app.lesson_app.LessonApp`), through the same
code the page runs (:meth:`LessonApp._on_address`). B must show the same
scene: the readout's texts to the last digit shown, the controls' values, the
letters' tips, and the picture pixel for pixel (the view's screenshot, which
in per-pixel mode is the page's picture). The browser's part, that the page
writes this query into its address bar after each change and reopens it, is
``tests/browser/test_address_round_trip.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from app_support import browser_camera

from phonglab.app import address
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
ENTRIES, _ = catalog(LESSONS)
EXPERIMENTS = [(e.path.stem, k) for e in ENTRIES if e.ok and e.lesson for k in range(len(e.lesson.experiments))]
#: the views' size here: small, so every experiment's two pictures stay cheap
SIZE = (192, 144)


@pytest.fixture(scope="module")
def tabs():
    """Two tabs on the real lessons, A (the student's) and B (the fresh tab the address opens in)."""
    import concurrent.futures

    from trame.app import get_server

    from phonglab.app import accuracy_panel
    from phonglab.app.lesson_app import LessonApp

    # the accuracy lesson's studies are not what this compares: they never start here
    patch = pytest.MonkeyPatch()
    patch.setattr(accuracy_panel, "submit", lambda *a, **k: concurrent.futures.Future())
    apps = []
    for name in ("a", "b"):
        app = LessonApp(get_server(f"address-scenes-{name}", client_type="vue3"), target=LESSONS)
        app.view.set_size(SIZE)
        apps.append(app)
    yield apps
    for app in apps:
        app.close()
    patch.undo()


def _index(app, stem):
    return [e.path.stem for e in app.entries].index(stem)


def _shown(app) -> dict:
    """What the tab shows: the texts of the readout and controls, the letters' tips, the picture."""
    s = app.state
    return {"readout": s.readout, "controls": s.control_values, "tips": s.arrow_tips, "term": app.options.get("term"),
            "mistake": app.options.get("mistake", False), "picture": app.view.screenshot()}


def _reopened(b, stem, query) -> dict:
    """Tab B opened fresh on ``query`` (as a new page sends it)."""
    b.open_lesson(_index(b, stem))  # the lesson as it opens, then the address's settings
    b.state[address.REQUEST_KEY] = query
    b._on_address()
    return _shown(b)


def _assert_same(query, a, b):
    problems = [name for name in ("readout", "controls", "tips", "term", "mistake") if a[name] != b[name]]
    assert not problems, (query, {name: (a[name], b[name]) for name in problems})
    diff = np.argwhere(np.any(a["picture"] != b["picture"], axis=-1))
    assert len(diff) == 0, (query, f"{len(diff)} pixels differ, first at row, column {diff[0].tolist()}:",
                            a["picture"][tuple(diff[0])].tolist(), b["picture"][tuple(diff[0])].tolist())


@pytest.mark.parametrize("stem, k", EXPERIMENTS, ids=[f"{s[:2]}-{k}" for s, k in EXPERIMENTS])
def test_the_address_after_an_experiment_reopens_the_same_view(tabs, stem, k):
    a, b = tabs
    a.open_lesson(_index(a, stem))
    a.apply_experiment(k)
    query = a.state[address.QUERY_KEY]
    shown = _shown(a)
    again = _reopened(b, stem, query)
    assert b.state.notice is None, (query, b.state.notice)
    assert b.state[address.QUERY_KEY] == query, (query, b.state[address.QUERY_KEY])
    _assert_same(query, shown, again)


def test_a_turned_zoomed_and_picked_view_after_experiments_comes_back(tabs):
    # lesson 7: every experiment in turn, the view turned by the mouse (its up vector tilts), zoomed past the
    # eye slider's end, the probe picked, the light moved by a pick: the address after each step
    a, b = tabs
    stem = "07-light-sources"
    a.open_lesson(_index(a, stem))
    steps = [lambda: a.apply_experiment(1), lambda: a.apply_experiment(0), lambda: a.apply_experiment(2)]
    for step in steps:
        step()
        _assert_same(a.state[address.QUERY_KEY], _shown(a), _reopened(b, stem, a.state[address.QUERY_KEY]))
    turned = browser_camera(a.scene, 23.0)
    turned["viewUp"] = [0.1, 0.05, 0.99]
    a.on_camera(turned)
    focal = np.array(a.scene.camera.focal_point)
    near = focal + 0.2 * (np.array(a.scene.camera.eye) - focal)  # nearer than the eye-distance slider goes
    a.on_camera({**turned, "position": near.tolist()})
    query = a.state[address.QUERY_KEY]
    assert "camera.eye=" in query and "camera.distance" not in query, query
    _assert_same(query, _shown(a), _reopened(b, stem, query))
    a.on_pick({"ray": [[0.2, -0.1, 3.0], [0.2, -0.1, -3.0]]})
    query = a.state[address.QUERY_KEY]
    assert "probe=" in query, query
    _assert_same(query, _shown(a), _reopened(b, stem, query))
    a.state.pick_target = "light"
    a.on_pick({"ray": [[-0.4, 0.3, 3.0], [-0.4, 0.3, -3.0]]})
    _assert_same(a.state[address.QUERY_KEY], _shown(a), _reopened(b, stem, a.state[address.QUERY_KEY]))
    a.state.pick_target = "probe"
    a.reset_lesson()
    assert a.state[address.QUERY_KEY] == f"?lesson={stem}", a.state[address.QUERY_KEY]
