"""The accuracy lesson's panel without a browser: checked picks, the images following the scene, the plot once."""

from __future__ import annotations

import base64
import concurrent.futures
import io
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from phonglab.accuracy import error_images
from phonglab.app import accuracy_panel as panel
from phonglab.app.lesson_app import LessonApp
from phonglab.bench.scenes import LESSONS

ACCURACY = LESSONS["11-accuracy.md"]

OTHER = ACCURACY.replace("number = 11", "number = 1").replace('title = "Accuracy costs time"', 'title = "Sphere"')


def inline(function, *args):
    """Run the work here and now: a done Future (what the worker processes would give later)."""
    future = concurrent.futures.Future()
    try:
        future.set_result(function(*args))
    except Exception as exc:  # noqa: BLE001 - handed to the Future like a worker would
        future.set_exception(exc)
    return future


@pytest.fixture
def calls(monkeypatch):
    """Work runs inline at 32 pixels; every submitted call is noted; the plot is a stand-in."""
    made = []

    def submit(function, *args):
        made.append((function.__name__, args))
        return inline(function, *args)

    monkeypatch.setattr(panel, "submit", submit)
    monkeypatch.setattr(panel, "IMAGE_SIZE", 32)
    def stand_in_plot():
        return "data:image/png;base64,cGxvdA=="

    monkeypatch.setattr(panel, "plot_data_url", stand_in_plot)
    monkeypatch.setattr(panel, "_plot", None)
    return made


@pytest.fixture
def app(tmp_path, calls):
    from trame.app import get_server

    (tmp_path / "01-sphere.md").write_text(OTHER, encoding="utf-8")
    (tmp_path / "11-accuracy.md").write_text(ACCURACY, encoding="utf-8")
    server = get_server(f"test-accuracy-{tmp_path.name}", client_type="vue3")
    application = LessonApp(server, target=tmp_path / "11-accuracy.md", export_dir=tmp_path / "exports")
    yield application
    application.close()


def control(app, key, value) -> None:
    """Set a control as the browser would, and run the panel refresh the app may have put off.

    When a browser test ran earlier in this process, Playwright's event loop
    counts as running and the app defers its panels to it.
    """
    app._on_control(key, value)
    app._later.run_waiting()  # a refresh the app put off for a running event loop


def decode(url: str) -> np.ndarray:
    assert url.startswith("data:image/png;base64,"), url[:40]
    with Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))) as image:
        return np.asarray(image.convert("RGB"))


@pytest.mark.parametrize("value", [7, 16.5, "16", True, None, float("nan"), [16]])
def test_bad_resolutions_are_refused_naming_the_value_and_the_choices(value):
    with pytest.raises(ValueError, match=r"accuracy\.resolution: must be one of 8, 16, 32, 64, 128, 256") as info:
        panel.check_resolution(value)
    assert repr(value) in str(info.value)


@pytest.mark.parametrize("value", ["phong", "", None, 1, ["flat"]])
def test_bad_methods_are_refused_naming_the_value_and_the_choices(value):
    with pytest.raises(ValueError, match=r"accuracy\.method: must be one of flat, gouraud, pixel") as info:
        panel.check_method(value)
    assert repr(value) in str(info.value)


def test_good_picks_pass_and_the_lesson_is_found_by_its_file_name():
    assert panel.check_resolution(64) == 64 and panel.check_resolution(32.0) == 32
    assert panel.check_method("pixel") == "pixel"
    assert panel.is_accuracy_lesson("lessons/11-accuracy.md") and panel.is_accuracy_lesson("x/3-accuracy.md")
    assert not panel.is_accuracy_lesson("lessons/08-interpolation.md")
    assert not panel.is_accuracy_lesson("lessons/11-accuracy-notes.md")


