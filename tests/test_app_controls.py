"""The page's controls: browser values checked, scene fields written, places in a frame."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import phonglab as pl
from phonglab.app import controls as ctl
from phonglab.app.address import DEFAULT_OPTIONS
from phonglab.app.control import ControlError, format_value
from phonglab.bench.scenes import red_sphere
from phonglab.scene import Camera

LESSONS = Path(__file__).resolve().parent.parent / "lessons"


def make_scene(**overrides):
    """The red sphere with a spotlight straight above it as a third light."""
    spot = pl.SpotLight(position=(0.0, 3.0, 0.0), direction=(0.0, -3.0, 0.0), cutoff=20.0, exponent=2.0)
    return red_sphere(16, lights=(spot,), **overrides)


@pytest.fixture(scope="module")
def scene():
    return make_scene()


@pytest.fixture(scope="module")
def by_path(scene):
    return {c.path: c for c in ctl.controls_by_key(scene).values()}


# ---------------------------------------------------------------------------
# refusing browser values


@pytest.mark.parametrize(
    "path, value, says",
    [
        ("material.ks.level", float("nan"), "finite"),
        ("material.ks.level", float("inf"), "finite"),
        ("material.ks.level", "0.5", "must be a number"),
        ("material.ks.level", True, "must be a number"),
        ("material.ks.level", None, "must be a number"),
        ("material.ks.level", 1.5, "between 0 and 1"),
        ("material.ks.level", -0.01, "between 0 and 1"),
        ("material.shininess.log", 3.5, "between 0 and 3"),
        ("material.kd.color", "red", "#rrggbb"),
        ("material.kd.color", "#12345", "#rrggbb"),
        ("two_sided", 1, "true or false"),
        ("model", "lambert", "one of phong, blinn-phong"),
        ("view.term", 3, "one of color"),
        ("material.kd", {"r": 1}, "must be a number"),
        ("material.kd", [1, "x", 2], "material.kd"),
        ("material.kd", -3, "material.kd"),
        ("lights[1].attenuation[0]", 0.0, "a + b·d + c·d²"),
        ("lights[2].cutoff", 95.0, "between 1 and 90"),
        ("lights[1].distance", float("nan"), "finite"),
    ],
)
def test_bad_values_raise_control_errors_naming_path_and_value(scene, by_path, path, value, says):
    control = by_path[path]
    with pytest.raises(ctl.ControlError) as info:
        control.apply(scene, value, {"term": "color"})
    message = str(info.value)
    assert message.startswith(path + ":"), f"{path} = {value!r}: {message}"
    assert says in message, f"{path} = {value!r}: {message}"


def test_a_refused_value_leaves_the_scene_unchanged(scene, by_path):
    before = ctl.scene_to_dict(scene)
    with pytest.raises(ctl.ControlError):
        by_path["material.ks.level"].apply(scene, float("nan"), {})
    assert ctl.scene_to_dict(scene) == before


# ---------------------------------------------------------------------------
# writing good values


def test_shininess_slider_is_log10_alpha_over_1_to_1000(scene, by_path):
    control = by_path["material.shininess.log"]
    assert (control.low, control.high) == (0.0, 3.0)
    assert control.read(scene, {}) == pytest.approx(math.log10(40.0))
    for log_alpha, alpha in ((0.0, 1.0), (1.5, 10**1.5), (3.0, 1000.0)):
        new, _ = control.apply(scene, log_alpha, {})
        assert new.material.shininess == pytest.approx(alpha, rel=1e-5), log_alpha
    assert format_value(control, 2.0) == "100"


@pytest.mark.parametrize("log_alpha", [math.log10(30.0), 1.66, 0.5, 2.37, 0.0, 3.0])
def test_the_shininess_slider_shows_the_alpha_the_readout_writes(scene, by_path, log_alpha):
    """The number beside the slider is the exponent of the readout's max(0, c)^α (46 beside ^45.71 was not)."""
    from phonglab.app.equation import exponent

    control = by_path["material.shininess.log"]
    new, _ = control.apply(scene, log_alpha, {})
    shown, written = format_value(control, log_alpha), exponent(new.material.shininess)
    assert shown == written, (log_alpha, new.material.shininess, shown, written)


