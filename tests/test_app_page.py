"""The lesson app without a browser: lessons, checked input, the colour push, picking, the readout."""

from __future__ import annotations

import re
import threading
from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.app.lesson_app import LessonApp, catalog
from phonglab.app.readout import probe_readout
from phonglab.bench.scenes import lesson, red_sphere_tables, write_lessons
from phonglab.render.glyphs import COLOR_ARRAY
from phonglab.scene import load_lesson

#: the red sphere with two of its controls and a probe
GOOD = lesson(
    """
number = 1
title = "Sphere"
goal = "See $k_s$."
controls = ["material.ks", "material.shininess"]
probe = [0.3, 0.4, 0.866]
""",
    red_sphere_tables(24),
    r"""
# Sphere

Diffuse is $k_d \max(0, n\cdot l)$.
""",
)


@pytest.fixture(scope="module")
def lessons(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lessons")
    (folder / "01-sphere.md").write_text(GOOD, encoding="utf-8")
    return write_lessons(folder, ["03-broken.md"])


@pytest.fixture
def app(lessons, tmp_path):
    from trame.app import get_server

    server = get_server(f"test-{tmp_path.name}", client_type="vue3")
    application = LessonApp(server, target=lessons, export_dir=tmp_path / "exports")
    yield application
    application.close()


def test_catalog_lists_good_and_broken_lessons_with_their_titles(lessons):
    entries, first = catalog(lessons / "03-broken.md")
    assert [(e.number, e.title, e.ok) for e in entries] == [(1, "Sphere", True), (3, "A broken lesson", False)]
    assert first == 1
    assert any("material.kd" in e and "-3" in e for e in entries[1].errors), entries[1].errors


def test_opening_lessons_fills_text_controls_and_errors(app):
    s = app.state
    assert s.lesson_title == "Sphere" and s.lesson_errors == []
    assert "<math" in s.lesson_html and "$" not in s.lesson_html, s.lesson_html
    assert s.material__ks__level == pytest.approx(0.6)
    assert s.material__shininess__log == pytest.approx(np.log10(20))
    app.open_lesson(1)
    assert s.lesson_errors and "03-broken.md" in s.lesson_errors[0], s.lesson_errors
    app.open_lesson(7)
    assert s.notice["kind"] == "error" and "no such lesson" in s.notice["text"]
    assert s.lesson_title == "A broken lesson", "a bad index leaves the page as it was"


def test_the_planners_reasons_and_the_readouts_notes_show_symbols_with_subscripts(app):
    """The planner wrote "k_a ∘ I_a = …" and the page showed the underscores (a student-eye review)."""
    from phonglab.app.wording import symbols_html

    rows = app.state.plan_computed + app.state.plan_skipped
    assert rows and all(row["html"] == symbols_html(row["reason"]) for row in rows), rows
    assert any("<sub>a</sub>" in row["html"] and "_" not in row["html"] for row in rows), rows
    readout = app.state.readout
    assert readout["notes_html"] == [symbols_html(note) for note in readout["notes"]], readout["notes"]


def test_a_broken_lesson_opened_after_a_comparison_shows_neither_the_comparison_nor_its_button(app):
    s = app.state
    app._on_control("view__compare", True)
    assert s.view__compare is True and s.compare_png["status"] in ("making", "ready"), s.compare_png
    app.open_lesson(1)
    assert s.lesson_errors, "lesson 3 is the broken one"
    assert s.view__compare is False and s.has_model_control is False and s.compare_png["status"] == "idle", \
        (s.view__compare, s.has_model_control, s.compare_png)
    assert s.lesson_html == "" and s.experiments == [] and s.answer_html == "", s.lesson_html


def test_a_colour_change_pushes_exactly_the_views_new_colours(app):
    before = np.array(app.view.mesh.point_data[COLOR_ARRAY])
    app._on_control("material__ks__level", 0.2)
    assert app.scene.material.ks == pytest.approx((0.2, 0.2, 0.2))
    push = app.state.view_colors
    colours = np.array(app.view.mesh.point_data[COLOR_ARRAY])
    assert not np.array_equal(colours, before), "k_s 0.6 -> 0.2 did not change the mesh colours"
    assert push["location"] == "point" and push["name"] == COLOR_ARRAY
    assert push["dataset"].endswith("-dataset")
    assert np.frombuffer(push["data"], np.uint8).reshape(-1, 3).tolist() == colours.tolist()


def without_a_loop(function, *args):
    """Call ``function`` in a thread where no event loop runs, as a script would: the app refreshes its panels at once.

    (Once the browser tests have started Playwright, its sync API keeps an event
    loop marked as running in the main thread, and the app would put the
    refresh off to a loop that never turns.)
    """
    errors = []

    def run():
        try:
            function(*args)
        except BaseException as exc:  # noqa: BLE001 - raised again in the caller's thread
            errors.append(exc)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    if errors:
        raise errors[0]


def test_a_value_change_keeps_the_controls_panel_and_a_new_light_type_redraws_it(app, monkeypatch):
    from phonglab.app import page

    drawn = []
    monkeypatch.setattr(page, "build_controls",
                        lambda server, chosen, all_controls=(): drawn.append([c.key for c in all_controls]))
    without_a_loop(app._on_control, "material__ks__level", 0.3)
    without_a_loop(app._on_control, "lights_1__azimuth", 20.0)
    assert app.scene.material.ks == pytest.approx((0.3,) * 3), app.state.notice
    assert app.state.material__ks__level == pytest.approx(0.3), app.state.notice
    assert app.state.lights_1__azimuth == pytest.approx(20), app.state.notice
    assert drawn == [], "a new value redrew the controls panel"
    without_a_loop(app._on_control, "lights_1__type", "directional")
    assert len(drawn) == 1, f"a point light turned directional redrew the panel {len(drawn)} times"
    assert "lights_1__elevation" in drawn[0] and "lights_1__distance" not in drawn[0], drawn[0]


@pytest.mark.parametrize("key, value", [
    ("material__ks__level", float("nan")),
    ("material__ks__level", "0.4"),
    ("material__kd", [1, "x", 2]),
    ("lights_1__attenuation_0", 0.0),
    ("interpolation", "phong"),
])
def test_bad_input_is_refused_visibly_and_the_scene_stays(app, key, value):
    scene = app.scene
    current = app.controls.by_key[key].read(scene, app.options)
    app._on_control(key, value)
    assert app.scene is scene, f"{key} = {value!r} changed the scene"
    assert app.state.notice["kind"] == "error" and "Refused" in app.state.notice["text"], app.state.notice
    assert app.state[key] == current, f"{key} was not reset to {current!r}"


def test_an_unexpected_failure_is_reported_not_raised(app, monkeypatch):
    def broken(scene, **_):
        raise RuntimeError("boom")

    monkeypatch.setattr(app.view, "update", broken)
    app._on_control("material__ks__level", 0.3)
    assert "boom" in app.state.notice["text"], app.state.notice


@pytest.mark.parametrize("call", [
    lambda app: app.open_lesson("two"),
    lambda app: app.open_lesson(None, 5, x=1),
    lambda app: app.apply_experiment(99),
    lambda app: app.apply_experiment({"a": 1}),
    lambda app: app.on_camera({"position": [0, 0, "far"]}),
    lambda app: app.on_camera([1, 2, 3]),
    lambda app: app.reset_lesson(1, 2, 3),
])
def test_triggers_with_odd_arguments_never_raise(app, call):
    scene = app.scene
    call(app)
    assert app.scene == scene


def test_a_failing_trigger_becomes_a_notice(app, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr("phonglab.render.figure", broken)
    app.export_figure()
    assert app.state.notice["kind"] == "error" and "disk full" in app.state.notice["text"], app.state.notice


def test_a_click_ray_moves_the_probe_to_the_first_surface_hit(app):
    # a ray from the eye towards (−0.5, 0.2, 0) hits the front of the unit sphere
    eye, target = np.array([0.0, 0.0, 4.0]), np.array([-0.5, 0.2, 0.0])
    app.on_pick({"ray": [eye.tolist(), target.tolist()]})
    p = np.array(app.scene.probe)
    assert abs(np.linalg.norm(p) - 1.0) < 0.02 and p[2] > 0 and p[0] < 0, p
    direction = (target - eye) / np.linalg.norm(target - eye)
    offset = (p - eye) - ((p - eye) @ direction) * direction
    assert np.linalg.norm(offset) < 0.02, f"probe {p} is off the click ray"
    for bad in (None, {"ray": "x"}, {"ray": [[0, 0, "a"], [1, 1, 1]]}, {"ray": [[0, 0, float("nan")], [1, 1, 1]]}):
        app.on_pick(bad)
        assert np.array(app.scene.probe) == pytest.approx(p), f"{bad!r} moved the probe"


def test_readout_numbers_are_the_cores(lessons):
    scene = load_lesson(lessons / "01-sphere.md").scene
    point = np.array([0.3, 0.4, 0.866])
    normal = point / np.linalg.norm(point)
    v = pl.vectors(point, normal, eye=scene.camera.eye, light=scene.lights[1])
    out = probe_readout(scene, point, normal, 1)
    shown = {d["name"]: float(d["value"]) for d in out["dots"]}
    assert shown == pytest.approx({"n·l": v.nl, "r·v": v.rv, "n·h": v.nh}, abs=5e-4)
    shading = pl.shade(point[None], normal[None], eye=scene.camera.eye, material=scene.material,
                       lights=scene.lights)
    terms = {t["name"]: [float(x) for x in t["value"].strip("()").split(",")] for t in out["terms"]}
    assert terms["total"] == pytest.approx(shading.color[0], abs=5e-4)
    assert terms["specular"] == pytest.approx(shading.specular[0], abs=5e-4)
    labels = re.findall(r'<span class="eq-label">(\w+)</span><math', out["equation"])
    assert labels == ["model", "ambient", "diffuse", "specular", "sum"], out["equation"][:200]


def test_readout_says_why_a_light_behind_the_surface_adds_nothing(lessons):
    scene = load_lesson(lessons / "01-sphere.md").scene
    point = np.array([-0.6, -0.6, -0.5291])
    normal = point / np.linalg.norm(point)
    v = pl.vectors(point, normal, eye=scene.camera.eye, light=scene.lights[1])
    assert v.nl < 0
    out = probe_readout(scene, point, normal, 1)
    assert any("n·l ≤ 0" in note for note in out["notes"]), out["notes"]
    terms = {t["name"]: t["value"] for t in out["terms"]}
    assert terms["diffuse"] == terms["specular"] == "(0.000, 0.000, 0.000)"


def test_export_writes_a_png_through_the_figure_code(app):
    app.export_figure()
    assert app.state.notice["kind"] == "success", app.state.notice
    files = list(app.export_dir.glob("lesson-01-*.png"))
    assert len(files) == 1 and files[0].read_bytes()[:4] == b"\x89PNG"
    # the same bytes go to the browser as a download
    sent = app.state.phonglab_download
    assert sent["name"] == files[0].name and sent["url"].startswith("data:image/png;base64,"), sent["name"]
    import base64

    assert base64.b64decode(sent["url"].split(",", 1)[1]) == files[0].read_bytes()


def test_export_without_an_export_folder_leaves_no_server_copy(app, tmp_path, monkeypatch):
    monkeypatch.setattr(app, "export_dir", None)
    monkeypatch.chdir(tmp_path)
    before = sorted(tmp_path.rglob("*"))
    app.export_figure("terms")
    assert app.state.notice["kind"] == "success", app.state.notice
    assert "-terms-" in app.state.phonglab_download["name"]
    assert sorted(tmp_path.rglob("*")) == before, "a file was written on the server"


MISTAKE_LESSON = GOOD.replace('probe = [0.3, 0.4, 0.866]', 'probe = [0.3, 0.4, 0.866]\nmistake = "unnormalised-normals"')


@pytest.fixture
def mistake_app(lesson_app):
    return lesson_app("01-raw.md", MISTAKE_LESSON, "test-mistake")


def test_the_mistake_switch_goes_through_the_view_and_says_when_it_cannot_show(mistake_app):
    app = mistake_app
    assert app.state.mistake["available"] and "view__mistake" in app.controls.by_key
    before = np.array(app.view.mesh.point_data[COLOR_ARRAY])
    app._on_control("view__mistake", True)
    # per vertex the normals are unit vectors: same colours, and the page says why
    assert app.view.mistake == "unnormalised-normals"
    assert np.array_equal(np.asarray(app.view.mesh.point_data[COLOR_ARRAY]), before)
    assert "per-pixel" in app.state.mistake_note, app.state.mistake_note
    # per pixel the mistake shows in the picture, and the note goes away
    app._on_control("interpolation", "pixel")
    wrong = app.state.pixel_src
    assert app.state.mistake_note == "" and wrong.startswith("data:image/png")
    app._on_control("view__mistake", False)
    assert app.view.mistake is None and app.state.pixel_src != wrong, "switching the mistake off kept the picture"
    app._on_control("view__mistake", True)
    assert app.state.pixel_src == wrong, "the same mistake twice gave two pictures"


def test_every_course_lesson_opens_in_the_app_and_its_experiments_apply(tmp_path):
    # the real lessons/ folder, as `phonglab serve` shows it
    from pathlib import Path

    from trame.app import get_server

    folder = Path(__file__).resolve().parents[1] / "lessons"
    server = get_server(f"test-course-{tmp_path.name}", client_type="vue3")
    app = LessonApp(server, target=folder, export_dir=tmp_path / "exports")
    try:
        assert len(app.entries) >= 10 and all(e.ok for e in app.entries), [(e.title, e.errors) for e in app.entries]
        for index, entry in enumerate(app.entries):
            app.open_lesson(index)
            s = app.state
            where = f"lesson {entry.number} {entry.title!r}"
            assert s.lesson_title == entry.title and not s.lesson_errors, (where, s.lesson_errors)
            assert "<math" in s.lesson_html and "$" not in s.lesson_html, where
            colours = np.array(app.view.mesh.point_data[COLOR_ARRAY])
            assert colours.size and colours.max() > 0, (where, "the mesh is black")
            for k, experiment in enumerate(entry.lesson.experiments):
                before = app.scene
                app.apply_experiment(k)
                assert s.notice["kind"] != "error", (where, experiment.label, s.notice)
                assert app.scene == before.replace_many(experiment.settings), (where, experiment.label)
    finally:
        app.close()


def test_an_experiment_that_sets_k_d_to_0_leaves_the_page_its_colour(tmp_path):
    """Lesson 1's "Ambient only", then the k_d slider up again: the sphere gets its colour back, not white."""
    from pathlib import Path

    from trame.app import get_server

    from phonglab.app.control import rgb_to_hex

    source = Path(__file__).resolve().parents[1] / "lessons" / "01-light-and-surfaces.md"
    (tmp_path / source.name).write_text(source.read_text(encoding="utf-8"), encoding="utf-8")
    app = LessonApp(get_server(f"hue-{tmp_path.name}", client_type="vue3"), target=tmp_path)
    try:
        kd = app.scene.material.kd
        ambient_only = next(i for i, e in enumerate(app.entry.lesson.experiments) if e.label == "Ambient only")
        app.apply_experiment(ambient_only)
        assert max(app.scene.material.kd) == 0 and app.state.material__kd__color == rgb_to_hex([c / max(kd) for c in kd])
        app._on_control("material__kd__level", max(kd))
        assert app.scene.material.kd == pytest.approx(kd), (kd, app.scene.material.kd)
    finally:
        app.close()


def test_a_material_control_after_a_lights_controls_has_its_own_heading(lesson_app):
    # lesson 5 lists light 1's and light 2's controls, then k_d: without a heading, k_d read as light 2's
    from phonglab.app import page

    text = (Path(__file__).resolve().parents[1] / "lessons" / "05-whole-model.md").read_text(encoding="utf-8")
    app = lesson_app("05-whole-model.md", text, "material-heading")
    template = app.state[f"trame__template_{page.CONTROLS_TEMPLATE}"]
    lesson_part = template.split('class="v-expansion-panels', 1)[0].split("phonglab-all", 1)[0]
    order = re.findall(r'phonglab-subsection">\s*([^<]+?)\s*<|phonglab-control-(material__kd__level)\b', lesson_part)
    seen = [heading or control for heading, control in order]
    assert "material__kd__level" in seen, seen
    before = seen[:seen.index("material__kd__level")]
    assert before and before[-1] == "Material", seen
    # a lesson that starts with the material still shows it without a heading
    text4 = (Path(__file__).resolve().parents[1] / "lessons" / "04-specular.md").read_text(encoding="utf-8")
    app4 = lesson_app("04-specular.md", text4, "material-heading-4")
    template4 = app4.state[f"trame__template_{page.CONTROLS_TEMPLATE}"].split("phonglab-all", 1)[0]
    first = template4.find("phonglab-control-material__shininess__log")
    assert first > 0 and "phonglab-subsection" not in template4[:first], template4[:first][-300:]


def test_a_notice_sets_k_s_as_the_formulas_do_and_escapes_the_rest(lesson_app):
    text = (Path(__file__).resolve().parents[1] / "lessons" / "10-beyond-phong.md").read_text(encoding="utf-8")
    app = lesson_app("10-beyond-phong.md", text, "notice-html")
    index = next(i for i, x in enumerate(app.entry.lesson.experiments) if x.label.startswith("Sharp, same"))
    app.apply_experiment(index)
    notice = app.state.notice
    assert "$" not in notice["text"] and "$" not in notice["html"], notice
    assert "<i>k</i><sub>s</sub>" in notice["html"], notice
    app.notify("error", "Refused: <b>k_d</b> must be at most 1")
    notice = app.state.notice
    assert "&lt;b&gt;" in notice["html"] and "<b>" not in notice["html"], notice
    assert "<i>k</i><sub>d</sub>" in notice["html"], notice