def test_error_panel_shows_the_error_images_and_their_figures(monkeypatch):
    monkeypatch.setattr(panel, "IMAGE_SIZE", 32)
    shown = panel.error_panel("gouraud", 16, 50.0)
    exact = error_images("gouraud", 16, size=32, shininess=50.0)
    for key in ("render", "reference", "error"):
        assert np.array_equal(decode(shown[key]), getattr(exact, key)), f"{key} differs from error_images'"
    assert decode(shown["scale"]).shape[1] == 256
    assert shown["scale_labels"] == ["10⁻⁴", "10⁻³", "10⁻²", "10⁻¹", "1"]
    figures = {f["name"]: f["value"] for f in shown["figures"]}
    for name, value in (("RMSE", exact.rmse), ("max error", exact.max_error), ("peak error", exact.peak_error)):
        assert float(figures[name]) == pytest.approx(value, rel=5e-3), (name, figures[name], value)
    assert figures["time"].endswith(" ms") and float(figures["time"][:-3]) > 0, figures


def test_the_panel_shows_on_the_accuracy_lesson_only_and_follows_its_scene(app, calls):
    s = app.state
    assert s.accuracy and s.accuracy_plot == {"status": "ready", "src": "data:image/png;base64,cGxvdA==", "error": ""}
    assert (s.accuracy_method, s.accuracy_resolution) == ("gouraud", 16)
    assert (s.accuracy_view["method"], s.accuracy_view["resolution"], s.accuracy_view["shininess"]) == ("gouraud", 16, 200)
    assert not s.accuracy_busy
    # an experiment (interpolation and resolution) moves the picker; α moves the images
    control(app, "interpolation", "pixel")
    assert (s.accuracy_method, s.accuracy_view["method"]) == ("pixel", "pixel")
    control(app, "material__shininess__log", 1.0)
    assert s.accuracy_view["shininess"] == pytest.approx(10.0), s.accuracy_view["shininess"]
    control(app, "material__shininess__log", 2.39)  # α = 245.470892: the caption writes it as the slider does
    assert s.accuracy_view["alpha"] == "245.47", s.accuracy_view
    assert s.accuracy_unpicked == "", s.accuracy_unpicked
    # a resolution the picker does not offer leaves the pick alone, and the panel says why
    control(app, "geometry__resolution", 20.0)
    assert s.accuracy_resolution == 16 and s.accuracy_view["resolution"] == 16
    assert "20 segments" in s.accuracy_unpicked and "8, 16, 32, 64, 128, 256" in s.accuracy_unpicked, s.accuracy_unpicked
    control(app, "geometry__resolution", 32.0)  # one it offers: followed, and the note goes
    assert s.accuracy_resolution == 32 and s.accuracy_unpicked == "", (s.accuracy_resolution, s.accuracy_unpicked)
    # the picker itself; the same pick twice computes once
    count = len(calls)
    s.accuracy_resolution = 64
    app.accuracy._on_pick("accuracy_resolution", panel.check_resolution)
    app.accuracy._on_pick("accuracy_resolution", panel.check_resolution)
    assert s.accuracy_view["resolution"] == 64 and len(calls) == count + 1, calls[count:]
    # another lesson hides the panel and asks for nothing
    app.open_lesson(0)
    assert not s.accuracy and len(calls) == count + 1


def test_bad_picks_are_refused_visibly_and_the_previous_value_stays(app):
    s = app.state
    shown = s.accuracy_view
    for key, check, bad in (("accuracy_resolution", panel.check_resolution, 7),
                            ("accuracy_method", panel.check_method, "phong")):
        before = s[key]
        s[key] = bad
        app.accuracy._on_pick(key, check)
        assert s.notice["kind"] == "error" and "Refused" in s.notice["text"] and repr(bad) in s.notice["text"], s.notice
        assert s[key] == before, f"{key} kept the refused {bad!r}"
        assert s.accuracy_view is shown