def test_level_and_colour_split_an_rgb_coefficient(scene, by_path):
    level, colour = by_path["material.kd.level"], by_path["material.kd.color"]
    assert level.read(scene, {}) == pytest.approx(0.8)
    assert colour.read(scene, {}) == ctl.rgb_to_hex((1.0, 0.375, 0.25))
    half, _ = level.apply(scene, 0.4, {})
    assert half.material.kd == pytest.approx((0.4, 0.15, 0.1))
    green, _ = colour.apply(scene, "#00ff00", {})
    assert green.material.kd == pytest.approx((0.0, 0.8, 0.0)), "the hue changes, the level stays"
    # at level 0 the picked hue is remembered for when the level comes back
    dark, options = level.apply(scene, 0.0, {})
    dark, options = colour.apply(dark, "#0000ff", options)
    back, _ = level.apply(dark, 0.5, options)
    assert back.material.kd == pytest.approx((0.0, 0.0, 0.5))


def test_term_view_is_a_view_option_not_a_scene_field(scene, by_path):
    new, options = by_path["view.term"].apply(scene, "specular", {"term": "color"})
    assert new is scene and options == {"term": "specular"}


frames = st.sampled_from([(0, 1, 0), (0, 0, 1), (1, 0, 0), (0.3, 1.0, -0.2)])
eyes = st.sampled_from([(0, 0, 4), (0, -4.3, 3.9), (3, 1, 2)])


@given(up=frames, eye=eyes, az=st.floats(-179, 179), el=st.floats(-85, 85), dist=st.floats(0.5, 12))
def test_place_and_offset_are_inverse_in_any_frame(up, eye, az, el, dist):
    try:
        camera = Camera(eye=eye, up=up)
    except ValueError:  # up parallel to the view: not a camera
        return
    frame = ctl.Frame.of_camera(camera)
    for a, b in ((frame.up, frame.front), (frame.up, frame.right), (frame.front, frame.right)):
        assert abs(np.dot(a, b)) < 1e-9, frame
    offset = ctl.place_offset(az, el, dist, frame)
    assert np.linalg.norm(offset) == pytest.approx(dist)
    got = ctl.place_of(offset, frame)
    assert got == pytest.approx((az, el, dist), abs=1e-6), (up, eye, az, el, dist, got)


def test_azimuth_zero_faces_the_lesson_eye():
    frame = ctl.Frame.of_camera(Camera(eye=(0, -4.3, 3.9), up=(0, 0, 1)))
    offset = ctl.place_offset(0.0, 0.0, 1.0, frame)
    assert offset == pytest.approx((0.0, -1.0, 0.0), abs=1e-12), offset
    assert ctl.place_offset(0.0, 90.0, 1.0, frame) == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)


def test_moving_a_light_changes_only_the_moved_coordinate(scene, by_path):
    focal = scene.camera.focal_point
    frame = ctl.Frame.of_camera(scene.camera)
    az0, el0, d0 = ctl.light_place(scene.lights[1], focal, frame)
    moved, _ = by_path["lights[1].azimuth"].apply(scene, 100.0, {})
    az, el, d = ctl.light_place(moved.lights[1], focal, frame)
    assert (az, el, d) == pytest.approx((100.0, el0, d0)), (az0, el0, d0)
    assert isinstance(moved.lights[1], pl.PointLight)


def test_a_spot_aimed_at_the_focal_point_stays_aimed_when_moved(scene, by_path):
    moved, _ = by_path["lights[2].elevation"].apply(scene, 40.0, {})
    spot = moved.lights[2]
    to_focal = -np.asarray(spot.position) / np.linalg.norm(spot.position)
    axis = np.asarray(spot.direction) / np.linalg.norm(spot.direction)
    assert to_focal @ axis == pytest.approx(1.0), (spot.position, spot.direction)


@pytest.mark.parametrize("kind, cls", [("directional", pl.DirectionalLight), ("spot", pl.SpotLight),
                                       ("point", pl.PointLight)])
def test_changing_a_light_type_keeps_its_direction_from_the_focal_point(scene, by_path, kind, cls):
    new, _ = by_path["lights[1].type"].apply(scene, kind, {})
    light = new.lights[1]
    assert type(light) is cls, light
    frame = ctl.Frame.of_camera(scene.camera)
    before = ctl.light_place(scene.lights[1], scene.camera.focal_point, frame)
    after = ctl.light_place(light, scene.camera.focal_point, frame)
    assert after[:2] == pytest.approx(before[:2]), (before, after)
    assert new.lights[0] == scene.lights[0] and new.lights[2] == scene.lights[2]


