"""The readout under a common mistake and its colour swatches, without a browser.

With a mistake on, the numbers are the mistaken code's (the ones that made
the picture), each term that differs carries the correct value and the wrong
and right lines of code; the swatches are display-encoded like the picture.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.app.readout import probe_readout, swatch_hex
from phonglab.scene import load_lesson, scene_to_dict, shade
from phonglab.teaching import MISTAKES

LESSONS = Path(__file__).resolve().parent.parent / "lessons"
#: a point on lesson 9's sheet where the lamp is behind it and the ungated specular is bright
UNLIT = np.array([-0.1, 0.15, 0.0])
UP = np.array([0.0, 0.0, 1.0])


def terms(out) -> dict:
    return {t["name"]: t for t in out["terms"]}


def values(text: str) -> list[float]:
    return [float(x) for x in text.strip("()").split(",")]


@pytest.fixture(scope="module")
def sheet():
    return load_lesson(LESSONS / "09-two-sided-and-hard-cases.md").scene


def readout(scene, point, normal, mistake=None):
    v = pl.vectors(point, normal, eye=scene.camera.eye, light=scene.lights[1], two_sided=scene.two_sided)
    return probe_readout(scene, point, normal, 1, mistake=mistake), v


def test_ungated_specular_readout_shows_the_pictures_highlight(sheet):
    out, v = readout(sheet, UNLIT, UP, "ungated-specular")
    assert v.nl < 0, v
    t = terms(out)
    picture = shade(sheet, UNLIT[None], UP[None], mistake="ungated-specular")
    assert values(t["specular"]["value"]) == pytest.approx(picture.specular[0], abs=5e-4), t["specular"]
    assert min(values(t["specular"]["value"])) > 0.1, t["specular"]
    assert values(t["specular"]["correct"]) == [0.0, 0.0, 0.0], t["specular"]
    m = MISTAKES["ungated-specular"]
    assert (t["specular"]["wrong"], t["specular"]["right"]) == (m.wrong, m.right)
    assert "correct" not in t["ambient"] and "correct" not in t["diffuse"], out["terms"]
    assert out["mistake"]["title"] == m.title
    assert not any("so diffuse and specular are 0." in n for n in out["notes"]), out["notes"]
    # the equation's specular row ends with the mistaken value, not 0
    assert "0.597" in out["equation"].split("specular</span>")[1].split("eq-row")[0], out["equation"][-800:]


def test_readout_without_the_mistake_is_the_correct_one(sheet):
    out, _ = readout(sheet, UNLIT, UP)
    t = terms(out)
    assert values(t["specular"]["value"]) == [0.0, 0.0, 0.0]
    assert out["mistake"] is None and all("correct" not in x for x in out["terms"]), out["terms"]
    assert any("so diffuse and specular are 0." in n for n in out["notes"]), out["notes"]


@pytest.mark.parametrize("name, term", [("no-clamp-diffuse", "diffuse"), ("zero-shininess", "specular")])
def test_each_mistake_changes_its_own_term(sheet, name, term):
    # a lit point for zero-shininess (α = 0 makes the whole lit side pale), the unlit one for no-clamp
    scene = sheet.replace("lights[1].position", [-1.2, -0.6, 2.5]) if name == "zero-shininess" else sheet
    out, _ = readout(scene, UNLIT, UP, name)
    t = terms(out)
    mistaken = getattr(shade(scene, UNLIT[None], UP[None], mistake=name), term)[0]
    right = getattr(shade(scene, UNLIT[None], UP[None]), term)[0]
    assert values(t[term]["value"]) == pytest.approx(mistaken, abs=5e-4), (name, t[term])
    assert values(t[term]["correct"]) == pytest.approx(right, abs=5e-4), (name, t[term])
    assert t[term]["wrong"] == MISTAKES[name].wrong


def test_a_mistake_that_does_not_bite_here_changes_nothing(sheet):
    # unit normals at the probe: unnormalised normals give the correct numbers
    out, _ = readout(sheet, UNLIT, UP, "unnormalised-normals")
    assert all("correct" not in x for x in out["terms"]), out["terms"]
    assert "equal the correct ones" in out["notes"][0], out["notes"]


@pytest.mark.parametrize("display, expected", [("srgb", "#bcbcbc"), ("linear", "#808080")])
def test_swatches_are_encoded_like_the_picture(sheet, display, expected):
    scene = sheet.replace("display", display)
    assert swatch_hex(scene, [0.5, 0.5, 0.5]) == expected
    out, _ = readout(scene, UNLIT, UP)
    assert ("sRGB-encoded" in out["display_note"]) == (display == "srgb"), out["display_note"]
    assert "linear light" in out["display_note"]


def test_swatch_follows_exposure_and_clips(sheet):
    assert swatch_hex(sheet.replace("exposure", 0.5), [1.0, 2.0, 0.0]) == "#bcff00"


@pytest.mark.parametrize("display", ["srgb", "linear"])
def test_the_display_note_names_an_exposure_other_than_1(sheet, display):
    # lesson 13's Gold sets 0.05: the numbers stay unscaled while the swatches are drawn ×0.05
    scene = sheet.replace("display", display)
    plain, _ = readout(scene, UNLIT, UP)
    assert "exposure" not in plain["display_note"], plain["display_note"]
    for exposure, shown in ((0.05, "×0.05"), (2.5, "×2.5")):
        out, _ = readout(scene.replace("exposure", exposure), UNLIT, UP)
        note = out["display_note"]
        assert f"exposure {shown}" in note and "linear light" in note, (display, exposure, note)
        assert note.startswith(plain["display_note"][:-1]), (display, exposure, note, plain["display_note"])


@pytest.fixture
def sheet_app(tmp_path):
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    folder = tmp_path / "lessons"
    folder.mkdir()
    (folder / "09-sheet.md").write_text((LESSONS / "09-two-sided-and-hard-cases.md").read_text("utf-8"), "utf-8")
    server = get_server(f"test-truth-{tmp_path.name}", client_type="vue3")
    application = LessonApp(server, target=folder, export_dir=tmp_path / "exports")
    yield application
    application.close()


def test_app_readout_and_export_follow_the_mistake_switch(sheet_app):
    app = sheet_app
    app.view.set_probe(UNLIT)
    app._refresh_panels()
    assert app.state.readout["mistake"] is None
    assert values(terms(app.state.readout)["specular"]["value"]) == [0.0, 0.0, 0.0]
    app._on_control("view__mistake", True)
    app._refresh_panels()  # the app defers the panels to the server loop; no loop here
    out = app.state.readout
    assert out["mistake"]["name"] == "ungated-specular", out["mistake"]
    # the correct code gives exactly 0 here (n·l < 0); the mistaken one a highlight the picture shows
    assert min(values(terms(out)["specular"]["value"])) > 0.01, out["terms"]
    # the export is the mistaken picture, with the red band that says so
    app.export_figure()
    assert app.state.notice["kind"] == "success", app.state.notice
    from PIL import Image

    (path,) = app.export_dir.glob("*.png")
    with Image.open(path) as img:
        rgb = np.asarray(img.convert("RGB")).astype(int)
    # the band's red heading over the top of the figure
    top = rgb[: rgb.shape[0] // 10].reshape(-1, 3)
    red = np.count_nonzero((top[:, 0] > 140) & (top[:, 1] < 80) & (top[:, 2] < 80))
    assert red > 200, f"no red 'common mistake' heading at the top of {path.name}: {red} red pixels"


@pytest.mark.parametrize("interpolation, words", [
    ("flat", "one colour per face (flat)"),
    ("gouraud", "interpolates vertex colours (Gouraud)"),
    ("pixel", None),
])
def test_the_readout_says_its_numbers_are_exact_where_the_picture_interpolates(sheet, interpolation, words):
    scene = sheet.replace("interpolation", interpolation)
    out, _ = readout(scene, UNLIT, UP)
    said = [n for n in out["notes"] if "evaluated exactly at the probe" in n]
    if words is None:
        assert said == [], (interpolation, out["notes"])
    else:
        assert len(said) == 1 and words in said[0], (interpolation, out["notes"])
    # the same with no directed light (the ambient-only readout)
    ambient = scene.replace("lights", [scene_to_dict(scene)["lights"][0]])
    out = probe_readout(ambient, UNLIT, UP, None)
    assert (len([n for n in out["notes"] if "evaluated exactly" in n]) == 1) == (words is not None), out["notes"]


# --- two directed lights: whose numbers the readout shows, and how they add up to the total ---

ORIGIN = np.zeros(3)


@pytest.fixture(scope="module")
def two_lights():
    """Lesson 5: an ambient light and two point lights (lights[1] warm white, lights[2] blue)."""
    scene = load_lesson(LESSONS / "05-whole-model.md").scene
    assert [type(x).__name__ for x in scene.lights] == ["AmbientLight", "PointLight", "PointLight"], scene.lights
    return scene


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def halfway(scene, light_index):
    """The normal at the origin that puts light ``light_index``'s highlight there (n = h, so r·v = 1)."""
    return unit(unit(scene.lights[light_index].position) + unit(scene.camera.eye))


