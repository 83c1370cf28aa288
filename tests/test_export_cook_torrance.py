"""Exports of the Cook–Torrance model: renders, roughness sweeps, Phong beside Cook–Torrance, the furnace plot."""

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from phonglab.render import figure
from phonglab.render.figures import COMPARED_MODELS
from phonglab.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
SPHERE = ROOT / "assets" / "scenes" / "sphere.toml"
SIZE = (480, 240)


def pixels(path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int16)


def halves(image):
    w = image.shape[1] // 2
    return image[:, :w], image[:, w:]


def test_models_figure_shades_each_panel_with_its_own_model(tmp_path):
    # the roughness is Cook–Torrance's: changing it must change the right panel and leave Phong's alone
    smooth = figure(SPHERE, tmp_path / "smooth.png", size=SIZE, models=True, vectors=None,
                    settings=["material.roughness=0.2"])
    rough = figure(SPHERE, tmp_path / "rough.png", size=SIZE, models=True, vectors=None,
                   settings=["material.roughness=0.8"])
    (phong_a, ct_a), (phong_b, ct_b) = halves(pixels(smooth)), halves(pixels(rough))
    assert [m for m, _ in COMPARED_MODELS] == ["phong", "cook-torrance"]
    assert np.abs(phong_a - phong_b).max() == 0, "the Phong panel changed with the roughness"
    change = np.abs(ct_a - ct_b)
    assert change.max() >= 20 and change.mean() > 0.2, "the Cook–Torrance panel did not change with the roughness"
    # and the shininess is Phong's: it moves the left panel only
    sharp = figure(SPHERE, tmp_path / "sharp.png", size=SIZE, models=True, vectors=None,
                   settings=["material.roughness=0.2", "material.shininess=300"])
    phong_c, ct_c = halves(pixels(sharp))
    assert np.abs(ct_a - ct_c).max() == 0 and np.abs(phong_a - phong_c).mean() > 0.5


def test_a_roughness_sweep_renders_one_cook_torrance_picture_per_value(tmp_path):
    out = figure(SPHERE, tmp_path / "sweep.png", size=(600, 240), vectors=None,
                 settings=["model=cook-torrance", "material.metallic=1"],
                 sweep=[("material.roughness", [0.15, 0.5, 0.9])])
    image = pixels(out)
    thirds = [image[:, i * 200:(i + 1) * 200] for i in range(3)]
    # each cell is shaded with its own roughness: no two are the same picture
    for i in range(3):
        for j in range(i + 1, 3):
            diff = np.abs(thirds[i] - thirds[j])
            assert diff.max() >= 20 and diff.mean() > 0.2, f"cells {i} and {j} differ by {diff.mean():.2f} on average"


def test_furnace_plot_and_models_from_the_command_line(tmp_path):
    for flags, name in ((["--plot", "furnace"], "furnace.png"), (["--models"], "models.png")):
        out = tmp_path / name
        done = subprocess.run([sys.executable, "-m", "phonglab.cli", "export", str(SPHERE), "-o", str(out),
                               "--size", "400x300", *flags], capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, (flags, done.stderr)
        assert Image.open(out).size == (400, 300)


@pytest.mark.parametrize("flags", [["--models", "--terms"], ["--models", "--plot", "lobe"],
                                   ["--models", "--mistake", "no-clamp-diffuse"]])
def test_models_refuses_what_it_cannot_combine_in_one_line(tmp_path, flags):
    out = tmp_path / "x.png"
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "export", str(SPHERE), "-o", str(out), *flags],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, (flags, done.stderr)
    assert "models" in done.stderr and not out.exists(), done.stderr


def test_page_exports_the_comparison_and_the_furnace():
    from phonglab.app.download import render_png

    scene = load_scene(SPHERE).replace("material.roughness", 0.35)
    for kind in ("models", "furnace"):
        data = render_png(scene, kind)
        assert Image.open(io.BytesIO(data)).format == "PNG", kind
