"""Study 4: a finite-size light, exactly, as a point, and by Monte Carlo.

A 1 × 1 light panel hangs at height 1 facing down over a diffuse floor; the
irradiance is wanted on a grid of floor points spanning 3 × 3. The reference
is the exact closed form for a polygonal light (Lambert's formula,
:func:`phonglab.core.area.polygon_irradiance`). Against it:

- the point-light approximation at the panel's centre (one evaluation);
- Monte Carlo with ``N`` uniform samples on the panel, error ∝ ``N^{-1/2}``;
- Monte Carlo with one sample in each of ``N`` cells (stratified), whose
  error falls faster for this smooth integrand (about ``N^{-1}``).

The error is the relative RMS error over the floor points,
``‖E − E_ref‖₂ / ‖E_ref‖₂``, root-mean-squared over several seeds; the slope of
log error against log N is fitted by least squares and printed.
"""

from __future__ import annotations

import math

import numpy as np

from phonglab.accuracy.timing import best_time
from phonglab.core.area import AreaLight, area_irradiance

__all__ = ["LIGHT", "floor_points", "relative_error", "fit_slope", "run"]

#: the light of the study: a 1 x 1 panel at height 1, facing down (-z)
LIGHT = AreaLight(position=(0.0, 0.0, 1.0), edge_u=(1.0, 0.0, 0.0), edge_v=(0.0, -1.0, 0.0), intensity=1.0)


def floor_points(side: int) -> tuple[np.ndarray, np.ndarray]:
    """A ``side × side`` grid of floor points on [−1.5, 1.5]², normals +z."""
    s = np.linspace(-1.5, 1.5, side)
    x, y = np.meshgrid(s, s)
    points = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    return points, np.broadcast_to(np.array([0.0, 0.0, 1.0]), points.shape)


def relative_error(estimate, exact) -> float:
    """``‖estimate − exact‖₂ / ‖exact‖₂``."""
    return float(np.linalg.norm(estimate - exact) / np.linalg.norm(exact))


def fit_slope(samples, errors) -> float:
    """Least-squares slope of ``log(error)`` against ``log(samples)``."""
    x, y = np.log(np.asarray(samples, float)), np.log(np.asarray(errors, float))
    return float(np.polyfit(x, y, 1)[0])


def run(*, samples=(1, 4, 16, 64, 256, 1024, 4096), seeds: int = 4, side: int = 24,
        repeats: int = 3, progress=None) -> dict:
    """The finite-size light study.

    Parameters
    ----------
    samples : sequence of int
        Monte Carlo sample counts N per point.
    seeds : int
        Independent estimates averaged (RMS) per N.
    side : int
        The floor grid is side × side points.
    repeats : int
        Timed repeats of the exact and point evaluations.

    Returns
    -------
    dict
        ``rows`` with ``method``, ``samples``, ``error`` and ``time`` (s, the
        median over seeds or repeats), ``slopes`` (method -> fitted slope)
        and the exact form's ``reference_time``.
    """
    points, normals = floor_points(side)
    exact_time, exact = best_time(lambda: area_irradiance(LIGHT, points, normals, method="exact"), repeats)
    point_time, approx = best_time(lambda: area_irradiance(LIGHT, points, normals, method="point"), repeats)
    rows = [
        {"method": "exact", "samples": 0, "error": 0.0, "time": exact_time},
        {"method": "point", "samples": 1, "error": relative_error(approx, exact), "time": point_time},
    ]
    slopes = {}
    for method in ("uniform", "stratified"):
        errors = []
        for n in samples:
            if progress:
                progress(f"finite light: {method} Monte Carlo, N = {n}")
            seconds, errs = [], []
            for seed in range(seeds):
                t, estimate = best_time(
                    lambda: area_irradiance(LIGHT, points, normals, method=method, samples=n, seed=seed),
                    1, warmup=False)
                seconds.append(t)
                errs.append(relative_error(estimate, exact))
            error = math.sqrt(float(np.mean(np.square(errs))))
            errors.append(error)
            rows.append({"method": method, "samples": int(n), "error": error,
                         "time": float(np.median(seconds))})
        slopes[method] = fit_slope(samples, errors)
    return {
        "name": "area_light",
        "title": "Finite-size light: point approximation and Monte Carlo against the exact form",
        "reference": (f"Lambert's closed form for a 1x1 panel at height 1 over a {side}x{side} floor grid; "
                      f"error = relative RMS error, RMS over {seeds} seeds"),
        "reference_time": exact_time,
        "rows": rows,
        "slopes": slopes,
    }