def core_terms(scene, normal, lights, mistake=None):
    """The core's shading at the origin with only ``lights`` (the mistaken code's with ``mistake``)."""
    return shade(scene.replace("lights", [scene_to_dict(scene)["lights"][i] for i in lights]),
                 ORIGIN[None], normal[None], mistake=mistake)


def parts(out) -> list[tuple[str, list[float]]]:
    return [(x["name"], values(x["value"])) for x in out["parts"]]


def eq_rows(out) -> list[tuple[str, str]]:
    """The equation's rows as (label, the row's numbers as text)."""
    import re

    rows = re.findall(r'<span class="eq-label">([^<]+)</span>(<math.*?</math>)', out["equation"])
    return [(label, " ".join(re.findall(r"<mn>([^<]+)</mn>", math))) for label, math in rows]


@pytest.fixture(scope="module")
def lit_by_both(two_lights):
    """Light 1's highlight at the origin, where light 2 lights the surface too (n·l > 0 for both)."""
    normal = halfway(two_lights, 1)
    v1 = pl.vectors(ORIGIN, normal, eye=two_lights.camera.eye, light=two_lights.lights[1])
    v2 = pl.vectors(ORIGIN, normal, eye=two_lights.camera.eye, light=two_lights.lights[2])
    assert v1.nl > 0.3 and v2.nl > 0.1 and v1.rv > 0.999, (normal, v1, v2)
    return two_lights, normal, v1


