"""The page's address names the lesson; a query from the browser is checked like any client value."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from phonglab.app import address

ENTRIES = [SimpleNamespace(path=Path("lessons") / name) for name in ("01-light.md", "04-specular.md")]


def test_query_round_trips_to_the_same_lesson():
    for i, entry in enumerate(ENTRIES):
        query = address.query_for(entry)
        assert address.lesson_index(query, ENTRIES) == (i, None), query


@pytest.mark.parametrize("query", [None, "", "?", "?other=1", "?lesson="])
def test_nothing_asked_opens_nothing(query):
    assert address.lesson_index(query, ENTRIES) == (None, None), query


@pytest.mark.parametrize("query, words", [
    ("?lesson=99-nope", "a lesson called 99-nope, but there is none"),
    ("?lesson=../../etc/passwd", "but there is none"),
    (42, "not a query string"),
    ("?lesson=" + "x" * 3000, "not a query string"),
])
def test_a_bad_address_is_refused_with_a_problem(query, words):
    index, problem = address.lesson_index(query, ENTRIES)
    assert index is None and words in problem, (str(query)[:40], problem)


# ---------------------------------------------------------------------------
# the settings in the address

from hypothesis import assume, given, settings, strategies as st  # noqa: E402

from phonglab.app.control import ControlError  # noqa: E402

from phonglab.app import controls as ctl  # noqa: E402
from phonglab.scene import scene_to_dict  # noqa: E402
from phonglab.scene.lessons import catalog  # noqa: E402

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
REAL, _ = catalog(LESSONS)
SPECULAR = next(e for e in REAL if e.path.stem == "04-specular")


def _controls(entry):
    """The tab's controls for ``entry`` (as LessonApp builds them), fitted to its scene."""
    extra = {"view__mistake": ctl.MISTAKE_SWITCH} if entry.lesson and entry.lesson.mistake else {}
    controls = ctl.ControlSet(ctl.Frame.of_camera(entry.scene.camera), entry.lesson.controls if entry.lesson else (),
                              extra)
    controls.update(entry.scene)
    return controls


def _change(entry, changes):
    """The scene and options after the widget values ``changes`` (state key -> value), as a student sets them."""
    controls = _controls(entry)
    scene, options = entry.scene, dict(address.DEFAULT_OPTIONS)
    for key, value in changes:
        controls.update(scene)
        scene, options = controls.by_key[key].apply(scene, value, options)
    controls.update(scene)
    return scene, options, controls


def _open(entry, query):
    """What a fresh tab shows for ``query`` on ``entry``: scene, options, problems."""
    pairs, problems = address.read_query(query)
    scene, options, refused = address.apply_settings(pairs, entry.scene, dict(address.DEFAULT_OPTIONS),
                                                     _controls(entry))
    return scene, options, problems + refused


@pytest.mark.parametrize("entry", [e for e in REAL if e.ok], ids=lambda e: e.path.stem)
def test_a_lesson_as_it_opens_has_only_its_name_in_the_address(entry):
    query = address.ViewAddress().query(entry, entry.scene, dict(address.DEFAULT_OPTIONS), _controls(entry))
    assert query == address.query_for(entry), query


CHANGES = [
    ("material__ks__level", 0.8), ("interpolation", "gouraud"), ("lights_1__azimuth", 40.0),
    ("lights_1__type", "spot"), ("lights_1__color", "#ffe0c0"), ("lights_1__exponent", 12.5),
    ("camera__azimuth", 31.7), ("camera__distance", 7.25), ("exposure", 1.5), ("display", "linear"),
    ("view__term", "specular"), ("view__mistake", True), ("material__shininess__log", 2.0),
]