def test_eye_controls_move_the_camera_around_the_focal_point(scene, by_path):
    new, _ = by_path["camera.azimuth"].apply(scene, 90.0, {})
    assert new.camera.eye == pytest.approx((4.0, 0.0, 0.0), abs=1e-9)
    assert new.camera.focal_point == scene.camera.focal_point


def test_the_no_cone_switch_makes_a_point_light_and_gives_the_cone_back(scene, by_path):
    off, options = by_path["lights[2].no_cone"].apply(scene, True, {})
    assert off.lights[2].cutoff == 180.0
    assert by_path["lights[2].cutoff"].read(off, options) == 90.0, "the slider stays in its range"
    back, _ = by_path["lights[2].no_cone"].apply(off, False, options)
    assert back.lights[2].cutoff == 20.0


def test_resolution_slider_writes_a_whole_number(scene, by_path):
    new, _ = by_path["geometry.resolution"].apply(scene, 31.6, {})
    assert new.geometry.resolution == 32


def test_field_mirrors_read_and_write_the_file_form(scene, by_path):
    assert by_path["material.ks"].read(scene, {}) == [0.6, 0.6, 0.6]
    assert by_path["lights[1].position"].read(scene, {}) == [2.0, 2.5, 3.0]
    new, _ = by_path["lights[1].position"].apply(scene, [1, 1, 1], {})
    assert new.lights[1].position == (1.0, 1.0, 1.0)


# ---------------------------------------------------------------------------
# which widgets a lesson gets


def test_lesson_control_paths_expand_to_their_widgets(scene):
    chosen = ctl.lesson_controls(
        ctl.scene_controls(scene),
        ["material.kd", "material.shininess", "lights[1].position", "lights[1].attenuation", "camera.eye",
         "no.such.field", "material.kd"],
    )
    assert [c.path for c in chosen] == [
        "material.kd.level", "material.kd.color", "material.shininess.log",
        "lights[1].azimuth", "lights[1].elevation", "lights[1].distance",
        "lights[1].attenuation[0]", "lights[1].attenuation[1]", "lights[1].attenuation[2]",
        "camera.azimuth", "camera.elevation", "camera.distance",
    ]


def test_every_control_reads_a_value_its_own_check_accepts(scene):
    for control in ctl.scene_controls(scene):
        value = control.read(scene, {"term": "color"})
        if control.kind == "slider":
            value = min(max(value, control.low), control.high)
        assert control.check(value) is not None or control.kind == "switch", (control.path, value)


# ---------------------------------------------------------------------------
# one tab's control set


def test_a_control_set_is_rebuilt_only_when_the_light_types_change(scene):
    controls = ctl.ControlSet(ctl.Frame.of_camera(scene.camera), ["material.ks"])
    assert controls.update(scene), "the first scene builds the set"
    widgets = controls.widgets
    assert [c.path for c in controls.chosen] == ["material.ks.level", "material.ks.color"]
    brighter = scene.replace("material.ks", [0.9, 0.9, 0.9]).replace("lights[1].position", [1, 2, 3])
    assert not controls.update(brighter), "a new value rebuilt the set"
    assert controls.widgets is widgets
    values = controls.values(brighter, {"term": "color"})
    assert values["material__ks"] == [0.9, 0.9, 0.9] and values["lights_1__position"] == [1.0, 2.0, 3.0], values
    directional = brighter.replace("lights[1].type", "directional")
    assert controls.update(directional), "a light of another type kept the old set"
    assert "lights_1__direction" in controls.by_key and "lights_1__distance" not in controls.by_key


def test_a_control_sets_field_reads_equal_the_scene_layers_and_are_its_own(scene):
    from phonglab.scene import field_value

    first, second = (ctl.ControlSet(ctl.Frame.of_camera(scene.camera)) for _ in range(2))
    other = scene.replace("material.kd", [0.1, 0.2, 0.3])
    for path in ("material.kd", "lights[1].position", "lights[2].cutoff", "camera.eye", "probe", "model"):
        assert first.read_field(scene, path) == field_value(scene, path), path
        assert second.read_field(other, path) == field_value(other, path), path
        assert first.read_field(scene, path) == field_value(scene, path), f"{path}: the other set's scene leaked in"
    # a value handed out is a copy: changing it changes nothing for the next reader
    first.read_field(scene, "material.kd").append(9)
    assert first.read_field(scene, "material.kd") == [0.8, 0.3, 0.2]