def test_two_lights_the_dots_carry_light_1s_own_terms_from_the_core(lit_by_both):
    scene, normal, v1 = lit_by_both
    out = probe_readout(scene, ORIGIN, normal, 1)
    assert out["light_name"] == "light 1", out["light_name"]
    dots = {d["name"]: d for d in out["dots"]}
    assert float(dots["n·l"]["value"]) == pytest.approx(v1.nl, abs=5e-4) and float(dots["r·v"]["value"]) == pytest.approx(v1.rv, abs=5e-4)
    assert "term" not in dots["n·h"], dots  # Phong: n·h makes no term
    diffuse, specular = values(dots["n·l"]["term"]["value"]), values(dots["r·v"]["term"]["value"])
    assert (dots["n·l"]["term"]["name"], dots["r·v"]["term"]["name"]) == ("diffuse", "specular"), dots
    # the core with light 1 alone (phonglab.shade) ...
    light = scene.lights[1]
    alone = pl.shade(ORIGIN[None], normal[None], material=scene.material, lights=(light,), eye=scene.camera.eye,
                     model=scene.model, two_sided=scene.two_sided)
    assert diffuse == pytest.approx(alone.diffuse[0], abs=5e-4), (dots["n·l"], alone.diffuse[0])
    assert specular == pytest.approx(alone.specular[0], abs=5e-4), (dots["r·v"], alone.specular[0])
    # ... which is the lesson's equation with light 1's own vectors
    f = v1.attenuation * v1.spot
    m = scene.material
    assert diffuse == pytest.approx(f * np.multiply(m.kd, light.diffuse_rgb) * max(0.0, v1.nl), abs=5e-4)
    assert specular == pytest.approx(f * np.multiply(m.ks, light.specular_rgb) * max(0.0, v1.rv) ** m.shininess,
                                     abs=5e-4)
    # and it is not the sum over both lights the terms beside it show: light 2 lights this point too
    t = terms(out)
    assert max(np.subtract(values(t["diffuse"]["value"]), diffuse)) > 0.05, (t["diffuse"], diffuse)


