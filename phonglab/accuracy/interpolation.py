"""Study 1: flat, Gouraud and per-pixel shading of a sphere against the exact sphere.

The scene is a unit sphere with a tight highlight (α = 200) seen by the
default camera. The *reference* shades, at every pixel, the point where the
pixel's ray meets the exact sphere, with the exact normal, in float64. Each
method shades the triangle mesh the app shows at a given resolution
(:func:`phonglab.render.mesh.build_mesh`), seen through the same pixels
(:mod:`phonglab.accuracy.raycast` finds the triangle and the barycentric
weights of each pixel's hit):

- ``flat``: one shade per triangle, at its centroid with its face normal;
- ``gouraud``: one shade per vertex, colours blended with the weights;
- ``pixel``: normals blended with the weights, one shade per pixel.

Errors are differences of the unclamped RGB colour, over the pixels both the
mesh and the sphere cover. Times are the shading work of each method only
(shade calls and blending): which triangle a pixel sees is found once and not
timed, since a rasterizer does that for every method alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from phonglab import core
from phonglab.accuracy.images import display_image
from phonglab.accuracy.raycast import View, camera_rays, hit_mesh, hit_sphere
from phonglab.accuracy.timing import best_time, interleaved_times

__all__ = [
    "METHODS",
    "Setup",
    "default_setup",
    "reference",
    "prepare",
    "shade_method",
    "measure",
    "ErrorView",
    "error_images",
    "false_colour",
    "error_scale_bar",
    "ERROR_RANGE",
]

#: interpolation methods, cheapest first
METHODS = ("flat", "gouraud", "pixel")

#: the error images' colour scale: log10 of |error| from the first to the second value
ERROR_RANGE = (1e-4, 1.0)

#: pixels not covered by the surface in the rendered images (RGB, 0-255)
BACKGROUND = (26, 26, 30)

#: pixels without an error value in the error image: a grey that the colour
#: map never uses, so a zero error (black) stands out from it
ERROR_BACKGROUND = (128, 128, 136)

#: a pixel belongs to the highlight where the reference's specular term is at
#: least this fraction of its peak
HIGHLIGHT_FRACTION = 0.1
#: the error images' side in pixels, as the page's accuracy panel shows them and lesson claims
#: measure them: the error at one pixel (the peak) moves with the pixel grid (0.06 to 0.14 for
#: per-pixel shading of 16 segments between 128 and 320 pixels), so the two must share one grid
ERROR_IMAGE_SIZE = 256


@dataclass(frozen=True)
class Setup:
    """Material, lights and camera of the study."""

    material: core.Material
    lights: tuple
    view: View = field(default_factory=View)


def default_setup(size: int = 128, shininess: float = 200.0) -> Setup:
    """The study's scene: a red plastic sphere with a tight white highlight (α = 200)."""
    return Setup(
        material=core.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.8, shininess=shininess),
        lights=(core.AmbientLight(intensity=0.2), core.PointLight(position=(2.0, 2.5, 3.0))),
        view=View(width=size, height=size),
    )


def _shade(setup: Setup, points, normals) -> core.Shading:
    return core.shade(points, normals, material=setup.material, lights=setup.lights, eye=setup.view.eye)


@dataclass(frozen=True)
class Reference:
    """The exact sphere seen through every pixel, shaded in float64.

    ``color`` and ``specular`` are (height, width, 3), NaN where the ray
    misses the sphere; ``peak`` is the (row, col) of the highlight's
    brightest pixel and ``highlight`` the pixels of the highlight.
    """

    color: np.ndarray
    specular: np.ndarray
    mask: np.ndarray
    peak: tuple[int, int]
    highlight: np.ndarray
    time: float


def reference_work(setup: Setup):
    """The reference's timed work, a function of no arguments, and the pixels it shades.

    Returns ``(fn, points, normals, mask)``: ``fn()`` shades the exact
    sphere's hit points (the part :func:`reference` times); finding them is
    not timed, as for the meshes.
    """
    points, normals, mask = hit_sphere(camera_rays(setup.view))
    p, n = points[mask], normals[mask]
    return (lambda: _shade(setup, p, n)), points, normals, mask


def reference(setup: Setup, *, repeats: int = 3, seconds: float | None = None) -> Reference:
    """Shade the exact sphere at every pixel (the reference of this study).

    ``seconds``, when given, is its time already measured (in turns with the
    methods, :func:`run`); otherwise it is timed here (warm-up, fastest of
    ``repeats``).
    """
    work, points, normals, mask = reference_work(setup)
    if seconds is None:
        seconds, s = best_time(work, repeats)
    else:
        s = work()
    color = np.full(points.shape, np.nan)
    specular = np.full(points.shape, np.nan)
    color[mask], specular[mask] = s.color, s.specular
    spec = np.where(mask, specular.sum(axis=-1), -np.inf)
    peak = np.unravel_index(int(np.argmax(spec)), mask.shape)
    highlight = mask & (spec >= HIGHLIGHT_FRACTION * spec[peak])
    return Reference(color, specular, mask, (int(peak[0]), int(peak[1])), highlight, seconds)


