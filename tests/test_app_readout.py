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
    return probe_readout(scene, point, normal, v, 1, mistake=mistake), v


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
    out = probe_readout(ambient, UNLIT, UP, None, None)
    assert (len([n for n in out["notes"] if "evaluated exactly" in n]) == 1) == (words is not None), out["notes"]
