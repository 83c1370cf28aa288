"""phonglab.accuracy: what each gain in accuracy costs in time, measured.

Four studies, each an error against a stated reference and a time measured
in the same run (the fastest of several repeats, after a warm-up):

1. :mod:`~phonglab.accuracy.interpolation`: flat, Gouraud and per-pixel
   shading of sphere meshes against the exact sphere;
2. :mod:`~phonglab.accuracy.precision`: float32 and float64 against 50-digit
   arithmetic, on ordinary points and hard cases;
3. :mod:`~phonglab.accuracy.models`: Phong against Blinn-Phong (cost, and the
   highlight with the 4α exponent relation);
4. :mod:`~phonglab.accuracy.arealight`: a finite-size light as a point and
   by Monte Carlo, against the exact closed form.

:func:`run_studies` runs all four; :func:`write_figure` draws them (error
against time, log–log); :func:`error_images` and :func:`accuracy_plot_png`
serve the "Accuracy costs time" lesson.
"""

from __future__ import annotations

from phonglab.accuracy.interpolation import ERROR_RANGE, ErrorView, error_images, error_scale_bar
from phonglab.accuracy.timing import Progress

__all__ = [
    "QUICK",
    "FULL",
    "run_studies",
    "write_figure",
    "accuracy_plot_png",
    "format_report",
    "error_images",
    "error_scale_bar",
    "ErrorView",
    "ERROR_RANGE",
]

#: settings of each study for ``--quick`` (a few seconds)
QUICK = {
    "interpolation": {"resolutions": (8, 16, 32, 64), "size": 96, "repeats": 5, "min_seconds": 0.01},
    "precision": {"points": 60, "timed_points": 200_000, "repeats": 3},
    "models": {"alphas": (10.0, 200.0), "size": 96, "timed_points": 200_000, "repeats": 3},
    "area_light": {"samples": (1, 4, 16, 64, 256, 1024), "seeds": 3, "side": 16, "repeats": 3},
}

#: settings of each study for the full run (about a minute)
FULL = {
    "interpolation": {"resolutions": (8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384), "size": 256,
                      "repeats": 7, "min_seconds": 0.02},
    "precision": {"points": 1000, "timed_points": 1_000_000, "repeats": 7},
    "models": {"alphas": (10.0, 50.0, 200.0, 1000.0), "size": 256, "timed_points": 1_000_000, "repeats": 7},
    "area_light": {"samples": (1, 4, 16, 64, 256, 1024, 4096, 16384), "seeds": 4, "side": 24,
                   "repeats": 7},
}


def run_studies(*, quick: bool = False, progress=None) -> dict:
    """Run the four studies.

    Parameters
    ----------
    quick : bool
        Smaller images, fewer resolutions, samples and repeats (:data:`QUICK`).
    progress : callable, optional
        Called with a one-line message as each step starts.

    Returns
    -------
    dict
        ``{"quick": bool, "studies": [interpolation, precision, models,
        area_light]}``, each study a JSON-ready dict with ``name``, ``title``,
        ``reference`` (what its errors are measured against) and ``rows``.
    """
    from phonglab.accuracy import arealight, interpolation, models, precision

    settings = QUICK if quick else FULL
    progress = progress or Progress(quiet=True)
    studies = [
        interpolation.run(**settings["interpolation"], progress=progress),
        precision.run(**settings["precision"], progress=progress),
        models.run(**settings["models"], progress=progress),
        arealight.run(**settings["area_light"], progress=progress),
    ]
    return {"quick": bool(quick), "studies": studies}


def write_figure(results: dict, path) -> str:
    """Draw the studies (error against time, log–log) to PNG, SVG or PDF; see :mod:`.figure`."""
    from phonglab.accuracy.figure import write_figure as _write

    return _write(results, path)


def accuracy_plot_png(path, *, results: dict | None = None) -> str:
    """Write the accuracy plot as a PNG file for the lesson.

    Parameters
    ----------
    path : str or Path
        Where to write; it must end in ``.png``. Written atomically.
    results : dict, optional
        From :func:`run_studies`; by default the quick studies are run
        (a few seconds).

    Returns
    -------
    str
        The path written.
    """
    if not str(path).lower().endswith(".png"):
        raise ValueError(f"path: must end in .png, got {str(path)!r}")
    if results is None:
        results = run_studies(quick=True)
    return write_figure(results, path)


def format_report(results: dict) -> str:
    """The studies as plain-text tables; see :mod:`.report`."""
    from phonglab.accuracy.report import format_report as _format

    return _format(results)