@dataclass(frozen=True)
class Prepared:
    """A sphere mesh at one resolution and what each pixel sees of it (untimed)."""

    resolution: int
    points: np.ndarray  # (V, 3) float64
    normals: np.ndarray  # (V, 3) float64, unit
    triangles: np.ndarray  # (T, 3)
    centroids: np.ndarray  # (T, 3) float64
    face_normals: np.ndarray  # (T, 3) float64
    mask: np.ndarray  # (height, width): pixels the mesh covers
    triangle: np.ndarray  # (n_hit,) triangle seen by each covered pixel
    weights: np.ndarray  # (n_hit, 3) barycentric weights

    @property
    def n_vertices(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_triangles(self) -> int:
        return int(self.triangles.shape[0])


def prepare(setup: Setup, resolution: int) -> Prepared:
    """Build the app's sphere mesh at ``resolution`` and cast the pixel rays at it."""
    from phonglab.render.mesh import build_mesh, face_centroids_normals, triangles
    from phonglab.scene import Geometry

    mesh = build_mesh(Geometry(kind="sphere", resolution=int(resolution)))
    tri = triangles(mesh)
    centroids, face_normals = face_centroids_normals(mesh)
    points = np.asarray(mesh.points, dtype=np.float64)
    centroids = np.asarray(centroids, dtype=np.float64)
    face_normals = np.asarray(face_normals, dtype=np.float64)
    # the sphere is closed: only triangles facing the eye can be seen first
    facing = np.flatnonzero(np.einsum("ij,ij->i", centroids - np.asarray(setup.view.eye), face_normals) < 0)
    hits = hit_mesh(setup.view, points, tri[facing])
    return Prepared(
        resolution=int(resolution),
        points=points,
        normals=np.asarray(mesh.point_data["Normals"], dtype=np.float64),
        triangles=tri,
        centroids=centroids,
        face_normals=face_normals,
        mask=hits.mask,
        triangle=facing[hits.triangle],
        weights=hits.weights,
    )


def _blend(values, prep: Prepared):
    """Barycentric blend of per-vertex ``values`` (V, 3) at every covered pixel."""
    corners = prep.triangles[prep.triangle]  # (n_hit, 3)
    w = prep.weights
    return w[:, 0:1] * values[corners[:, 0]] + w[:, 1:2] * values[corners[:, 1]] + w[:, 2:3] * values[corners[:, 2]]


def shade_method(setup: Setup, prep: Prepared, method: str) -> np.ndarray:
    """The colours of the covered pixels (n_hit, 3) under one interpolation method."""
    if method == "flat":
        per_face = _shade(setup, prep.centroids, prep.face_normals).color
        return per_face[prep.triangle]
    if method == "gouraud":
        per_vertex = _shade(setup, prep.points, prep.normals).color
        return _blend(per_vertex, prep)
    if method == "pixel":
        # normals blended then renormalised by the core: Phong shading
        return _shade(setup, _blend(prep.points, prep), _blend(prep.normals, prep)).color
    raise ValueError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")


def _image(mask, values) -> np.ndarray:
    out = np.full(mask.shape + (3,), np.nan)
    out[mask] = values
    return out


def errors(ref: Reference, image: np.ndarray, mask: np.ndarray) -> dict:
    """RMSE, maximum error, highlight RMSE and highlight peak error of an image.

    Over the pixels covered by both the image (``mask``) and the reference;
    errors are absolute differences of the RGB colour.
    """
    both = mask & ref.mask
    diff = np.abs(image[both] - ref.color[both])
    highlight = both & ref.highlight
    hdiff = np.abs(image[highlight] - ref.color[highlight])
    row, col = ref.peak
    peak = float(np.max(np.abs(image[row, col] - ref.color[row, col]))) if both[row, col] else math.nan
    return {
        "rmse": float(np.sqrt(np.mean(diff**2))) if diff.size else math.nan,
        "max_error": float(diff.max()) if diff.size else math.nan,
        "highlight_rmse": float(np.sqrt(np.mean(hdiff**2))) if hdiff.size else math.nan,
        "peak_error": peak,
        "pixels": int(both.sum()),
    }


def measure(setup: Setup, ref: Reference, prep: Prepared, method: str, *, repeats: int = 3,
            seconds: float | None = None):
    """One row of the study: the errors and time (fastest of the repeats) of ``method`` on ``prep``.

    ``seconds``, when given, is a time already measured for this method
    (:func:`run` times the three methods in turn); otherwise it is timed here.

    Returns
    -------
    row : dict
        ``method``, ``resolution``, ``vertices``, ``triangles``, ``shades``
        (shade evaluations), ``time`` (s), and the keys of :func:`errors`.
    image : ndarray, (height, width, 3)
        The rendered colours (NaN where the mesh is not seen).
    """
    if seconds is None:
        seconds, colours = best_time(lambda: shade_method(setup, prep, method), repeats)
    else:
        colours = shade_method(setup, prep, method)
    image = _image(prep.mask, colours)
    shades = {"flat": prep.n_triangles, "gouraud": prep.n_vertices, "pixel": int(prep.mask.sum())}[method]
    row = {
        "method": method,
        "resolution": prep.resolution,
        "vertices": prep.n_vertices,
        "triangles": prep.n_triangles,
        "shades": shades,
        "time": seconds,
        **errors(ref, image, prep.mask),
    }
    return row, image


def run(resolutions, *, size: int = 128, repeats: int = 3, min_seconds: float = 0.005, progress=None) -> dict:
    """The interpolation study at the given mesh resolutions.

    Every case (each method at each resolution, and the exact sphere) is
    warmed up before any is timed, then timed in turns, one sample of each
    per round (:func:`~phonglab.accuracy.timing.interleaved_times`): a busy
    start (imports, a first render elsewhere on the machine) would otherwise
    fall on the first resolution timed and make the coarsest mesh look the
    slowest. Each timed sample loops the method for at least
    ``min_seconds``; the fastest of ``repeats`` samples is reported.

    Returns
    -------
    dict
        ``reference`` (what the errors are against, and its time), ``rows``
        (one per method and resolution, see :func:`measure`).
    """
    setup = default_setup(size)
    preps = []
    for resolution in resolutions:
        if progress:
            progress(f"interpolation: sphere mesh at resolution {resolution}")
        preps.append(prepare(setup, resolution))
    if progress:
        progress(f"interpolation: timing {3 * len(preps) + 1} cases in turns, fastest of {repeats}")
    work = {"reference": reference_work(setup)[0]}
    for prep in preps:
        for m in METHODS:
            work[(m, prep.resolution)] = lambda m=m, prep=prep: shade_method(setup, prep, m)
    times = interleaved_times(work, repeats, min_seconds=min_seconds)
    ref = reference(setup, seconds=times["reference"])
    rows = []
    for prep in preps:
        for method in METHODS:
            rows.append(measure(setup, ref, prep, method, seconds=times[(method, prep.resolution)])[0])
    return {
        "name": "interpolation",
        "title": "Interpolation: flat, Gouraud and per-pixel shading of a sphere mesh",
        "reference": (f"the exact sphere shaded per pixel (exact normals, float64), "
                      f"{size}x{size} pixels, shininess {setup.material.shininess:g}"),
        "reference_time": ref.time,
        "repeats": int(repeats),
        "rows": rows,
    }


# ---------------------------------------------------------------------------
# images for the lesson


def _to_uint8(image, mask, encoding: str = "srgb", exposure: float = 1.0) -> np.ndarray:
    """Linear radiance as the display shows it (:func:`~phonglab.accuracy.images.display_image`)."""
    return display_image(image, mask, background=BACKGROUND, encoding=encoding, exposure=exposure)


def false_colour(error, mask, *, lo: float = ERROR_RANGE[0], hi: float = ERROR_RANGE[1]) -> np.ndarray:
    """Map per-pixel errors to RGB with a log scale and the "inferno" colour map.

    ``lo`` and below are black, ``hi`` and above bright yellow; pixels
    outside ``mask`` are grey (:data:`ERROR_BACKGROUND`).
    """
    from matplotlib import colormaps

    e = np.where(mask, error, lo)
    t = (np.log10(np.maximum(e, lo)) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))
    rgba = colormaps["inferno"](np.clip(t, 0.0, 1.0))
    out = np.round(rgba[..., :3] * 255).astype(np.uint8)
    out[~mask] = ERROR_BACKGROUND
    return out