#: settings a tab's address goes through, each step changing one thing: a file-form field's text (the
#: widget settings before it are kept), a widget's text, a value the widget refuses and then takes, an
#: unknown key's text, a light's type
REOPENED = [
    [("interpolation", "gouraud"), ("material.shininess", "89.125094")],
    [("interpolation", "gouraud"), ("material.shininess", "12.5")],
    [("interpolation", "flat"), ("material.shininess", "12.5")],
    [("interpolation", "flat"), ("lights[1].intensity", "5")],
    [("interpolation", "flat"), ("lights[1].intensity", "0.5")],
    [("nonsense.key", "1"), ("material.shininess", "20")],
    [("nonsense.key", "2"), ("material.shininess", "20")],
    [("material.shininess", "40"), ("lights[1].type", "spot"), ("lights[1].exponent", "12.5")],
    [("material.shininess", "41"), ("lights[1].type", "spot"), ("lights[1].exponent", "12.5")],
    [("material.shininess", "41"), ("lights[1].type", "point"), ("lights[1].exponent", "12.5")],
]


def test_a_tab_reopens_each_address_as_a_fresh_tab_does_though_it_keeps_what_the_last_one_shared():
    kept = address.ViewAddress()
    controls = _controls(SPECULAR)
    for settings in REOPENED:
        scene, options, problems = kept.reopen(SPECULAR, settings, controls)
        fresh = address.apply_settings(settings, SPECULAR.scene, dict(address.DEFAULT_OPTIONS), _controls(SPECULAR))
        assert (scene_to_dict(scene), options, problems) == (scene_to_dict(fresh[0]), fresh[1], fresh[2]), settings

def test_the_address_carries_every_changed_setting_and_reopens_the_same_view():
    scene, options, controls = _change(SPECULAR, CHANGES)
    query = address.ViewAddress().query(SPECULAR, scene, options, controls)
    # readable: field paths and short values
    for part in ("lesson=04-specular", "material.ks=0.8", "interpolation=gouraud", "lights[1].type=spot",
                 "lights[1].color=ffe0c0", "camera.azimuth=31.7", "camera.distance=7.25", "view.term=specular",
                 "view.mistake=true", "material.shininess=100", "display=linear", "exposure=1.5"):
        assert part in query.split("?")[1].split("&"), (part, query)
    reopened, reopened_options, problems = _open(SPECULAR, query)
    assert problems == [], (query, problems)
    assert reopened_options == options, (query, reopened_options, options)
    # the same scene, to the address's rounding
    controls = _controls(SPECULAR)
    controls.update(reopened)  # the tab's controls follow its scene (a spot light now)
    again = address.ViewAddress().query(SPECULAR, reopened, reopened_options, controls)
    assert again == query
    a, b = scene_to_dict(scene), scene_to_dict(reopened)
    for name in ("material", "model", "interpolation", "display", "exposure"):
        assert a[name] == b[name], (name, a[name], b[name])
    assert a["lights"][1]["position"] == pytest.approx(b["lights"][1]["position"], abs=1e-4), query
    assert a["camera"]["eye"] == pytest.approx(b["camera"]["eye"], abs=1e-3), query


def test_back_to_the_lesson_values_drops_them_from_the_address():
    scene, options, controls = _change(SPECULAR, [("material__ks__level", 0.8), ("material__ks__level", 0.6),
                                                  ("view__term", "diffuse"), ("view__term", "color")])
    assert address.ViewAddress().query(SPECULAR, scene, options, controls) == "?lesson=04-specular"


