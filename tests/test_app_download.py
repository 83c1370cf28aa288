"""Exports from the page: PNG bytes for the browser, a server copy only when asked."""

from __future__ import annotations

import base64
import io

import pytest

pytest.importorskip("vtk")

from phonglab.app import download  # noqa: E402
from phonglab.scene import load_lesson  # noqa: E402


def _png_size(data: bytes):
    from PIL import Image

    assert data[:8] == b"\x89PNG\r\n\x1a\n", data[:16]
    with Image.open(io.BytesIO(data)) as img:
        return img.size


def test_terms_figure_bytes_and_data_url():
    scene = load_lesson("lessons/04-specular.md").scene
    data = download.render_png(scene, "terms")
    assert _png_size(data) == (1200, 900)
    url = download.data_url(data)
    assert url.startswith("data:image/png;base64,") and base64.b64decode(url.split(",", 1)[1]) == data


def test_mistake_comparison_needs_a_mistake_and_unknown_kinds_are_refused():
    from phonglab.render import FigureError

    scene = load_lesson("lessons/04-specular.md").scene
    with pytest.raises(FigureError, match="compare"):
        download.render_png(scene, "mistake", None)
    with pytest.raises(ValueError, match="render, terms, mistake"):
        download.render_png(scene, "gif")


def test_file_names_carry_the_kind():
    assert download.file_name("lesson-04", "terms", 0).startswith("lesson-04-terms-")
    assert download.file_name("lesson-04", "render", 0).endswith(".png")
