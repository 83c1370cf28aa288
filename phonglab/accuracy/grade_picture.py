"""The graded exercise's picture: a student's shading of a sphere beside the core's, and their difference.

The sphere is ray-cast exactly (:mod:`phonglab.accuracy.raycast`); the core
shades every hit point and the student's ``shade`` runs on the same points
in its sandbox (:class:`phonglab.teaching.sandbox.Sandbox`), in batches with
a time limit each. ``phonglab grade --picture`` writes :func:`picture_png`
to a file; the page's "Your code" panel shows it.
"""

from __future__ import annotations

import math

__all__ = ["PICTURE_SIZE", "DIFFERENCE_RANGE", "CAPTION_HEIGHT", "SCALE_TOP", "SCALE_HEIGHT", "picture_scene",
           "sphere_images", "caption_lines", "difference_colours", "picture_png"]

#: the picture: a unit sphere seen from (0, 0, 4), lit from the front-right and,
#: to show the mistakes, from behind (no-clamp darkens the front, ungated glows on the rim)
PICTURE_SIZE = 96
#: how long one point may take in the picture's batches, on top of the per-case limit
PICTURE_SECONDS_PER_POINT = 0.01
PICTURE_BATCH = 256
#: the difference map's log scale: |difference| from the first to the second value
DIFFERENCE_RANGE = (1e-4, 1.0)
#: the picture's layout in pixels: each panel's side, the gap around panels, a caption line's height
PANEL = PICTURE_SIZE * 2
GAP = 8
LINE = 14
#: lines a panel's caption may take (a longer one wraps at spaces; past this it is cut with "…")
CAPTION_LINES = 2
#: the band above the panels that holds their captions
CAPTION_HEIGHT = CAPTION_LINES * LINE + 4
#: the difference map's colour scale under its panel: the bar's top (below the panels) and height, in pixels
SCALE_TOP = 4
SCALE_HEIGHT = 10
#: the band below the panels that holds the scale: its bar and a line of tick labels
SCALE_BAND = SCALE_TOP + SCALE_HEIGHT + 3 + LINE



def picture_scene():
    """The material, lights and view of the picture."""
    from phonglab import core as pl
    from phonglab.accuracy.raycast import View

    material = pl.Material(ka=(0.25, 0.3, 0.4), kd=(0.55, 0.6, 0.75), ks=0.6, shininess=30)
    lights = (pl.AmbientLight(intensity=0.3),
              pl.PointLight(position=(2.5, 2.0, 3.0)),
              pl.DirectionalLight(direction=(-0.6, 0.3, -1.0), color=(1.0, 0.8, 0.5), intensity=0.8))
    view = View(eye=(0.0, 0.0, 4.0), view_angle=32.0, width=PICTURE_SIZE, height=PICTURE_SIZE)
    return material, lights, view


def sphere_images(file, limits):
    """The core's and the student's sphere, (h, w, 3) float64 each, NaN where the student gave no colour.

    Returns ``core, student, mask, failures`` with ``failures`` the number of
    pixels the student's code gave no colour for.
    """
    import numpy as np

    from phonglab import core as pl
    from phonglab.accuracy.raycast import camera_rays, hit_sphere
    from phonglab.teaching.grading import encode_scene
    from phonglab.teaching.sandbox import Sandbox

    material, lights, view = picture_scene()
    points, normals, mask = hit_sphere(camera_rays(view))
    p, n = points[mask], normals[mask]
    core = np.full(points.shape, np.nan)
    core[mask] = pl.shade(p, n, material=material, lights=lights, eye=view.eye, model="phong").color
    colours = np.full(p.shape, np.nan)
    scene = encode_scene(material, lights)
    with Sandbox(file, limits) as box:
        for start in range(0, len(p), PICTURE_BATCH):
            stop = min(start + PICTURE_BATCH, len(p))
            limit = limits.time_limit + (stop - start) * PICTURE_SECONDS_PER_POINT
            for i, outcome in enumerate(box.evaluate(p[start:stop], n[start:stop], eye=view.eye,
                                                     scene=scene, time_limit=limit)):
                if outcome.value is not None:
                    colours[start + i] = outcome.value
    student = np.full(points.shape, np.nan)
    student[mask] = colours
    failures = int(np.sum(~np.all(np.isfinite(colours), axis=-1)))
    return core, student, mask, failures


def caption_lines(text: str, width: float, measure) -> list[str]:
    """``text`` in lines no wider than ``width`` (``measure(line)`` gives a line's width), broken at spaces.

    At most :data:`CAPTION_LINES` lines; what does not fit ends the last with "…".
    A word wider than ``width`` on its own keeps a line to itself.
    """
    lines: list[str] = []
    for word in text.split():
        if lines and measure(f"{lines[-1]} {word}") <= width:
            lines[-1] = f"{lines[-1]} {word}"
        else:
            lines.append(word)
    if len(lines) > CAPTION_LINES:
        last = " ".join(lines[CAPTION_LINES - 1:])
        while last and measure(last + "…") > width:
            last = last[:-1]
        lines = lines[:CAPTION_LINES - 1] + [last.rstrip() + "…"]
    return lines


