"""Study 3: Phong against Blinn-Phong, in time and in the highlight.

Cost: the time (fastest of the repeats) to shade a million points with each model, for a local
viewer with a point light (``l``, ``v`` and so ``h`` change at every point)
and for an infinite viewer with a directional light (``l`` and ``v`` are
constant, so Blinn-Phong's ``h`` is one vector for the whole image, while
Phong still reflects ``l`` about every normal).

Highlight: the specular term alone (``k_s = 1``) on the exact sphere, one
shade per pixel, for several shininesses α, in both setups. The reference is Phong with α;
Blinn-Phong with the same α has a wider highlight, with ``4α`` nearly the
same one. Where ``n``, ``l`` and ``v`` lie in one plane the angle between
``n`` and ``h`` is half the angle between ``r`` and ``v``, and for small
angles

.. math:: \\cos^{4\\alpha}(\\theta/2) \\approx e^{-4\\alpha\\theta^2/8}
          = e^{-\\alpha\\theta^2/2} \\approx \\cos^{\\alpha}\\theta ;

out of that plane the Blinn-Phong highlight is stretched, so the match is
close but not exact.
"""

from __future__ import annotations

import numpy as np

from phonglab import core
from phonglab.accuracy.raycast import View, camera_rays, hit_sphere
from phonglab.accuracy.timing import interleaved_times

__all__ = ["SETUPS", "run", "highlight"]

#: setup name -> (lights, viewer keywords)
SETUPS = {
    "local viewer, point light": (
        (core.PointLight(position=(2.0, 2.5, 3.0)),), {"eye": (0.0, 0.0, 4.0)}),
    "infinite viewer, directional light": (
        (core.DirectionalLight(direction=(2.0, 2.5, 3.0)),), {"view_direction": (0.0, 0.0, 1.0)}),
}


def highlight(alpha: float, model: str, *, size: int = 128, setup: str = "local viewer, point light") -> np.ndarray:
    """The specular term of the exact sphere (``k_s = 1``) per covered pixel."""
    points, normals, mask = hit_sphere(camera_rays(View(width=size, height=size)))
    lights, viewer = SETUPS[setup]
    material = core.Material(ka=0.0, kd=0.0, ks=1.0, shininess=alpha)
    return core.shade(points[mask], normals[mask], material=material, lights=lights, model=model,
                      **viewer).specular[:, 0]


def _sphere_points(count: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(count, 3))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    return p


def run(*, alphas=(10.0, 50.0, 200.0), size: int = 128, timed_points: int = 1_000_000,
        repeats: int = 3, progress=None) -> dict:
    """The Phong / Blinn-Phong study.

    Returns
    -------
    dict
        ``timing``: rows with ``setup``, ``model``, ``time_per_million`` (s)
        and ``ratio`` (Blinn-Phong over Phong);
        ``rows``: per setup, α and Blinn-Phong exponent (α or 4α), the
        ``max_diff`` and ``rms_diff`` of the specular term against Phong
        with α, and the ``time_per_million`` of Blinn-Phong in that setup.
    """
    points = _sphere_points(timed_points)
    material = core.Material(ka=0.1, kd=0.6, ks=0.5, shininess=50.0)
    timing = []
    for setup, (lights, viewer) in SETUPS.items():
        if progress:
            progress(f"phong vs blinn-phong: timing, {setup}")
        seconds = interleaved_times(
            {model: (lambda model=model: core.shade(points, points, material=material, lights=lights,
                                                    model=model, **viewer))
             for model in core.MODELS},
            repeats)
        for model in core.MODELS:
            timing.append({
                "setup": setup, "model": model,
                "time_per_million": seconds[model] * 1e6 / timed_points,
                "ratio": seconds[model] / seconds["phong"],
            })
    rows = []
    for setup in SETUPS:
        blinn_time = next(t["time_per_million"] for t in timing
                          if t["setup"] == setup and t["model"] == "blinn-phong")
        for alpha in alphas:
            if progress:
                progress(f"phong vs blinn-phong: highlight at shininess {alpha:g}, {setup}")
            phong = highlight(alpha, "phong", size=size, setup=setup)
            for factor in (1, 4):
                blinn = highlight(factor * alpha, "blinn-phong", size=size, setup=setup)
                diff = np.abs(blinn - phong)
                rows.append({
                    "setup": setup, "alpha": float(alpha), "blinn_exponent": "4a" if factor > 1 else "a",
                    "blinn_shininess": float(factor * alpha),
                    "max_diff": float(diff.max()), "rms_diff": float(np.sqrt(np.mean(diff**2))),
                    "time_per_million": blinn_time,
                })
    return {
        "name": "models",
        "title": "Phong against Blinn-Phong: cost and highlight",
        "reference": (f"Phong with shininess a, specular term only (k_s = 1) on the exact sphere, "
                      f"{size}x{size} pixels; times: {timed_points} points per call"),
        "timing": timing,
        "rows": rows,
    }
