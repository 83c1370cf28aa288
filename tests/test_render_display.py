"""The display encoding end to end: scene options, the mesh colours and exported figures.

The core computes linear light; what reaches the screen or a PNG is
linear → exposure → clip → sRGB (default) or the raw values (``display = "linear"``).
A 50 % grey Lambertian plane lit head-on by a unit light has radiance 0.5:
188/255 encoded as sRGB, 128/255 raw.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("vtk")

import phonglab as pl  # noqa: E402
from phonglab.render import figure  # noqa: E402
from phonglab.render.glyphs import light_color_255  # noqa: E402
from phonglab.render.shading import display_rgb8, pixel_colors, vertex_colors  # noqa: E402
from phonglab.scene import Camera, Geometry, Scene, SceneError, scene_from_dict, scene_to_dict  # noqa: E402


def grey_plane(**changes) -> Scene:
    """A 50 % grey Lambertian plane facing the eye, lit head-on by a unit directional light."""
    s = Scene(
        geometry=Geometry("plane", 8),
        material=pl.Material(ka=0.0, kd=0.5, ks=0.0, shininess=1.0),
        lights=(pl.DirectionalLight(direction=(0.0, 0.0, 1.0)),),
        camera=Camera(eye=(0.0, 0.0, 3.0)),
        interpolation="pixel",
    )
    for path, value in changes.items():
        s = s.replace(path, value)
    return s


def centre_pixel(path) -> np.ndarray:
    """A 5 × 5 patch of the plane below the middle (the light's marker sits in the middle)."""
    from PIL import Image

    with Image.open(path) as img:
        rgb = np.asarray(img.convert("RGB"))
    h, w, _ = rgb.shape
    row = int(0.7 * h)
    return rgb[row - 2 : row + 3, w // 2 - 2 : w // 2 + 3].reshape(-1, 3)


@pytest.mark.parametrize("settings, expected", [({}, 188), ({"display": "linear"}, 128)])
def test_half_grey_plane_exports_as_188_srgb_and_128_linear(tmp_path, settings, expected):
    out = figure(grey_plane(**settings), tmp_path / "grey.png", size=(160, 120), vectors=None)
    pixels = centre_pixel(out)
    assert np.all(np.abs(pixels.astype(int) - expected) <= 1), (settings, pixels[:3].tolist(), expected)


def test_exposure_scales_radiance_before_the_curve(tmp_path):
    # 0.5 × 2 = 1.0: white; 0.5 × 0.5 = 0.25: sRGB 137
    bright = centre_pixel(figure(grey_plane(exposure=2.0), tmp_path / "b.png", size=(160, 120), vectors=None))
    dim = centre_pixel(figure(grey_plane(exposure=0.5), tmp_path / "d.png", size=(160, 120), vectors=None))
    assert np.all(bright >= 254), bright[:3].tolist()
    assert np.all(np.abs(dim.astype(int) - 137) <= 1), dim[:3].tolist()


def test_mesh_colours_follow_the_scene_display():
    import pyvista as pv

    mesh = pv.Plane(i_resolution=2, j_resolution=2).compute_normals()
    srgb = vertex_colors(grey_plane(), mesh)["color"]
    linear = vertex_colors(grey_plane(display="linear"), mesh)["color"]
    assert np.all(srgb == 188), srgb.tolist()
    assert np.all(linear == 128), linear.tolist()


def test_display_rgb8_clips_over_exposure_and_blacks_out_nan():
    values = np.array([[2.0, -1.0, np.nan]])
    assert display_rgb8(grey_plane(), values).tolist() == [[255, 0, 0]]
    assert display_rgb8(grey_plane(exposure=0.25), np.array([[2.0, 0.5, 0.0]])).tolist() == [[188, 99, 0]]


def test_light_marker_colour_is_srgb_encoded():
    # a light of linear colour (1, 0.5, 0) shows its orange as sRGB (255, 188, 0)
    assert light_color_255(pl.PointLight(position=(0, 0, 1), color=(1.0, 0.5, 0.0))) == (255, 188, 0)
    # a lamp that gives no light is drawn switched off (lesson 7's second lamp at intensity 0 was a bright white)
    from phonglab.render.glyphs import OFF_LIGHT_COLOR

    for off in (pl.PointLight(position=(0, 0, 1), intensity=0.0), pl.PointLight(position=(0, 0, 1), color=(0, 0, 0))):
        assert light_color_255(off) == OFF_LIGHT_COLOR, off
    assert light_color_255(pl.PointLight(position=(0, 0, 1), intensity=0.05)) == (255, 255, 255)


def test_display_and_exposure_are_scene_fields():
    s = grey_plane()
    assert (s.display, s.exposure) == ("srgb", 1.0)
    t = s.replace("display", "linear").replace("exposure", 2)
    assert (t.display, t.exposure) == ("linear", 2.0)
    data = scene_to_dict(t)
    assert (data["display"], data["exposure"]) == ("linear", 2.0)
    again = scene_from_dict(data)
    assert (again.display, again.exposure) == ("linear", 2.0)


@pytest.mark.parametrize("path, value, words", [
    ("display", "gamma", ['display', '"srgb", "linear"', '"gamma"']),
    ("exposure", 0, ["exposure", "> 0", "got 0"]),
    ("exposure", -1.5, ["exposure", "> 0", "-1.5"]),
    ("exposure", "bright", ["exposure", "finite number", "bright"]),
])
def test_bad_display_options_name_field_value_and_allowed(path, value, words):
    with pytest.raises(SceneError) as info:
        grey_plane().replace(path, value)
    message = str(info.value)
    assert all(w in message for w in words), (path, value, message)


def test_display_lessons_grey_patch_is_188_srgb_and_128_linear(tmp_path):
    from pathlib import Path

    from phonglab.scene import load_lesson

    les = load_lesson(Path(__file__).resolve().parents[1] / "lessons" / "12-display.md")
    patch = next(e for e in les.experiments if e.label == "The grey patch").apply(les.scene)
    for display, expected in (("srgb", 188), ("linear", 128)):
        out = figure(patch.replace("display", display), tmp_path / f"{display}.png", size=(160, 120), vectors=None)
        pixels = centre_pixel(out)
        # the patch lies a little off the lamp's axis below the middle (n·l ≈ 0.98): within 4 of the centre's value
        assert np.all(np.abs(pixels.astype(int) - expected) <= 4), (display, pixels[:3].tolist(), expected)