def test_the_plot_is_measured_once_per_process_and_again_after_a_failure(app, calls, monkeypatch, tmp_path):
    from trame.app import get_server

    plots = [name for name, _ in calls if name == "stand_in_plot"]
    assert len(plots) == 1
    other = LessonApp(get_server(f"test-accuracy-2-{tmp_path.name}", client_type="vue3"),
                      target=tmp_path / "11-accuracy.md", export_dir=tmp_path / "exports")
    try:
        assert other.state.accuracy_plot["status"] == "ready"
        assert [name for name, _ in calls if name == "stand_in_plot"] == plots, "a second tab measured the plot again"
    finally:
        other.close()

    def broken():
        raise RuntimeError("matplotlib is missing")

    monkeypatch.setattr(panel, "_plot", None)
    monkeypatch.setattr(panel, "plot_data_url", broken)
    app.open_lesson(1)
    failed = app.state.accuracy_plot
    # in plain words (the error itself is in the server's log), the last plot kept
    assert failed["status"] == "failed" and "stopped with an error" in failed["error"], failed
    assert "RuntimeError" not in failed["error"] and failed["src"] == "data:image/png;base64,cGxvdA==", failed
    monkeypatch.setattr(panel, "plot_data_url", lambda: "data:image/png;base64,YWdhaW4=")
    app.open_lesson(1)
    assert app.state.accuracy_plot == {"status": "ready", "src": "data:image/png;base64,YWdhaW4=", "error": ""}


def test_the_worker_processes_run_the_work_and_stop():
    try:
        future = panel.submit(panel.check_resolution, 32)
        assert future.result(timeout=60) == 32
        failing = panel.submit(panel.check_method, "phong")
        with pytest.raises(ValueError, match="accuracy.method"):
            failing.result(timeout=60)
    finally:
        panel.shutdown()
    from phonglab.app import worker

    assert not worker.started()


@pytest.mark.parametrize("method, resolution", [("pixel", 16), ("gouraud", 128)])
def test_the_error_figures_a_lesson_states_are_the_panels(method, resolution):
    # the peak error is one pixel's and moves with the pixel grid (0.06 at 160 pixels, 0.14 at 256 for
    # per-pixel shading of 16 segments): lesson 11 stated one grid's figure while the panel showed another's
    from phonglab.accuracy import claims
    from phonglab.scene.lessons import load_lesson

    lesson_file = Path(__file__).resolve().parents[1] / "lessons" / "11-accuracy.md"
    scene = load_lesson(lesson_file).scene.replace_many([("camera.view_angle", 30.0)])
    shown = panel.error_panel(method, resolution, scene.material.shininess)
    figures = {f["name"]: f["value"] for f in shown["figures"]}
    for measure, name in (("peak_error", "peak error"), ("highlight_rmse", "highlight RMSE"), ("rmse", "RMSE")):
        stated = claims._error(scene, method, float(resolution), measure)
        assert panel._figure(stated) == figures[name], (method, resolution, measure, stated, figures)


def test_the_accuracy_lesson_offers_no_probe_and_a_click_leaves_it_where_it_is(app):
    """Its panel takes the readout's place: a probe there moved arrows whose numbers the page never showed."""
    ray = {"ray": [[0.2, -0.1, 3.0], [0.2, -0.1, -3.0]]}
    probe = app.scene.probe
    app.on_pick(ray)
    assert app.scene.probe == probe, f"a click in the accuracy lesson moved the probe from {probe} to {app.scene.probe}"
    template = app.ui.html
    toggle = template[template.index("phonglab-pick-toggle") - 400:template.index("phonglab-pick-toggle") + 200]
    assert 'v-if="!accuracy"' in toggle, f"the Probe/Light toggle is offered in the accuracy lesson: {toggle}"
    assert "accuracy ? 'Drag to turn'" in template, "the hint still says: Click the surface to move the probe"
    app.open_lesson(0)  # another lesson: a click moves the probe there (the test can fail)
    before = app.scene.probe
    app.on_pick(ray)
    assert app.scene.probe != before, f"a click in lesson 1 left the probe at {before}"


def test_the_panel_offers_every_mesh_the_lessons_error_figures_are_measured_on():
    """The text quoted Gouraud on 256 segments (0.10, 0.03) while the picker stopped at 128."""
    import re

    text = (Path(__file__).resolve().parents[1] / "lessons" / "11-accuracy.md").read_text(encoding="utf-8")
    quoted = {int(n) for n in re.findall(r"error\('\w+', (\d+), '\w+'\)", text)}
    assert quoted, "the lesson's claims name no error(method, resolution, measure)"
    missing = sorted(quoted - set(panel.RESOLUTIONS))
    assert not missing, f"the lesson measures {sorted(quoted)}, the panel offers {panel.RESOLUTIONS}: missing {missing}"