def test_two_lights_the_parts_add_up_to_the_total(lit_by_both):
    scene, normal, v1 = lit_by_both
    out = probe_readout(scene, ORIGIN, normal, 1)
    (first, with_1), (second, adds_2), (last, total) = parts(out)
    assert (first, second, last) == ("ambient + light 1", "light 2 adds", "total"), out["parts"]
    assert with_1 == pytest.approx(core_terms(scene, normal, [0, 1]).color[0], abs=5e-4)
    assert adds_2 == pytest.approx(core_terms(scene, normal, [0, 2]).color[0] - core_terms(scene, normal, [0]).color[0], abs=5e-4)
    assert total == values(terms(out)["total"]["value"]), (out["parts"], out["terms"])
    assert np.add(with_1, adds_2) == pytest.approx(total, abs=2e-3), out["parts"]
    # the worked equation is light 1's and ends with the same parts and the total
    rows = eq_rows(out)
    assert [label for label, _ in rows] == ["model", "ambient", "diffuse", "specular", "light 1", "light 2", "total"], rows
    assert "light 1" in out["equation"].split("<div class=\"eq-row\"")[0], out["equation"][:300]
    assert rows[-1][1].endswith(" ".join(f"{c:.3f}" for c in total)), rows[-1]
    assert rows[-3][1].endswith(" ".join(f"{c:.3f}" for c in with_1)), rows[-3]
    assert not any("other light" in n for n in out["notes"]), out["notes"]


def test_one_directed_light_keeps_the_plain_readout(sheet):
    out, _ = readout(sheet, UNLIT, UP)
    assert out["light_name"] is None and out["parts"] == [], out
    assert all("term" not in d for d in out["dots"]), out["dots"]
    assert [label for label, _ in eq_rows(out)] == ["model", "ambient", "diffuse", "specular", "sum"]


@pytest.mark.parametrize("mistake", sorted(MISTAKES))
@pytest.mark.parametrize("attenuated", [False, True])
def test_two_lights_with_a_mistake_the_parts_are_the_mistaken_codes_and_add_up(lit_by_both, mistake, attenuated):
    scene, normal, _ = lit_by_both
    if attenuated:  # a falloff on light 1, so that f differs from 1 (the attenuated-ambient mistake bites)
        scene = scene.replace("lights[1].attenuation", [1.0, 0.3, 0.0])
    out = probe_readout(scene, ORIGIN, normal, 1, mistake=mistake)
    got = parts(out)
    total = got[-1][1]
    picture = shade(scene, ORIGIN[None], normal[None], mistake=mistake).color[0]
    assert total == pytest.approx(picture, abs=5e-4), (mistake, out["parts"])
    assert np.sum([rgb for _, rgb in got[:-1]], axis=0) == pytest.approx(total, abs=2e-3), (mistake, out["parts"])
    # light 1's own terms beside its dots are the mistaken code's for light 1 (the ones its equation works out)
    own = core_terms(scene, normal, [0, 1], mistake)
    dots = {d["name"]: d for d in out["dots"]}
    assert values(dots["n·l"]["term"]["value"]) == pytest.approx(own.diffuse[0], abs=5e-4), (mistake, dots)
    assert values(dots["r·v"]["term"]["value"]) == pytest.approx(own.specular[0], abs=5e-4), (mistake, dots)
    assert got[0][1] == pytest.approx(own.color[0], abs=5e-4), (mistake, out["parts"])


