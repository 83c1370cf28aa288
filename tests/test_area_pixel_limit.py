"""A Monte Carlo area light's work is samples × shaded points: vertices, or pixels in a per-pixel scene."""

from __future__ import annotations

import pytest

from phonglab.bench.scenes import red_sphere_tables
from phonglab.scene import SceneError, load_scene
from phonglab.scene.limits import PIXEL_PICTURE, check_picture_work, shaded_points
from phonglab.scene.schema import MAX_AREA_SAMPLE_POINTS

#: the area light added to the red sphere (resolution 12: 84 vertices)
AREA_LIGHT = """
[area_light]
position = [-0.5, 2, -0.5]
method = "uniform"
samples = {samples}
"""


def scene_file(tmp_path, interpolation: str, samples: int):
    path = tmp_path / f"{interpolation}-{samples}.toml"
    text = f'interpolation = "{interpolation}"\n\n' + red_sphere_tables(12) + AREA_LIGHT.format(samples=samples)
    path.write_text(text, encoding="utf-8")
    return path


def test_a_coarse_sphere_with_many_samples_passes_per_vertex(tmp_path):
    # 4096 samples × 84 vertices: about 344,000 rays, well within the limit
    scene = load_scene(scene_file(tmp_path, "gouraud", 4096))
    vertices, pixels = shaded_points(scene)
    assert pixels is None and 4096 * vertices < MAX_AREA_SAMPLE_POINTS, (vertices, pixels)


def test_the_same_scene_per_pixel_is_refused_for_its_pixels(tmp_path):
    # per pixel the same light is shot from every pixel of the picture: 4096 × 2.56 M ≈ 10 G rays
    # (minutes of work); counted by vertices, as before, it passed
    path = scene_file(tmp_path, "pixel", 4096)
    with pytest.raises(SceneError) as refused:
        load_scene(path)
    text = str(refused.value)
    assert "area_light.samples" in text and f"{PIXEL_PICTURE:,} pixels" in text, text
    assert f"at most {MAX_AREA_SAMPLE_POINTS:,}" in text and "at most 19 samples" in text, text


def test_switching_to_per_pixel_is_refused_like_a_file(tmp_path):
    scene = load_scene(scene_file(tmp_path, "gouraud", 4096))
    with pytest.raises(SceneError, match="area_light.samples"):
        scene.replace("interpolation", "pixel")
    fewer = load_scene(scene_file(tmp_path, "gouraud", MAX_AREA_SAMPLE_POINTS // PIXEL_PICTURE))
    assert fewer.replace("interpolation", "pixel").interpolation == "pixel"


def test_an_export_checks_its_own_pixels(tmp_path):
    from phonglab.render import figure

    samples = MAX_AREA_SAMPLE_POINTS // PIXEL_PICTURE  # fits the page's largest view
    scene = load_scene(scene_file(tmp_path, "pixel", samples))
    check_picture_work(scene, PIXEL_PICTURE)
    out = tmp_path / "big.png"
    # 1200 × 900 at supersample 2 renders 4.32 M pixels: past the limit at this many samples
    with pytest.raises(SceneError, match="area_light.samples") as refused:
        figure(scene, out, size=(1200, 900), supersample=2)
    assert "4,320,000 pixels" in str(refused.value), refused.value
    assert not out.exists() and not list(tmp_path.glob(".*")), sorted(p.name for p in tmp_path.iterdir())


def test_the_page_never_shades_more_pixels_than_the_scene_was_checked_for():
    from phonglab.app.view_input import MAX_PIXEL_SIDE

    assert MAX_PIXEL_SIDE**2 <= PIXEL_PICTURE, (MAX_PIXEL_SIDE, PIXEL_PICTURE)