def test_a_retyped_light_is_written_as_its_type_and_what_changed_after():
    scene, options, controls = _change(SPECULAR, [("lights_1__type", "spot")])
    query = address.ViewAddress().query(SPECULAR, scene, options, controls)
    assert query == "?lesson=04-specular&lights[1].type=spot", query
    scene, options, controls = _change(SPECULAR, [("lights_1__type", "spot"), ("lights_1__cutoff", 40.0),
                                                  ("lights_1__azimuth", 10.0)])
    view = address.ViewAddress()
    query = view.query(SPECULAR, scene, options, controls)
    assert "lights[1].type=spot" in query and "lights[1].cutoff=40" in query, query
    assert "no_cone" not in query and "exponent" not in query, query
    reopened, reopened_options, problems = _open(SPECULAR, query)
    assert not problems, (query, problems)
    a, b = scene_to_dict(scene)["lights"][1], scene_to_dict(reopened)["lights"][1]
    assert a.keys() == b.keys(), (a, b)
    for name in a:
        assert a[name] == (pytest.approx(b[name], abs=1e-4) if name in ("position", "direction") else b[name]), (name, a, b)
    # the same address object, back to the lesson's light: the type goes away again
    controls.update(SPECULAR.scene)
    assert view.query(SPECULAR, SPECULAR.scene, dict(address.DEFAULT_OPTIONS), controls) == "?lesson=04-specular"


@pytest.mark.parametrize("x, decimals, text", [
    (0.8, 3, "0.8"), (0.8000000000000002, 3, "0.8"), (30.0, 4, "30"), (-0.00001, 4, "0"), (31.66, 1, "31.7"),
    (2.31760368, 4, "2.3176"), (-12.0, 1, "-12"),
])
def test_numbers_are_written_compactly(x, decimals, text):
    assert address.compact_number(x, decimals) == text, (x, decimals)


def _sliders(entry):
    return [c for c in _controls(entry).widgets if c.kind == "slider"]


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_any_slider_position_comes_back_from_the_address(data):
    control = data.draw(st.sampled_from(_sliders(SPECULAR)), label="slider")
    steps = int(round((control.high - control.low) / control.step))
    value = control.low + control.step * data.draw(st.integers(0, steps), label="steps")
    try:
        scene, options, controls = _change(SPECULAR, [(control.key, value)])
    except ControlError:  # a value the page refuses too (attenuation all zero)
        assume(False)
    query = address.ViewAddress().query(SPECULAR, scene, options, controls)
    reopened, reopened_options, problems = _open(SPECULAR, query)
    assert not problems, (control.path, value, query, problems)
    back = _controls(SPECULAR).by_key[control.key].read(reopened, reopened_options)
    shown = control.read(scene, options)
    if control.path.endswith("azimuth"):  # -180° and 180° are the same place
        back = shown + ((back - shown + 180.0) % 360.0 - 180.0)
    assert control.same(back, shown), (control.path, value, shown, back, query)


@pytest.mark.parametrize("setting, words", [
    ("material.ks=-1", ["specular k_s (material.ks) = -1,", "out of range", "a number of 0 or more"]),
    ("material.ks=abc", ["specular k_s (material.ks) = abc,", "not a number", "a number of 0 or more"]),
    ("interpolation=banana", ["interpolation = banana,", "not one of its choices", "flat, gouraud or pixel"]),
    ("camera.azimuth=400", ["eye azimuth (camera.azimuth) = 400,", "out of range", "from -180 to 180 degrees"]),
    ("camera.azimuth=nan", ["eye azimuth (camera.azimuth) = nan,", "not a number", "from -180 to 180 degrees"]),
    ("lights[1].color=zzz", ["light 1 colour (lights[1].color) = zzz,", "not a colour", "six hex digits"]),
    ("view.mistake=maybe", ["show the mistake (view.mistake) = maybe,", "neither true nor false"]),
    ("material.kd=1,2,3,4,5", ["diffuse k_d (material.kd) = 1,2,3,4,5,", "has 5 numbers", "three of them"]),
    ("probe=1,2", ["probe point (probe) = 1,2,", "has 2 numbers", "three numbers separated by commas"]),
    ("lights[7].intensity=1", ["lights[7].intensity = 1,", "no setting called that"]),
    ("colour=red", ["colour = red,", "no setting called that"]),
    ("lesson.x=1", ["lesson.x = 1,", "no setting called that"]),
    ("material.ks=" + "1" * 300, ["material.ks", "300 characters", "at most 200"]),
], ids=lambda x: x[:30] if isinstance(x, str) else "")
def test_a_bad_setting_is_dropped_with_a_notice_and_the_rest_applies(setting, words):
    query = f"?lesson=04-specular&interpolation=gouraud&{setting}&material.shininess=10"
    scene, options, problems = _open(SPECULAR, query)
    assert len(problems) == 1, (query, problems)
    for word in words:
        assert word in problems[0], (query, word, problems)
    assert scene.interpolation == "gouraud" and scene.material.shininess == 10, (query, problems)
    assert "material.ks" not in setting or scene.material.ks == SPECULAR.scene.material.ks
    assert options == address.DEFAULT_OPTIONS or "view" not in setting