def test_two_lights_light_1_behind_under_the_unclamped_diffuse(two_lights):
    # light 2 in front, light 1 behind: the note names light 1; the mistaken diffuse beside n·l is negative
    n = unit(unit(two_lights.lights[2].position) - 0.9 * unit(two_lights.lights[1].position))
    v1 = pl.vectors(ORIGIN, n, eye=two_lights.camera.eye, light=two_lights.lights[1])
    v2 = pl.vectors(ORIGIN, n, eye=two_lights.camera.eye, light=two_lights.lights[2])
    assert v1.nl < 0 < v2.nl, (n, v1, v2)
    out = probe_readout(two_lights, ORIGIN, n, 1, mistake="no-clamp-diffuse")
    dots = {d["name"]: d for d in out["dots"]}
    assert min(values(dots["n·l"]["term"]["value"])) < 0, dots["n·l"]
    assert any(x.startswith("n·l ≤ 0: light 1 is behind") and "mistaken code gives diffuse" in x for x in out["notes"]), out["notes"]
    assert "correct" in terms(out)["diffuse"], out["terms"]
    right = probe_readout(two_lights, ORIGIN, n, 1)
    assert "n·l ≤ 0: light 1 is behind the surface here, so its diffuse and specular are 0." in right["notes"], right["notes"]


def test_two_lights_blinn_phong_puts_light_1s_specular_beside_n_dot_h(lit_by_both):
    scene, normal, _ = lit_by_both
    scene = scene.replace("model", "blinn-phong")
    out = probe_readout(scene, ORIGIN, normal, 1)
    dots = {d["name"]: d for d in out["dots"]}
    assert "term" not in dots["r·v"] and dots["n·h"]["term"]["name"] == "specular", dots
    alone = pl.shade(ORIGIN[None], normal[None], material=scene.material, lights=(scene.lights[1],),
                     eye=scene.camera.eye, model="blinn-phong", two_sided=scene.two_sided)
    assert values(dots["n·h"]["term"]["value"]) == pytest.approx(alone.specular[0], abs=5e-4), (dots, alone.specular[0])
    assert max(alone.specular[0]) > 0.1, alone.specular[0]  # n = h: light 1's Blinn highlight


@pytest.mark.parametrize("lesson", sorted(p.name for p in LESSONS.glob("[0-9]*.md")))
def test_each_worked_rows_mathml_is_the_one_latex2mathml_writes(lesson, monkeypatch):
    # a row's numbers are put into the MathML of its formula: the markup must be the converter's own
    from phonglab.app import equation, text
    from phonglab.render.mesh import build_mesh

    rows = []
    own = equation.as_mathml

    def spy(tex):
        rows.append(tex)
        return own(tex)

    monkeypatch.setattr(equation, "as_mathml", spy)
    scene = load_lesson(LESSONS / lesson).scene
    mesh = build_mesh(scene.geometry)
    rng = np.random.default_rng(7)
    picks = rng.choice(mesh.n_points, size=2, replace=False)
    light = next((i for i, x in enumerate(scene.lights) if not isinstance(x, pl.AmbientLight)), None)
    for model in ("phong", "blinn-phong"):
        for mistake in (None, *MISTAKES):
            for shininess in (7.25, 999.5):
                edited = scene.replace("model", model).replace("material.shininess", shininess)
                for i in picks:
                    with np.errstate(all="ignore"):
                        probe_readout(edited, mesh.points[i], mesh.point_data["Normals"][i], light, mistake=mistake)
    assert rows, lesson
    wrong = [tex for tex in set(rows) if own(tex) != text.mathml(tex)]
    assert not wrong, (lesson, wrong[:3])


def test_cook_torrance_says_why_its_factors_are_0_where_the_eye_is_below_the_surface():
    """Lesson 13 turned: D and V read "= 0 = 0.000" with nothing to say why (a student-eye review)."""
    scene = load_lesson(LESSONS / "13-physically-based.md").scene
    assert scene.model == "cook-torrance", scene.model
    eye = np.asarray(scene.camera.eye, dtype=float)
    away = -eye / np.linalg.norm(eye)  # the far side of a sphere at the origin: its normal faces away from the eye
    below = probe_readout(scene, away, away, 1)
    facing = probe_readout(scene, -away, -away, 1)
    says = "the eye is below the surface"
    assert any(says in n for n in below["notes"]), below["notes"]
    assert not any(says in n for n in facing["notes"]), facing["notes"]


