"""Saving images and figures, each file whole or not at all.

Every file the render layer writes goes through
:func:`phonglab.render._files.write_atomically`: written to a hidden
temporary file in the target folder, then renamed into place.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from phonglab.render import _files
from phonglab.render.errors import FigureError
from phonglab.render.layout import canvas


#: matplotlib settings that keep a figure's words as text in SVG and PDF files
TEXT_AS_TEXT = {"svg.fonttype": "none", "pdf.fonttype": 42}


def save_png(image: np.ndarray, path) -> None:
    """Write an RGB image as PNG, whole or not at all (temporary file, then rename).

    Raises
    ------
    OSError
        When the file cannot be written; nothing is left behind.
    """
    _files.write_atomically(path, lambda tmp: Image.fromarray(np.asarray(image, dtype=np.uint8)).save(tmp, format="PNG"))


def write_output(path: Path, write) -> None:
    """Write a figure's file whole or not at all: ``write(tmp_path)`` then a rename.

    Raises
    ------
    FigureError
        If the file cannot be written (one line naming the path); nothing is left behind.
    """
    try:
        _files.write_atomically(path, write)
    except OSError as exc:
        raise FigureError(f"{path}: cannot write: {exc.strerror or exc}") from None


def save_image(image: np.ndarray, path: Path, ext: str) -> None:
    """Write an RGB image: PNG directly; SVG/PDF as a page holding the image at 100 dpi."""
    if ext == ".png":
        write_output(path, lambda tmp: Image.fromarray(image).save(tmp, format="PNG"))
        return
    fig = canvas((image.shape[1], image.shape[0]))
    fig.figimage(image, 0, 0, origin="upper")
    save_figure(fig, path, ext)


def save_figure(fig, path: Path, ext: str) -> None:
    """Save a matplotlib figure in the format of ``ext`` (``".png"``, ``".svg"``, ``".pdf"``), atomically, and close it."""
    import matplotlib
    import matplotlib.pyplot as plt

    def write(tmp):
        # text stays text (editable on a slide): SVG <text> elements, TrueType fonts embedded in PDF
        with matplotlib.rc_context(TEXT_AS_TEXT):
            fig.savefig(tmp, format=ext[1:], dpi=100, facecolor=fig.get_facecolor())

    try:
        write_output(path, write)
    finally:
        plt.close(fig)