def test_the_address_is_bounded():
    many = "?lesson=04-specular&" + "&".join(["exposure=1.5"] * (address.MAX_SETTINGS + 10))
    scene, _, problems = _open(SPECULAR, many)
    assert scene.exposure == 1.5 and any(f"more than {address.MAX_SETTINGS} settings; only the first "
                                         f"{address.MAX_SETTINGS}" in p for p in problems), problems
    pairs, problems = address.read_query("?" + "x" * (address.MAX_QUERY_CHARS + 1))
    assert pairs == [] and f"at most {address.MAX_QUERY_CHARS} characters" in problems[0], problems
    pairs, problems = address.read_query("?" + "k" * 100 + "=1")
    assert pairs == [] and "longer than the name of any setting" in problems[0], problems
    assert address.read_query(None) == ([], []) and address.read_query(42)[0] == []


def test_the_keys_of_trames_own_page_are_no_settings():
    # a notebook's iframe opens the page at ?ui=main&reconnect=auto: no notice about settings it does not have
    query = "?ui=main&reconnect=auto&exposure=1.5"
    scene, _, problems = _open(SPECULAR, query)
    assert problems == [] and scene.exposure == 1.5, (query, problems)


def test_the_notice_is_one_line():
    _, _, problems = _open(SPECULAR, "?interpolation=banana&colour=red")
    text = address.notice(problems)
    assert "\n" not in text and "banana" in text and "colour" in text, text
    assert text.endswith("The lesson opened without them; the rest of the address applies."), text


#: bad addresses of every kind: (query after the lesson, the address key, the value as typed, the allowed words)
PLAIN_CASES = [
    ("material.ks=abc", "material.ks", "abc", "a number of 0 or more"),
    ("material.ks=-1", "material.ks", "-1", "a number of 0 or more"),
    ("material.shininess=-5", "material.shininess", "-5", "a number of 0 or more"),
    ("material.kd=1,2", "material.kd", "1,2", "three of them (red, green, blue)"),
    ("exposure=-1", "exposure", "-1", "a number above 0"),
    ("material.ks.level=1.5", "material.ks.level", "1.5", "from 0 to 1"),
    ("material.shininess.log=7", "material.shininess.log", "7", "from 0 to 3"),
    ("lights[1].intensity=x", "lights[1].intensity", "x", "a number of 0 or more"),
    ("lights[1].attenuation=0,0,0", "lights[1].attenuation", "0,0,0", "above 0 at every distance"),
    ("lights[1].position=1,2,abc", "lights[1].position", "1,2,abc", "three numbers separated by commas"),
    ("model=phongg", "model", "phongg", "phong, blinn-phong or cook-torrance"),
    ("two_sided=yes", "two_sided", "yes", "true or false"),
    ("display=x", "display", "x", "srgb or linear"),
    ("geometry.resolution=2000", "geometry.resolution", "2000", "a whole number from 3 to 1024"),
    ("colour=red", "colour", "red", "no setting called that"),
]