def test_the_factor_f_is_said_as_its_product(monkeypatch):
    # lesson 7's spot: "f = 0.239 = attenuation … (at distance …) × spot factor …", never "f = distance 2.04, …"
    import re

    scene = load_lesson(LESSONS / "07-light-sources.md").scene
    point, normal = np.array([0.3, -0.4, 0.0]), np.array([0.0, 0.0, 1.0])
    spot = next(i for i, light in enumerate(scene.lights) if isinstance(light, pl.SpotLight))
    out = probe_readout(scene, point, normal, spot)
    said = [n for n in out["notes"] if re.search(r"\bf = ", n)]
    assert len(said) == 1, out["notes"]
    found = re.search(r"f = ([\d.]+) = attenuation ([\d.]+) \(at distance ([\d.]+)\) × spot factor ([\d.]+)\.", said[0])
    assert found, said
    f, attenuation, _, factor = (float(x) for x in found.groups())
    assert f == pytest.approx(attenuation * factor, abs=1.5e-3), said
    assert 0 < f < 1, said
    # several lights: each light's row says its name, a colon and a space before its sum
    assert re.search(r"<mtext>light&#x000A0;\d:</mtext><mspace", out["equation"]), out["equation"][-600:]


def _row_texts(out) -> dict:
    """label -> the row's text as the page reads it (MathML text, no markup)."""
    import re
    import xml.etree.ElementTree as ET

    return {label: "".join(ET.fromstring(m).itertext())
            for label, m in re.findall(r'<span class="eq-label">([^<]+)</span>(<math.*?</math>)', out["equation"])}


@pytest.fixture(scope="module")
def shadow_lesson():
    return load_lesson(LESSONS / "14-shadows.md").scene


def test_with_shadows_the_rows_carry_the_shadow_factor_with_its_recorded_value(shadow_lesson):
    # lesson 14's probe: on the floor under the ball, facing the lamp (n·l = +0.830) but blocked
    scene, probe = shadow_lesson, np.array(shadow_lesson.probe, dtype=float)
    shaded = _row_texts(probe_readout(scene, probe, UP, 1))
    assert shaded["model"].startswith("I=kaIa+Sfkd") and "+Sfks" in shaded["model"], shaded
    # S = 0 substituted before the other factors, so "= 0.000" follows from the digits shown
    for term in ("diffuse", "specular"):
        assert shaded[term].startswith("Sfk") and "=0·1.000·" in shaded[term], (term, shaded)
    assert "max(0,0.830)" in shaded["diffuse"], shaded
    # the same point with the ball moved away: lit, S = 1
    lit_scene = scene.replace("objects[0].geometry", {"kind": "sphere", "resolution": 48,
                                                      "center": [0, 0, 9.0], "scale": 1})
    lit = _row_texts(probe_readout(lit_scene, probe, UP, 1))
    assert lit["diffuse"].startswith("Sfkd") and "=1·1.000·0.70·1.00·max(0,0.830)=0.581" in lit["diffuse"], lit
    shaded_notes = probe_readout(scene, probe, UP, 1)["notes"]
    lit_notes = probe_readout(lit_scene, probe, UP, 1)["notes"]
    assert "in shadow here (blocked by the ball): S = 0" in shaded_notes[0], shaded_notes
    assert "lit here, S = 1" in lit_notes[0], lit_notes
    # without shadows the rows stay as they were: no S
    plain = _row_texts(probe_readout(scene.replace("shadows", False), probe, UP, 1))
    assert plain["model"] == "I=kaIa+fkdIdmax(0,n·l)+fksIsmax(0,r·v)α", plain
    assert plain["diffuse"] == "fkdIdmax(0,n·l)=1.000·0.70·1.00·max(0,0.830)=0.581", plain