def error_scale_bar(width: int = 256, height: int = 12) -> np.ndarray:
    """The error images' colour scale as a (height, width, 3) uint8 strip.

    The left edge is ``ERROR_RANGE[0]``, the right edge ``ERROR_RANGE[1]``,
    logarithmic in between (one decade per quarter of the width for the
    default range 1e-4 .. 1).
    """
    lo, hi = ERROR_RANGE
    errors = np.logspace(math.log10(lo), math.log10(hi), width)
    row = false_colour(errors, np.ones(width, dtype=bool))
    return np.repeat(row[None], height, axis=0)


@dataclass(frozen=True)
class ErrorView:
    """A render, its reference and the false-coloured difference, for display.

    Attributes
    ----------
    method : str
    resolution : int
    render, reference, error : ndarray, (height, width, 3), uint8 RGB
        The method's image, the exact sphere's image (linear colours
        through the display encoding: exposure, clip, sRGB by default) and
        ``max over RGB |render − reference|`` coloured on a log scale over
        ``error_range`` (see :func:`false_colour`); pixels seen by only one
        of the two (at the silhouette) or by neither are grey.
    error_range : (float, float)
        The errors shown as the darkest and the brightest colour.
    rmse, max_error, highlight_rmse, peak_error : float
        As in :func:`errors`, on the unclamped colours.
    time : float
        Seconds of the method's shading work, the fastest of ``repeats``.
    reference_time : float
        Seconds of shading the reference, timed in turns with the method.
    repeats : int
        How many samples each time is the fastest of (after the untimed warm-ups).
    """

    method: str
    resolution: int
    render: np.ndarray
    reference: np.ndarray
    error: np.ndarray
    error_range: tuple[float, float]
    rmse: float
    max_error: float
    highlight_rmse: float
    peak_error: float
    time: float
    reference_time: float
    repeats: int = 1