@pytest.mark.parametrize("setting, key, value, allowed", PLAIN_CASES, ids=[c[0][:30] for c in PLAIN_CASES])
def test_a_notice_is_a_plain_sentence_naming_key_value_and_what_is_allowed(setting, key, value, allowed):
    _, _, problems = _open(SPECULAR, f"?lesson=04-specular&{setting}")
    assert len(problems) == 1, (setting, problems)
    text = address.notice(problems)
    assert f"{key} = {value}," in text or f"({key}) = {value}," in text, (setting, text)
    assert allowed in text, (setting, allowed, text)
    # no Python repr quotes or brackets, no comparison signs, no "must be"/"got" of the code's messages
    for code in ("'", '"', ">=", "<=", " > ", " < ", "got ", "must be", "[1.0", "None"):
        assert code not in text, (setting, code, text)
    assert "\n" not in text and text.startswith("The address asks for ") and text.count(". ") == 1, text
    assert len(text) <= 300, (len(text), text)  # a notice is cut past 300 characters (owned.NOTICE_CHARS)


def test_every_problem_of_an_address_reads_as_a_sentence():
    problems = address.read_query("?" + "k" * 100 + "=1")[1] + address.read_query("?x=" + "1" * 300)[1]
    problems += address.read_query("?" + "&".join(["exposure=1"] * (address.MAX_SETTINGS + 5)))[1]
    problems += [address.lesson_index("?lesson=nope", ENTRIES)[1], address.lesson_index(42, ENTRIES)[1]]
    assert len(problems) == 5, problems
    for text in problems:
        assert text.startswith("The address ") and text.endswith(".") and "'" not in text, problems


@pytest.fixture
def make_app(tmp_path):
    """LessonApp tabs on the test lessons (no browser), closed at the end."""
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp
    from phonglab.bench.scenes import write_lessons

    (tmp_path / "lessons").mkdir()
    folder = write_lessons(tmp_path / "lessons", ["01-sphere.md", "02-spot.md"])
    apps = []

    def make():
        server = get_server(f"address-{tmp_path.name}-{len(apps)}", client_type="vue3")
        apps.append(LessonApp(server, target=folder))
        return apps[-1]

    yield make
    for app in apps:
        app.close()


def test_a_tab_writes_its_settings_and_another_tab_opens_them(make_app):
    app = make_app()
    assert app.state[address.QUERY_KEY] == "?lesson=01-sphere"
    app._on_control("material__ks__level", 0.8)
    app._on_control("interpolation", "flat")
    app._on_control("view__term", "specular")
    query = app.state[address.QUERY_KEY]
    assert sorted(query[1:].split("&")) == ["interpolation=flat", "lesson=01-sphere", "material.ks=0.8",
                                            "view.term=specular"], query
    # the query as the next page sends it
    other = make_app()
    other.state[address.REQUEST_KEY] = query
    other._on_address()
    assert other.scene == app.scene and other.options == app.options, query
    assert other.state[address.QUERY_KEY] == query and other.state.notice is None, other.state.notice
    assert other.state.readout == app.state.readout
    # a bad value: one notice, the lesson opens (lesson 2 here) and the rest applies
    other.state[address.REQUEST_KEY] = "?lesson=02-spot&lights[1].exponent=-3&lights[1].cutoff=40"
    other._on_address()
    assert other.entry.path.stem == "02-spot" and other.scene.lights[1].cutoff == 40
    text = other.state.notice["text"]
    assert "(lights[1].exponent) = -3," in text and "a number of 0 or more" in text, text
    assert other.state[address.QUERY_KEY] == "?lesson=02-spot&lights[1].cutoff=40"


def test_an_eye_slider_after_a_turn_ends_the_turned_view_in_the_address(make_app):
    # a turn shows the browser's camera as it is (view.turned); the eye's slider then sets a camera of its own,
    # framed as the lesson frames it, so the address must no longer say the view is turned
    from app_support import browser_camera

    app = make_app()
    app._apply_camera(browser_camera(app.scene, 25), final=True)
    app._refresh_panels()
    turned = app.state[address.QUERY_KEY]
    assert "view.turned=true" in turned, turned
    app._on_control("camera__azimuth", 10.0)
    app._refresh_panels()
    query = app.state[address.QUERY_KEY]
    assert "view.turned" not in query and "camera.azimuth=10" in query, (turned, query, app.options)
    other = make_app()
    other.state[address.REQUEST_KEY] = query
    other._on_address()
    assert other.scene.camera == app.scene.camera and other.options == app.options, (query, other.options)


