"""Rendered images against reference images in tests/images/, with a stated tolerance.

Tolerance (see :mod:`phonglab.render.compare`): the mean absolute difference
per channel is at most 2/255, and at most 0.5% of the pixels have a channel
off by more than 16/255. That absorbs a rasterizer's edge differences and
fails on a moved highlight, a wrong colour or a missing arrow.

To regenerate the references after an intended change, run

    PHONGLAB_REGEN_IMAGES=1 python -m pytest tests/test_render_images.py

then look at the new PNGs before committing them.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("vtk")

import phonglab as pl  # noqa: E402
from phonglab.render.compare import image_difference  # noqa: E402
from phonglab.render.figures import figure, render  # noqa: E402
from phonglab.scene import Camera, Geometry, Scene  # noqa: E402

IMAGES = Path(__file__).parent / "images"
REGEN = os.environ.get("PHONGLAB_REGEN_IMAGES") == "1"
SIZE = (200, 150)


def coarse_sphere(interpolation: str) -> Scene:
    return Scene(
        geometry=Geometry("sphere", 12),
        material=pl.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=40),
        lights=(pl.AmbientLight(intensity=0.2), pl.PointLight(position=(2, 2.5, 3))),
        camera=Camera(eye=(0.0, 0.0, 5.0)),
        interpolation=interpolation,
        probe=(0.35, 0.45, 0.82),
        title="Coarse sphere",
    )


def check_against_reference(image: np.ndarray, name: str) -> None:
    from PIL import Image

    path = IMAGES / name
    if REGEN:
        IMAGES.mkdir(exist_ok=True)
        Image.fromarray(image).save(path)
        pytest.skip(f"regenerated {path}")
    assert path.exists(), f"no reference {path}; run with PHONGLAB_REGEN_IMAGES=1 to make it"
    with Image.open(path) as ref:
        reference = np.asarray(ref.convert("RGB"))
    assert image.shape == reference.shape, f"{name}: shape {image.shape}, reference {reference.shape}"
    diff = image_difference(image, reference)
    assert diff.within(), f"{name}: {diff} (allowed: mean <= 2/255, <= 0.5% of pixels off by > 16/255)"


@pytest.mark.parametrize("interpolation", ["flat", "gouraud", "pixel"])
def test_coarse_sphere_matches_reference(interpolation):
    image = render(coarse_sphere(interpolation), SIZE)
    assert image.shape == (SIZE[1], SIZE[0], 3)
    check_against_reference(image, f"sphere_{interpolation}.png")


def test_terms_figure_matches_reference(tmp_path):
    from PIL import Image

    out = tmp_path / "terms.png"
    figure(coarse_sphere("pixel"), out, size=(480, 150), terms=True)
    with Image.open(out) as img:
        image = np.asarray(img.convert("RGB"))
    check_against_reference(image, "terms_row.png")


def test_comparison_catches_a_moved_highlight():
    # the tolerance is not so loose that a different light passes
    a = render(coarse_sphere("pixel"), SIZE, vectors=None)
    b = render(coarse_sphere("pixel").replace("lights[1].position", [-2, 2.5, 3]), SIZE, vectors=None)
    diff = image_difference(a, b)
    assert not diff.within(), f"moving the light went unnoticed: {diff}"