def difference_colours(diff):
    """The difference map's colours (uint8 RGB) for ``|difference|`` values: inferno over :data:`DIFFERENCE_RANGE` in log scale."""
    import numpy as np
    from matplotlib import colormaps

    lo, hi = DIFFERENCE_RANGE
    t = (np.log10(np.maximum(diff, lo)) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))
    return np.round(colormaps["inferno"](np.clip(t, 0, 1))[..., :3] * 255).astype(np.uint8)


def picture_png(file, limits, *, encoding: str = "srgb", exposure: float = 1.0) -> tuple[bytes | None, str]:
    """``student | core | difference`` as PNG bytes, and a note on pixels without a colour.

    The two spheres are linear light through the display encoding
    (:func:`phonglab.accuracy.images.display_image`: exposure, clip, the sRGB
    curve by default or the raw values with ``encoding="linear"``); the
    difference is measured on linear light. Returns ``(None, reason)`` when
    a limit stopped the student's code before any picture.
    """
    import io

    import numpy as np
    from PIL import Image, ImageDraw, ImageFont

    from phonglab.accuracy.images import display_image
    from phonglab.teaching.sandbox import LoadError

    try:
        core, student, mask, failures = sphere_images(file, limits)
    except LoadError as exc:  # loaded for the grading, so only a limit can stop it here
        return None, f"no picture: {exc}"
    bad = mask & ~np.all(np.isfinite(student), axis=-1)

    def to_rgb(image):
        return display_image(image, mask, background=(26, 26, 30), encoding=encoding, exposure=exposure)

    diff = np.max(np.abs(np.nan_to_num(student - core, nan=0.0)), axis=-1)
    diff_rgb = difference_colours(diff)
    diff_rgb[~mask] = (128, 128, 136)
    student_rgb = to_rgb(student)
    for image in (student_rgb, diff_rgb):
        image[bad] = (255, 0, 255)  # no colour from the student: an error, NaN or time-out

    size, gap, caption = PANEL, GAP, CAPTION_HEIGHT
    canvas = Image.new("RGB", (3 * size + 4 * gap, size + caption + 2 * gap + SCALE_BAND), (255, 255, 255))
    draw = ImageDraw.Draw(canvas)
    try:
        font = ImageFont.load_default(size=12)
    except TypeError:  # Pillow < 10.1: the bitmap font only
        font = ImageFont.load_default()
    worst = float(diff[mask & ~bad].max()) if np.any(mask & ~bad) else 0.0
    lo_text, hi_text = (f"{v:g}" for v in DIFFERENCE_RANGE)
    labels = ("your shade()", "phonglab.shade", f"|difference| max {worst:.2g} (log scale {lo_text} to {hi_text})")
    for i, (image, label) in enumerate(zip((student_rgb, to_rgb(core), diff_rgb), labels)):
        x = gap + i * (size + gap)
        canvas.paste(Image.fromarray(image).resize((size, size), Image.NEAREST), (x, caption + gap))
        # each caption within its own panel's width, wrapped rather than cut at the picture's edge
        for row, line in enumerate(caption_lines(label, size, lambda t: draw.textlength(t, font=font))):
            draw.text((x, 3 + row * LINE), line, fill=(0, 0, 0), font=font)
    _draw_scale(canvas, draw, font, x=gap + 2 * (size + gap), y=caption + gap + size + SCALE_TOP, width=size)
    buffer = io.BytesIO()
    canvas.save(buffer, format="PNG")
    return buffer.getvalue(), (f"{failures} pixels without a colour, shown magenta" if failures else "")


def _draw_scale(canvas, draw, font, *, x: int, y: int, width: int) -> None:
    """The difference map's colour bar at ``(x, y)``, ``width`` wide, with its ends and middle labelled.

    The bar runs over :data:`DIFFERENCE_RANGE` in log scale, left to right,
    in the colours the map uses (:func:`difference_colours`).
    """
    import numpy as np
    from PIL import Image

    lo, hi = DIFFERENCE_RANGE
    values = 10.0 ** np.linspace(math.log10(lo), math.log10(hi), width)
    bar = np.repeat(difference_colours(values)[None, :, :], SCALE_HEIGHT, axis=0)
    canvas.paste(Image.fromarray(bar), (x, y))
    draw.rectangle((x - 1, y - 1, x + width, y + SCALE_HEIGHT), outline=(90, 90, 90))
    mid = 10.0 ** ((math.log10(lo) + math.log10(hi)) / 2)
    top = y + SCALE_HEIGHT + 3
    for value, tick in ((lo, x), (mid, x + width // 2), (hi, x + width - 1)):
        draw.line((tick, y + SCALE_HEIGHT, tick, y + SCALE_HEIGHT + 2), fill=(90, 90, 90))
        label = f"{value:g}"
        # the end labels stay under the bar, the middle one is centred on its tick
        left = min(max(tick - draw.textlength(label, font=font) / 2, x), x + width - draw.textlength(label, font=font))
        draw.text((left, top), label, fill=(0, 0, 0), font=font)