def _edits(controls):
    """A value for every widget: a slider's middle and a quarter, each select's items, each switch flipped."""
    for control in controls.widgets:
        if control.kind == "slider":
            for share in (0.5, 0.25):
                yield control, control.low + share * (control.high - control.low)
        elif control.kind == "select":
            for value, _ in control.items:
                yield control, value
        elif control.kind == "switch":
            yield control, "flip"
        elif control.kind == "color":
            yield control, "#3366cc"


@pytest.mark.parametrize("lesson", sorted(p.name for p in LESSONS.glob("[0-9]*.md")))
def test_a_control_sets_values_after_each_edit_are_what_reading_every_control_gives(lesson):
    # the set reads again only the controls of the fields that changed: every other value must be the same
    from phonglab.scene import load_lesson

    entry = load_lesson(LESSONS / lesson)
    scene, options = entry.scene, {"term": "color"}
    controls = ctl.ControlSet(ctl.Frame.of_camera(scene.camera), entry.controls)
    controls.update(scene)
    steps = [(c, v) for c, v in _edits(controls)][:60]
    steps.append((None, ("camera.focal_point", [0.25, -0.25, 0.5])))  # no widget moves it; the lights' places do
    for control, value in steps:
        try:
            if control is None:
                scene = scene.replace(*value)
            else:
                value = not control.read(scene, options) if value == "flip" else value
                scene, options = control.apply(scene, value, options)
        except ctl.ControlError:
            continue
        controls.update(scene)
        got = controls.values(scene, options)
        fresh = {key: c.read(scene, options) for key, c in controls.by_key.items()}
        assert got == fresh, (lesson, control and control.path, value,
                              {k: (got[k], fresh[k]) for k in fresh if got.get(k) != fresh[k]})


def test_a_coefficient_an_experiment_sets_to_0_keeps_its_colour(scene, by_path):
    """Lesson 1's "Ambient only" sets k_d = 0: the swatch turned white and k_d raised again gave a white sphere."""
    level, colour = by_path["material.kd.level"], by_path["material.kd.color"]
    hue = ctl.split_level(scene.material.kd)[1]
    dark = scene.replace("material.kd", 0)
    options = ctl.keep_hues(scene, dark, {})
    assert colour.read(dark, options) == colour.read(scene, {}), options
    raised, _ = level.apply(dark, 0.5, options)
    assert raised.material.kd == pytest.approx([0.5 * c for c in hue]), raised.material.kd
    assert ctl.keep_hues(dark, dark, {}) == {}, "a coefficient already at 0 has no colour to keep"


#: a lesson's settings a slider does not reach on purpose, each said so in the lesson's own text:
#: (lesson, experiment label, control key)
BEYOND_A_SLIDER = {
    # "The same lamp a thousand radii away, like the sun, further than the distance slider reaches (12)"
    ("03-diffuse", "The sun, far away", "lights_1__distance"),
}


def _lesson_scenes():
    """Every lesson's opening scene and each experiment's, with the controls' frame the page uses (the lesson's)."""
    from phonglab.scene.lessons import catalog

    entries, _ = catalog(LESSONS)
    for entry in entries:
        assert entry.ok, entry
        frame = ctl.Frame.of_camera(entry.scene.camera)
        yield entry.path.stem, None, entry.scene, frame
        for experiment in entry.lesson.experiments:
            yield entry.path.stem, experiment.label, entry.scene.replace_many(experiment.settings), frame


def test_every_lesson_and_experiment_setting_sits_on_its_slider():
    """A student can always move a slider back to the value a lesson set: no setting lies beyond its slider's ends.

    Lesson 7's inverse-square experiment set attenuation c = 1 on a slider ending at 0.5 (one key press
    left jumped to 0.495), and lesson 13's gold set the exposure to 0.05 on a slider starting at 0.1.
    """
    outside = []
    for stem, label, scene, frame in _lesson_scenes():
        for control in ctl.scene_controls(scene, frame):
            if control.kind != "slider" or (stem, label, control.key) in BEYOND_A_SLIDER:
                continue
            value = control.read(scene, dict(DEFAULT_OPTIONS))
            try:
                control.check(value)  # the rule a browser's value meets: could a student's slider send it?
            except ControlError as exc:
                outside.append((stem, label or "the lesson's scene", control.key, str(exc)))
    assert not outside, f"settings beyond their slider's ends (lesson, experiment, control, refusal): {outside}"
