"""Text on rendered images: vector labels and the legend, drawn with Pillow.

Labels are drawn after rendering, on the final RGB image, so they stay crisp,
sit on top of every shading mode (including the per-pixel composite) and use
the same DejaVu font as the matplotlib plots.
"""

from __future__ import annotations

import functools
import math
import os

import matplotlib
import numpy as np
from PIL import Image, ImageDraw, ImageFont


@functools.lru_cache(maxsize=32)
def font(size: int, bold: bool = False) -> ImageFont.FreeTypeFont:
    """DejaVu Sans (shipped with matplotlib) at ``size`` pixels."""
    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    return ImageFont.truetype(os.path.join(matplotlib.get_data_path(), "fonts", "ttf", name), int(size))


#: places about a tip, tried in turn: rings further out, each turned from the arrow's direction (degrees)
LABEL_TURNS = (0, 45, -45, 90, -90, 135, -135, 180)
LABEL_RINGS = 3
#: tips nearer than this (pixels) are one place: their letters cannot tell them apart
SAME_TIP = 3.0
#: pixels kept free between two letters' boxes
LABEL_PAD = 2.0


def _to_segment(point, a, b) -> float:
    """Pixels from ``point`` to the segment from ``a`` to ``b``."""
    u = b - a
    uu = float(u @ u)
    t = min(1.0, max(0.0, float((point - a) @ u) / uu)) if uu > 0 else 0.0
    return float(np.hypot(*(point - a - t * u)))


def place_labels(tips, directions, offsets, halves, size) -> list[np.ndarray]:
    """Where each letter's centre goes: about its own tip, never nearer another arrow's tip.

    Parameters
    ----------
    tips : sequence of (x, y)
        The arrow tips in image pixels (row 0 at the top), in drawing order.
    directions : sequence of (dx, dy)
        Each arrow on the image, its tip less its base (zero: seen end-on, the letter goes above).
    offsets : sequence of float
        How far past its tip each letter's centre goes first, in pixels.
    halves : sequence of float
        Half the side of each letter's box, in pixels.
    size : (width, height)
        The image's size.

    Returns
    -------
    list of ndarray
        Each letter's centre.

    Notes
    -----
    The first place is ``offset`` past the tip along the arrow. Where it
    covers a letter placed before, lies outside the image, is as near
    another tip as its own (a letter reads as its nearest tip's; tips
    within :data:`SAME_TIP` are one) or lies on another arrow (its box over
    the line from that arrow's base to its tip), the letter turns about its own tip by
    :data:`LABEL_TURNS`, then a ring half a box further out; with no free
    place in :data:`LABEL_RINGS` rings, the place covering, straying and
    crossing least is taken. A letter never wanders off to another arrow.
    The page places its letters by the same rules (``placeLetter`` in
    ``app/www/phonglab.js``).
    """
    width, height = size
    tips = [np.asarray(t, dtype=float) for t in tips]
    # each arrow on the image, from its base (the probe) to its tip: a direction is the tip less the base
    shafts = [(tip - np.asarray(direction, dtype=float), tip) for tip, direction in zip(tips, directions)]
    placed: list[tuple[np.ndarray, float]] = []
    for tip, direction, offset, half in zip(tips, directions, offsets, halves):
        d = np.asarray(direction, dtype=float)
        norm = float(np.hypot(*d))
        d = d / norm if norm > 1e-9 else np.array([0.0, -1.0])
        apart = [j for j, t in enumerate(tips) if float(np.hypot(*(t - tip))) >= SAME_TIP]
        others = [tips[j] for j in apart]
        best = None
        for ring in range(LABEL_RINGS):
            r = offset + ring * half
            for turn in LABEL_TURNS:
                c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
                centre = tip + r * np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
                covers = sum(bool(np.all(np.abs(centre - other) < half + other_half + LABEL_PAD))
                             for other, other_half in placed)
                strays = sum(float(np.hypot(*(other - centre))) <= r + 1.0 for other in others)
                crosses = sum(_to_segment(centre, *shafts[j]) < half for j in apart)
                outside = not (half <= centre[0] <= width - half and half <= centre[1] <= height - half)
                cost = 3 * covers + 2 * strays + 2 * outside + crosses + ring
                if best is None or cost < best[0]:
                    best = (cost, centre)
                if cost == ring:  # free: the nearest free place
                    break
            if best[0] == ring:
                break
        placed.append((best[1], half))
    return [centre for centre, _ in placed]


def label_places(labels, size) -> tuple[list[np.ndarray], list[float]]:
    """The centres :func:`draw_labels` gives ``labels`` on an image of ``size`` (width, height), and their half extents."""
    size_px = max(12, round(size[1] / 24))
    fnt = font(size_px, bold=True)
    # each letter's half extent from its centre (a box anchored at its middle ends there)
    extents = [max(fnt.getbbox(text, anchor="mm")[2:]) for text, *_ in labels]
    centres = place_labels([xy for _, xy, _, _ in labels], [d for _, _, d, _ in labels],
                           [0.45 * size_px + 0.6 * e for e in extents], [e + 1 for e in extents], size)
    return centres, extents


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
        A new image with the labels, each about its own tip (:func:`place_labels`).
    """
    height = image.shape[0]
    size = max(12, round(height / 24))
    fnt = font(size, bold=True)
    out = Image.fromarray(image)
    draw = ImageDraw.Draw(out)
    centres, extents = label_places(labels, (image.shape[1], height))
    for (text, _, _, rgb), centre, extent in zip(labels, centres, extents):
        half = 0.5 * extent + 2
        centre = np.clip(centre, [half, half], [image.shape[1] - half, height - half])  # inside the image
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
