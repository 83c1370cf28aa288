"""Text on rendered images: vector labels and the legend, drawn with Pillow.

Labels are drawn after rendering, on the final RGB image, so they stay crisp,
sit on top of every shading mode (including the per-pixel composite) and use
the same DejaVu font as the matplotlib plots.
"""

from __future__ import annotations

import functools
import os

import matplotlib
import numpy as np
from PIL import Image, ImageDraw, ImageFont


@functools.lru_cache(maxsize=32)
def font(size: int, bold: bool = False) -> ImageFont.FreeTypeFont:
    """DejaVu Sans (shipped with matplotlib) at ``size`` pixels."""
    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    return ImageFont.truetype(os.path.join(matplotlib.get_data_path(), "fonts", "ttf", name), int(size))


def _overlaps(a, b, pad=2.0) -> bool:
    return not (a[2] + pad <= b[0] or b[2] + pad <= a[0] or a[3] + pad <= b[1] or b[3] + pad <= a[1])


def draw_labels(image: np.ndarray, labels) -> np.ndarray:
    """Draw vector letters next to arrow tips.

    Parameters
    ----------
    image : ndarray, shape (height, width, 3), uint8
    labels : sequence of (text, (x, y), (dx, dy), rgb)
        ``(x, y)`` is the arrow tip in image pixels (row 0 at the top),
        ``(dx, dy)`` the arrow's on-screen direction (the label goes a little
        beyond the tip along it), ``rgb`` the label colour (0..255).

    Returns
    -------
    ndarray
        A new image with the labels; a label that would cover an earlier one
        is moved down until it does not.
    """
    height = image.shape[0]
    size = max(12, round(height / 24))
    fnt = font(size, bold=True)
    out = Image.fromarray(image)
    draw = ImageDraw.Draw(out)
    placed = []
    for text, (x, y), (dx, dy), rgb in labels:
        d = np.array([dx, dy], dtype=float)
        norm = np.linalg.norm(d)
        d = d / norm if norm > 1e-9 else np.array([0.0, -1.0])
        width_px, height_px = draw.textbbox((0, 0), text, font=fnt, anchor="mm")[2:]
        centre = np.array([x, y]) + d * (0.45 * size + 0.6 * max(width_px, height_px))
        # keep the label inside the image
        half = 0.5 * max(width_px, height_px) + 2
        centre = np.clip(centre, [half, half], [image.shape[1] - half, height - half])
        for _ in range(8):
            left, top, right, bottom = draw.textbbox(tuple(centre), text, font=fnt, anchor="mm")
            box = np.array([left, top, right, bottom], dtype=float)
            if not any(_overlaps(box, other) for other in placed):
                break
            centre = centre + np.array([0.0, (bottom - top) + 2])
        placed.append(box)
        # a dark outline keeps the letter readable on bright highlights
        draw.text(
            tuple(centre), text, font=fnt, anchor="mm", fill=tuple(int(c) for c in rgb),
            stroke_width=max(1, size // 10), stroke_fill=(15, 15, 20),
        )
    return np.asarray(out)


def draw_legend(image: np.ndarray, entries, *, corner: str = "bottom-left") -> np.ndarray:
    """Draw a legend box: a coloured arrow, the letter and a description per entry.

    Parameters
    ----------
    image : ndarray, shape (height, width, 3), uint8
    entries : sequence of (letter, description, rgb)
    corner : {"bottom-left", "top-left"}

    Returns
    -------
    ndarray
        A new image with the legend.
    """
    if not entries:
        return image
    height, width = image.shape[:2]
    size = max(10, round(height / 38))
    fnt, bold = font(size), font(size, bold=True)
    line = round(size * 1.45)
    pad = round(size * 0.6)
    icon = round(size * 1.8)
    measure = ImageDraw.Draw(Image.new("RGBA", (1, 1)))
    text_width = max(measure.textlength(f"{d}", font=fnt) for _, d, _ in entries)
    letter_width = max(measure.textlength(letter, font=bold) for letter, _, _ in entries)
    box_w = min(int(pad * 3 + icon + letter_width + size * 0.6 + text_width), width - 2 * pad)
    box_h = min(int(pad * 2 + line * len(entries)), height - 2 * pad)
    # draw on the legend's own patch of the image only
    left = pad
    top = height - box_h - pad if corner == "bottom-left" else pad
    patch = Image.fromarray(np.ascontiguousarray(image[top:top + box_h + 1, left:left + box_w + 1])).convert("RGBA")
    layer = Image.new("RGBA", patch.size, (0, 0, 0, 0))
    draw = ImageDraw.Draw(layer)
    x0, y0 = 0, 0
    draw.rounded_rectangle((x0, y0, box_w, box_h), radius=pad, fill=(10, 10, 14, 170))
    for i, (letter, description, rgb) in enumerate(entries):
        colour = tuple(int(c) for c in rgb) + (255,)
        cy = y0 + pad + line * i + line / 2
        ax = x0 + pad
        # the arrow icon: a shaft and a head
        shaft = max(2, size // 6)
        draw.line((ax, cy, ax + icon - size * 0.5, cy), fill=colour, width=shaft)
        head = size * 0.45
        draw.polygon(
            [(ax + icon, cy), (ax + icon - head * 1.4, cy - head), (ax + icon - head * 1.4, cy + head)], fill=colour
        )
        tx = ax + icon + pad
        draw.text((tx, cy), letter, font=bold, fill=colour, anchor="lm")
        draw.text((tx + letter_width + size * 0.6, cy), description, font=fnt, fill=(235, 235, 235, 255), anchor="lm")
    out = np.array(image)
    out[top:top + box_h + 1, left:left + box_w + 1] = np.asarray(Image.alpha_composite(patch, layer).convert("RGB"))
    return out


def downsample(image: np.ndarray, factor: int) -> np.ndarray:
    """Average ``factor × factor`` blocks (supersampling antialiasing)."""
    if factor <= 1:
        return image
    return np.asarray(Image.fromarray(np.ascontiguousarray(image)).reduce(int(factor)))
