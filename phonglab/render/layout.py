"""Where things go on a figure: the canvas, the grid of cells, frames and labels in cells.

Boxes are ``(x, y_from_top, width, height)`` in pixels of the figure;
matplotlib figures are made at 100 dpi, so a size in pixels is the size in
hundredths of an inch and a font of ``0.72 * unit`` points is about ``unit``
pixels tall.
"""

from __future__ import annotations

import numpy as np

from phonglab.render.errors import FigureError
from phonglab.render.text import fit_width


def canvas(size, facecolor="white"):
    """A matplotlib figure of ``size`` = (width, height) pixels at 100 dpi (Agg)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100, facecolor=facecolor)


def unit(size) -> int:
    """The layout's unit in pixels: about the height of a label's text."""
    return max(10, round(min(size) / 30))


def grid_layout(size, rows, cols, *, title: bool, row_labels: bool, col_labels: bool, top_offset: int = 0):
    """Pixel boxes (x, y_from_top, w, h) of the cells by row, and the layout's unit.

    Room is kept for a title, row labels on the left and column labels on
    top when asked; ``top_offset`` pixels at the top are kept free (for a
    mistake's band).

    Raises
    ------
    FigureError
        When a cell would be smaller than 8 pixels.
    """
    width, height = size
    u = unit(size)
    top = (round(2.2 * u) if title else round(0.5 * u)) + (round(1.8 * u) if col_labels else 0)
    top += int(top_offset)
    left = round(5.5 * u) if row_labels else round(0.5 * u)
    gap = max(2, round(0.3 * u))
    bottom = right = round(0.5 * u)
    cell_w = (width - left - right - gap * (cols - 1)) // cols
    cell_h = (height - top - bottom - gap * (rows - 1)) // rows
    if cell_w < 8 or cell_h < 8:
        raise FigureError(f"size: {width}x{height} is too small for a {rows} x {cols} grid")
    boxes = [
        [(left + c * (cell_w + gap), top + r * (cell_h + gap), cell_w, cell_h) for c in range(cols)]
        for r in range(rows)
    ]
    return boxes, u


#: a sweep's cells when the figure's size is left to the grid: 4:3, this wide at most and at least
GRID_CELL_WIDTH = (600, 300)
#: and the whole figure this wide at most (before its margins)
GRID_WIDTH = 1800


def grid_size(rows, cols, *, title: bool, row_labels: bool, col_labels: bool,
              max_pixels: int | None = None) -> tuple[int, int]:
    """A figure size (width, height) in pixels whose :func:`grid_layout` cells are 4:3.

    Each cell is :data:`GRID_WIDTH` / ``cols`` wide, kept within
    :data:`GRID_CELL_WIDTH`: a row of three sweeps is 1800 pixels of cells
    and a few hundred tall, not three tall strips in a 4:3 page. With
    ``max_pixels``, the cells shrink (down to the narrowest) until the
    figure has at most that many pixels.
    """
    widest, narrowest = GRID_CELL_WIDTH
    cell_w = max(narrowest, min(widest, GRID_WIDTH // cols))
    while True:
        size = _fitted(rows, cols, cell_w, title=title, row_labels=row_labels, col_labels=col_labels)
        if max_pixels is None or size[0] * size[1] <= max_pixels or cell_w <= narrowest:
            return size
        cell_w = max(narrowest, int(cell_w * 0.95))


def _fitted(rows, cols, cell_w, **shape) -> tuple[int, int]:
    """The size whose grid cells are ``cell_w`` by three quarters of it."""
    cell_h = cell_w * 3 // 4
    size = (cell_w * cols, cell_h * rows)
    for _ in range(8):  # the margins follow the size's unit, which follows the size
        boxes, _unit = grid_layout(size, rows, cols, **shape)
        _, _, w, h = boxes[0][0]
        if (w, h) == (cell_w, cell_h):
            break
        size = (size[0] + (cell_w - w) * cols, size[1] + (cell_h - h) * rows)
    return size


def place(fig, image, box, size):
    """Put an image at a pixel box (top-left origin), unscaled."""
    x, y, w, h = box
    fig.figimage(image, xo=x, yo=size[1] - y - h, origin="upper")


def frame(fig, box, size, u, color):
    """A coloured frame drawn along the edge of a pixel box (top-left origin); ``u`` is the layout's unit."""
    from matplotlib.patches import Rectangle

    x, y, w, h = box
    W, H = size
    fig.add_artist(Rectangle((x / W, 1 - (y + h) / H), w / W, h / H, transform=fig.transFigure, fill=False,
                             edgecolor=color, linewidth=max(1.5, u * 0.12), zorder=2))


def grid_titles(fig, boxes, size, u, *, title="", top_offset: int = 0, row_titles=None, col_titles=None) -> None:
    """The figure's title over the grid, column titles above the first row, row titles left of the first column."""
    fs = u * 0.72  # points at 100 dpi: about u pixels tall
    W, H = size
    if title:
        fig.text(0.5, 1 - (top_offset + 0.3 * u) / H, title, ha="center", va="top", fontsize=fs * 1.25,
                 weight="bold")
    if col_titles:
        for c, text in enumerate(col_titles):
            x, y, w, _ = boxes[0][c]
            fig.text((x + w / 2) / W, 1 - (y - 0.4 * u) / H, text, ha="center", va="bottom", fontsize=fs)
    if row_titles:
        for r, text in enumerate(row_titles):
            x, y, _, h = boxes[r][0]
            fig.text((x - 0.4 * u) / W, 1 - (y + h / 2) / H, text, ha="right", va="center", fontsize=fs)


def cell_labels(fig, boxes, cols, labels, u, size):
    """A label inside each cell's top edge, in a rounded box, shrunk to fit the cell's width.

    ``labels`` holds ``(text, box colour)`` per cell, row-major. Returns each
    label's pixel box ``(x0, y0_from_top, x1, y1_from_top)``, its rounded box included.
    """
    fs = min(u * 0.72, boxes[0][0][2] / 13 * 0.72)
    renderer = fig.canvas.get_renderer()
    W, H = size
    placed = []
    for i, (text, facecolor) in enumerate(labels):
        r, c = divmod(i, cols)
        x, y, w, _ = boxes[r][c]
        label = fig.text((x + w / 2) / W, 1 - (y + 0.3 * u) / H, text, ha="center", va="top",
                         fontsize=fs, color="white", linespacing=1.5,
                         bbox=dict(boxstyle="round,pad=0.3", facecolor=facecolor, edgecolor="none"))
        # the label and its box's padding (0.3 em a side) stay inside the cell, clear of a frame
        fit_width(label, renderer, w - 0.6 * fs / 0.72 - 0.6 * u)
        extent = label.get_window_extent(renderer)
        pad = 0.3 * label.get_fontsize() * 100 / 72  # the rounded box's padding, 0.3 em
        placed.append((extent.x0 - pad, H - extent.y1 - pad, extent.x1 + pad, H - extent.y0 + pad))
    return placed


def fill(fig, box, size, color):
    """Paint a pixel box (top-left origin) with ``color``, under everything drawn on it."""
    from matplotlib.patches import Rectangle

    x, y, w, h = box
    W, H = size
    fig.add_artist(Rectangle((x / W, 1 - (y + h) / H), w / W, h / H, transform=fig.transFigure,
                             facecolor=color, edgecolor="none", zorder=-1))


# ---------------------------------------------------------------------------
# contrast: a panel must read on a projector

#: the least contrast (WCAG style, 1 to 21) between a panel's subject and its background
MIN_CONTRAST = 3.0


def relative_luminance(rgb) -> np.ndarray:
    """WCAG relative luminance of sRGB colours (``(..., 3)`` in [0, 1]): 0 for black, 1 for white.

    Notes
    -----
    Each channel is decoded from sRGB to linear light
    (:math:`c/12.92` below 0.04045, else :math:`((c + 0.055)/1.055)^{2.4}`), then
    :math:`L = 0.2126 R + 0.7152 G + 0.0722 B`.
    """
    c = np.asarray(rgb, dtype=float)
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return linear @ np.array([0.2126, 0.7152, 0.0722])


def contrast_ratio(l1, l2) -> float:
    """WCAG contrast :math:`(L_1 + 0.05) / (L_2 + 0.05)` of two luminances, lighter over darker (1 to 21)."""
    hi, lo = max(float(l1), float(l2)), min(float(l1), float(l2))
    return (hi + 0.05) / (lo + 0.05)


def subject_contrast(image, background) -> float:
    """Contrast between what a render shows and its background colour.

    ``image`` is a (h, w, 3) uint8 render, ``background`` its background in
    [0, 1]. The subject is every pixel more than 6/255 away from the
    background in some channel; its luminance is the mean of theirs. An
    image with no subject has nothing to lose: ``inf``.
    """
    pixels = np.asarray(image, dtype=float) / 255.0
    bg = np.asarray(background, dtype=float)
    subject = np.abs(pixels - bg).max(axis=-1) > 6 / 255
    if not subject.any():
        return float("inf")
    return contrast_ratio(relative_luminance(pixels[subject]).mean(), relative_luminance(bg))