#: timed samples of each pick's method and exact sphere (the panel says "fastest of 5"); with the
#: warm-ups about 15 shading runs of a 256-pixel image each, well under a second in all
PANEL_REPEATS = 5


def error_images(method: str, resolution: int, *, size: int = 256, shininess: float = 200.0,
                 repeats: int = PANEL_REPEATS, encoding: str = "srgb", exposure: float = 1.0) -> ErrorView:
    """Render the sphere with one method and compare it with the exact sphere.

    Parameters
    ----------
    method : {"flat", "gouraud", "pixel"}
    resolution : int
        The sphere mesh's resolution (segments around), 3 to 1024.
    size : int
        Width and height of the images in pixels, 16 to 1024.
    shininess : float
        The material's α (>= 0); the rest of the scene is the study's
        (lesson 11's front matter).
    repeats : int
        Timed samples of the method and of the exact sphere, taken in turns
        after untimed warm-ups of both; the fastest of each is reported.
    encoding : {"srgb", "linear"}
        The display encoding of the render and reference images (a scene's
        ``display``); the errors are measured on linear light either way.
    exposure : float > 0
        The images' exposure (a scene's ``exposure``).

    Returns
    -------
    ErrorView

    Examples
    --------
    >>> view = error_images("gouraud", 16, size=32, repeats=1)
    >>> view.render.shape, view.error.dtype.name
    ((32, 32, 3), 'uint8')
    """
    if method not in METHODS:
        raise ValueError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or not 3 <= resolution <= 1024:
        raise ValueError(f"resolution: must be a whole number from 3 to 1024, got {resolution!r}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 16 <= size <= 1024:
        raise ValueError(f"size: must be a whole number from 16 to 1024, got {size!r}")
    try:
        setup = default_setup(int(size), shininess)
    except core.InvalidValue:
        raise ValueError(f"shininess: must be a finite number >= 0, got {shininess!r}") from None
    if encoding not in ("srgb", "linear"):
        raise ValueError(f"encoding: must be srgb or linear, got {encoding!r}")
    if isinstance(exposure, bool) or not isinstance(exposure, (int, float)) or not 0 < exposure < math.inf:
        raise ValueError(f"exposure: must be a finite number > 0, got {exposure!r}")
    prep = prepare(setup, int(resolution))
    # the method and the exact sphere are warmed up, then timed in turns: a busy moment of the
    # machine (another tab's study) lands on both, so the two times of one pick compare fairly
    times = interleaved_times({"method": lambda: shade_method(setup, prep, method),
                               "reference": reference_work(setup)[0]}, repeats)
    ref = reference(setup, seconds=times["reference"])
    row, image = measure(setup, ref, prep, method, seconds=times["method"])
    both = prep.mask & ref.mask
    diff = np.max(np.abs(np.nan_to_num(image) - np.nan_to_num(ref.color)), axis=-1)
    return ErrorView(
        method=method,
        resolution=int(resolution),
        render=_to_uint8(image, prep.mask, encoding, exposure),
        reference=_to_uint8(ref.color, ref.mask, encoding, exposure),
        error=false_colour(diff, both),
        error_range=ERROR_RANGE,
        rmse=row["rmse"],
        max_error=row["max_error"],
        highlight_rmse=row["highlight_rmse"],
        peak_error=row["peak_error"],
        time=row["time"],
        reference_time=ref.time,
        repeats=max(1, int(repeats)),
    )
