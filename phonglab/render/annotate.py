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
#: tips nearer than this many font sizes share one label, "N, L, R": each letter past its own tip would
#: fall on the others' (lesson 3's probe, θ ≈ 1.9° from the mirror direction, puts N, L and R there)
TOGETHER = 1.0
#: what stands between the letters of a shared label, and its colour (each letter keeps its arrow's)
JOIN = ", "
JOIN_COLOR = (225, 225, 230)


def _to_segment(point, a, b) -> float:
    """Pixels from ``point`` to the segment from ``a`` to ``b``."""
    u = b - a
    uu = float(u @ u)
    t = min(1.0, max(0.0, float((point - a) @ u) / uu)) if uu > 0 else 0.0
    return float(np.hypot(*(point - a - t * u)))


def _between_segments(a0, a1, b0, b1) -> float:
    """Pixels between the segment ``a0``–``a1`` and the segment ``b0``–``b1`` (0 where they cross)."""
    def side(p, q, r):
        return float((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    if side(a0, a1, b0) * side(a0, a1, b1) < 0 and side(b0, b1, a0) * side(b0, b1, a1) < 0:
        return 0.0
    return min(_to_segment(a0, b0, b1), _to_segment(a1, b0, b1), _to_segment(b0, a0, a1), _to_segment(b1, a0, a1))


def place_labels(tips, directions, offsets, halves, size) -> list[np.ndarray]:
    """Where each label's centre goes: about its own tip, never nearer another arrow's tip.

    Parameters
    ----------
    tips : sequence of (x, y)
        The arrow tips in image pixels (row 0 at the top), in drawing order.
    directions : sequence of (dx, dy)
        Each arrow on the image, its tip less its base (zero: seen end-on, the letter goes above).
    offsets : sequence of float
        How far past its tip each label's centre goes first, in pixels.
    halves : sequence of float or (float, float)
        Half the side of each label's square box, or half its width and
        half its height (a shared label, "N, L, R", is wider than tall), in pixels.
    size : (width, height)
        The image's size.

    Returns
    -------
    list of ndarray
        Each label's centre.

    Notes
    -----
    The first place is ``offset`` past the tip along the arrow (a wide
    label goes further by the part of its width that lies along that
    way: ``(half width − half height)·|cos|``). Where it
    covers a label placed before, lies outside the image, is as near
    another tip as its own (a letter reads as its nearest tip's; tips
    within :data:`SAME_TIP` are one) or lies on another arrow (its box over
    the line from that arrow's base to its tip), the label turns about its own tip by
    :data:`LABEL_TURNS`, then a ring half a box further out; with no free
    place in :data:`LABEL_RINGS` rings, the place covering, straying and
    crossing least is taken. A label never wanders off to another arrow.
    The page places its letters by the same rules (``placeLetter`` in
    ``app/www/phonglab.js``).
    """
    width, height = size
    tips = [np.asarray(t, dtype=float) for t in tips]
    # each arrow on the image, from its base (the probe) to its tip: a direction is the tip less the base
    shafts = [(tip - np.asarray(direction, dtype=float), tip) for tip, direction in zip(tips, directions)]
    placed: list[tuple[np.ndarray, float, float]] = []
    for tip, direction, offset, half in zip(tips, directions, offsets, halves):
        hx, hy = (float(half), float(half)) if np.ndim(half) == 0 else (float(half[0]), float(half[1]))
        wide = hx - hy  # how much wider than tall: 0 for a letter alone
        d = np.asarray(direction, dtype=float)
        norm = float(np.hypot(*d))
        d = d / norm if norm > 1e-9 else np.array([0.0, -1.0])
        apart = [j for j, t in enumerate(tips) if float(np.hypot(*(t - tip))) >= SAME_TIP]
        others = [tips[j] for j in apart]
        best = None
        for ring in range(LABEL_RINGS):
            for turn in LABEL_TURNS:
                c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
                way = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
                r = offset + ring * hy + wide * abs(way[0])
                centre = tip + r * way
                covers = sum(bool(abs(centre[0] - other[0]) < hx + other_hx + LABEL_PAD
                                  and abs(centre[1] - other[1]) < hy + other_hy + LABEL_PAD)
                             for other, other_hx, other_hy in placed)
                strays = sum(float(np.hypot(*(other - centre))) <= r + 1.0 for other in others)
                if wide > 0:  # a wide label: its middle line, widened by half its height on every side
                    line = (centre - (wide, 0.0), centre + (wide, 0.0))
                    crosses = sum(_between_segments(*line, *shafts[j]) < hy for j in apart)
                else:
                    crosses = sum(_to_segment(centre, *shafts[j]) < hy for j in apart)
                outside = not (hx <= centre[0] <= width - hx and hy <= centre[1] <= height - hy)
                cost = 3 * covers + 2 * strays + 2 * outside + crosses + ring
                if best is None or cost < best[0]:
                    best = (cost, centre)
                if cost == ring:  # free: the nearest free place
                    break
            if best[0] == ring:
                break
        placed.append((best[1], hx, hy))
    return [centre for centre, _, _ in placed]


def share_labels(tips, together: float) -> list[list[int]]:
    """Which arrows share one label: tips nearer than ``together`` pixels, chained, in drawing order.

    Parameters
    ----------
    tips : sequence of (x, y)
        The arrow tips on the image, in drawing order.
    together : float
        Tips nearer than this are one place for their letters (about a letter's size).

    Returns
    -------
    list of list of int
        Each label's arrows (indices into ``tips``, ascending), ordered by their first arrow.
    """
    tips = [np.asarray(t, dtype=float) for t in tips]
    groups: list[list[int]] = []
    for i, tip in enumerate(tips):
        near = [g for g in groups if any(float(np.hypot(*(tips[j] - tip))) < together for j in g)]
        groups = [g for g in groups if g not in near] + [sorted([j for g in near for j in g] + [i])]
    return sorted(groups)


class Label:
    """One label at the arrow tips as an image shows it: a letter, or the letters of arrows that meet, "N, L, R".

    Attributes
    ----------
    letters : tuple of str
        The letters, in drawing order.
    colours : tuple of (r, g, b)
        Each letter's colour (its arrow's).
    pieces : list of (text, (x, y), rgb, anchor)
        What is drawn: each letter and each :data:`JOIN` between two, its
        place on the image as Pillow's ``anchor`` names it, and its colour. A
        letter alone is centred on :attr:`centre` (``"mm"``); the pieces of a
        shared label are set from their middle left (``"lm"``).
    boxes : dict
        letter -> its own box ``(left, top, right, bottom)`` on the image (the glyph's ink, outline included).
    centre : ndarray
        The label's centre.
    font, stroke
        The font and the outline's width (pixels) the pieces are drawn with.
    """

    def __init__(self, letters, colours, centre, fnt, stroke: int):
        self.letters, self.colours, self.centre = tuple(letters), tuple(colours), centre
        self.font, self.stroke = fnt, stroke  # what the pieces are drawn with (:func:`draw_labels`)
        texts = [JOIN if i % 2 else self.letters[i // 2] for i in range(2 * len(self.letters) - 1)]
        colour = [JOIN_COLOR if i % 2 else self.colours[i // 2] for i in range(len(texts))]
        x = float(centre[0]) - fnt.getlength("".join(texts)) / 2
        self.pieces, self.boxes = [], {}
        for i, text in enumerate(texts):
            start = x + fnt.getlength("".join(texts[:i]))
            if len(texts) == 1:
                self.pieces.append((text, (float(centre[0]), float(centre[1])), colour[i], "mm"))
            else:
                self.pieces.append((text, (start, float(centre[1])), colour[i], "lm"))
            if not i % 2:
                left, top, right, bottom = fnt.getbbox(text, anchor="lm", stroke_width=stroke)
                self.boxes[text] = (start + left, centre[1] + top, start + right, centre[1] + bottom)

    @property
    def text(self) -> str:
        """The label as one string, ``"N, L, R"``."""
        return JOIN.join(self.letters)


def label_layout(labels, size) -> list[Label]:
    """The labels :func:`draw_labels` draws for ``labels`` on an image of ``size`` (width, height).

    Arrows whose tips lie nearer than :data:`TOGETHER` font sizes share one
    label (:func:`share_labels`): their letters side by side, ``"N, L, R"``,
    each in its arrow's colour, past the tips' middle along their mean
    direction. Every other letter is placed about its own tip alone
    (:func:`place_labels`), as if no label were shared.
    """
    size_px = max(12, round(size[1] / 24))
    fnt = font(size_px, bold=True)
    stroke = max(1, size_px // 10)
    tips = [np.asarray(xy, dtype=float) for _, xy, _, _ in labels]
    groups = share_labels(tips, TOGETHER * size_px)
    # each label's half extent from its centre (a letter's box anchored at its middle ends there)
    extents = [max(max(fnt.getbbox(labels[i][0], anchor="mm")[2:]) for i in group) for group in groups]
    anchors, directions, offsets, halves = [], [], [], []
    for group, extent in zip(groups, extents):
        anchors.append(np.mean([tips[i] for i in group], axis=0))
        # the arrows share their base (the probe): the mean direction ends at the tips' middle
        directions.append(np.mean([np.asarray(labels[i][2], dtype=float) for i in group], axis=0))
        offsets.append(0.45 * size_px + 0.6 * extent)
        if len(group) == 1:
            halves.append(extent + 1)
        else:
            text = JOIN.join(labels[i][0] for i in group)
            left, _, right, _ = fnt.getbbox(text, anchor="mm")
            halves.append((max(-left, right) + 1, extent + 1))
    centres = place_labels(anchors, directions, offsets, halves, size)
    out = []
    for group, centre, extent in zip(groups, centres, extents):
        half_y = 0.5 * extent + 2
        half_x = half_y if len(group) == 1 else 0.5 * fnt.getlength(JOIN.join(labels[i][0] for i in group)) + 2
        centre = np.clip(centre, [half_x, half_y], [size[0] - half_x, size[1] - half_y])  # inside the image
        out.append(Label([labels[i][0] for i in group], [labels[i][3] for i in group], centre, fnt, stroke))
    return out


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
        A new image with the labels, each about its own tip; the letters of
        arrows whose tips meet share one label, "N, L, R" (:func:`label_layout`).
    """
    out = Image.fromarray(image)
    draw = ImageDraw.Draw(out)
    for label in label_layout(labels, (image.shape[1], image.shape[0])):
        for text, at, rgb, anchor in label.pieces:
            # a dark outline keeps the letter readable on bright highlights
            draw.text(
                at, text, font=label.font, anchor=anchor, fill=tuple(int(c) for c in rgb),
                stroke_width=label.stroke, stroke_fill=(15, 15, 20),
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
