"""``phonglab grade FILE.py``: grade a student's ``shade()`` against the core.

The file defines ``shade(point, normal, eye, material, lights)`` for one
point (the contract is in :mod:`phonglab.teaching.grading` and in the
starter that ``phonglab grade --template [PATH]`` writes). It runs in an
isolated worker process (:mod:`phonglab.teaching.sandbox`) on a fixed set of
cases in ten groups worth 100 points; the report shows, for every group,
passed or failed with its points, the worst case with its inputs, expected
and got, and the common mistake the wrong answers match.

``--json FILE`` also writes Gradescope's ``results.json``; ``--picture PNG``
(off by default) draws the student's shading of a sphere beside the core's
and the difference between them.

Exit status: 0 every case passes, 1 some fail, 2 the file cannot be loaded
(syntax error, import error, no ``shade``: the reason on one line) or bad
usage.
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

#: the picture: a unit sphere seen from (0, 0, 4), lit from the front-right and,
#: to show the mistakes, from behind (no-clamp darkens the front, ungated glows on the rim)
PICTURE_SIZE = 96
#: how long one point may take in the picture's batches, on top of the per-case limit
PICTURE_SECONDS_PER_POINT = 0.01
PICTURE_BATCH = 256
#: the difference map's log scale: |difference| from the first to the second value
DIFFERENCE_RANGE = (1e-4, 1.0)


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "grade",
        help="grade a student's shade() for one point against the core",
        description="Run FILE.py's shade(point, normal, eye, material, lights) on a fixed set of cases in an "
                    "isolated process and compare it with phonglab.shade (one-sided Phong, local viewer, "
                    "float64). Exit status: 0 all pass, 1 some fail, 2 the file cannot be loaded.",
    )
    parser.add_argument("file", nargs="?", metavar="FILE.py", help="the student's file")
    parser.add_argument("--template", nargs="?", const="shade.py", metavar="PATH",
                        help="write the starter file (default shade.py) and stop; never overwrites a file")
    parser.add_argument("--json", metavar="FILE", help="also write the results in Gradescope's results.json format")
    parser.add_argument("--picture", metavar="PNG",
                        help="also draw the student's sphere beside the core's and their difference (off by default)")
    parser.add_argument("--time-limit", type=float, default=2.0, metavar="SECONDS",
                        help="time limit per case (default 2)")
    parser.add_argument("--total-limit", type=float, default=120.0, metavar="SECONDS",
                        help="time limit for all cases together (default 120)")
    return parser


def run(args) -> int:
    from phonglab.cli import UsageError
    from phonglab.teaching import grading

    if args.template is not None:
        if args.file is not None:
            raise UsageError("give either FILE.py to grade or --template, not both")
        return _write_template(Path(args.template), grading.starter_text())
    if args.file is None:
        raise UsageError("give FILE.py to grade, or --template [PATH] for a starter file")
    for name in ("time_limit", "total_limit"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            raise UsageError(f"--{name.replace('_', '-')}: must be a number of seconds > 0, got {value:g}")
    limits = grading.Limits(time_limit=args.time_limit, total_limit=args.total_limit)

    started = time.monotonic()
    try:
        report = grading.grade_file(args.file, limits)
    except grading.LoadError as exc:
        reason = " ".join(str(exc).split())
        print(f"phonglab grade: cannot load {args.file}: {reason}", file=sys.stderr)
        if args.json:
            _write_json(args.json, grading.gradescope_results(None, load_error=reason,
                                                              execution_time=time.monotonic() - started))
        return 2
    print(grading.format_report(report))
    if args.json:
        _write_json(args.json, grading.gradescope_results(report, execution_time=time.monotonic() - started))
        print(f"wrote {args.json}")
    if args.picture:
        note = _write_picture(args.picture, args.file, limits)
        print(f"wrote {args.picture}" + (f" ({note})" if note else ""))
    return 0 if report.passed else 1


def _write_template(path: Path, text: str) -> int:
    from phonglab.cli import UsageError

    try:
        with open(path, "x", encoding="utf-8") as f:  # "x": refuse to overwrite
            f.write(text)
    except FileExistsError:
        raise UsageError(f"{path} exists: not overwritten (give another PATH)") from None
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None
    print(f"wrote {path}: fill in shade(), then run `phonglab grade {path}`")
    return 0


def _write_atomically(path, data: bytes) -> None:
    """Write ``data`` to a temporary file beside ``path``, then rename it: whole or not at all."""
    from phonglab.cli import UsageError

    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=path.suffix, dir=path.resolve().parent)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.chmod(tmp, 0o644)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None


def _write_json(path, results: dict) -> None:
    _write_atomically(path, (json.dumps(results, indent=2, ensure_ascii=False) + "\n").encode("utf-8"))


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


def _write_picture(png, file, limits) -> str:
    """Draw ``student | core | difference`` into ``png``; a note on pixels without a colour."""
    import io

    import numpy as np
    from matplotlib import colormaps
    from PIL import Image, ImageDraw, ImageFont

    from phonglab.teaching.sandbox import LoadError

    try:
        core, student, mask, failures = sphere_images(file, limits)
    except LoadError as exc:  # loaded for the grading, so only a limit can stop it here
        return f"no picture: {exc}"
    bad = mask & ~np.all(np.isfinite(student), axis=-1)

    def to_rgb(image):
        out = np.round(np.clip(np.nan_to_num(image, nan=0.0), 0, 1) * 255).astype(np.uint8)
        out[~mask] = (26, 26, 30)
        return out

    lo, hi = DIFFERENCE_RANGE
    diff = np.max(np.abs(np.nan_to_num(student - core, nan=0.0)), axis=-1)
    t = (np.log10(np.maximum(diff, lo)) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))
    diff_rgb = np.round(colormaps["inferno"](np.clip(t, 0, 1))[..., :3] * 255).astype(np.uint8)
    diff_rgb[~mask] = (128, 128, 136)
    student_rgb = to_rgb(student)
    for image in (student_rgb, diff_rgb):
        image[bad] = (255, 0, 255)  # no colour from the student: an error, NaN or time-out

    size, gap, caption = PICTURE_SIZE * 2, 8, 18
    canvas = Image.new("RGB", (3 * size + 4 * gap, size + caption + 2 * gap), (255, 255, 255))
    draw = ImageDraw.Draw(canvas)
    try:
        font = ImageFont.load_default(size=12)
    except TypeError:  # Pillow < 10.1: the bitmap font only
        font = ImageFont.load_default()
    worst = float(diff[mask & ~bad].max()) if np.any(mask & ~bad) else 0.0
    labels = ("your shade()", "phonglab.shade", f"|difference| max {worst:.2g} (log 1e-4..1)")
    for i, (image, label) in enumerate(zip((student_rgb, to_rgb(core), diff_rgb), labels)):
        x = gap + i * (size + gap)
        canvas.paste(Image.fromarray(image).resize((size, size), Image.NEAREST), (x, caption + gap))
        draw.text((x, 3), label, fill=(0, 0, 0), font=font)
    buffer = io.BytesIO()
    canvas.save(buffer, format="PNG")
    _write_atomically(png, buffer.getvalue())
    return f"{failures} pixels without a colour, shown magenta" if failures else ""