def test_the_address_written_stays_within_the_bounds_it_is_read_with(monkeypatch):
    scene, options, controls = _change(SPECULAR, CHANGES)
    monkeypatch.setattr(address, "MAX_QUERY_CHARS", 80)
    query = address.ViewAddress().query(SPECULAR, scene, options, controls)
    assert len(query) <= 80 and query.startswith("?lesson=04-specular&lights[1].type=spot"), query
    assert address.read_query(query)[1] == [], query


def test_a_view_zoomed_past_the_eye_sliders_end_writes_an_address_that_reads_back():
    # the wheel can take the eye closer than the eye-distance slider goes (0.68 against 1.5): the address then
    # carries the eye itself, and reopening it refuses nothing and gives that eye
    from phonglab.app.eye import scene_camera

    c = SPECULAR.scene.camera
    direction = [e - f for e, f in zip(c.eye, c.focal_point)]
    length = sum(d * d for d in direction) ** 0.5
    near = [f + d * 0.68 / length for f, d in zip(c.focal_point, direction)]
    scene = scene_camera(SPECULAR.scene, {"position": near, "focalPoint": list(c.focal_point), "viewUp": list(c.up)})
    controls = _controls(SPECULAR)
    controls.update(scene)
    assert controls.by_key["camera__distance"].read(scene, dict(address.DEFAULT_OPTIONS)) == pytest.approx(0.68)
    query = address.ViewAddress().query(SPECULAR, scene, dict(address.DEFAULT_OPTIONS), controls)
    parts = query.split("?")[1].split("&")
    assert not any(p.startswith("camera.distance=") for p in parts), query
    reopened, _, problems = _open(SPECULAR, query)
    assert problems == [] and reopened.camera == scene.camera, (query, problems, reopened.camera, scene.camera)


@pytest.mark.parametrize("setting, field", [
    ("lights[1].intensity=5", "lights[1].intensity"),      # past the intensity slider (0..2)
    ("lights[1].color=0.35,0.5,1", "lights[1].color"),     # no sRGB hex code gives these
    ("exposure=9", "exposure"),                             # past the exposure slider (0.1..4)
    ("camera.up=0.1,1,0.05", "camera.up"),                  # a roll: no widget says it
])
def test_the_address_takes_what_a_lesson_file_takes_past_a_widget(setting, field):
    scene, _, problems = _open(SPECULAR, f"?lesson=04-specular&{setting}")
    assert problems == [], (setting, problems)
    got = scene_to_dict(scene)
    for part in field.replace("]", "").replace("[", ".").split("."):
        got = got[int(part)] if part.isdigit() else got[part]
    expected = [float(x) for x in setting.split("=")[1].split(",")]
    assert got == pytest.approx(expected if len(expected) > 1 else expected[0]), (setting, got)


def test_an_experiment_past_the_sliders_is_written_exactly():
    # lesson 7's inverse-square experiment sets intensity 5, past the slider: the address says 5, not the slider's 2
    entry = next(e for e in REAL if e.path.stem == "07-light-sources")
    experiment = next(x for x in entry.lesson.experiments if "Inverse-square" in x.label)
    scene = entry.scene.replace_many(experiment.settings)
    controls = _controls(entry)
    controls.update(scene)
    query = address.ViewAddress().query(entry, scene, dict(address.DEFAULT_OPTIONS), controls)
    assert "lights[1].intensity=5" in query.split("?")[1].split("&"), query
    reopened, _, problems = _open(entry, query)
    assert problems == [] and address.differing_fields(scene, reopened) == [], (query, problems)
