"""Study 2: float32 against float64, both against a 50-digit mpmath reference.

The core shades in float32 when given float32 arrays, else in float64. Both
are compared with the Phong model evaluated in 50-digit arithmetic
(:mod:`mpmath`) on the float64 inputs, so the float32 error includes storing
the scene in float32, as a float32 pipeline does. Four sets of points:

- ``ordinary``: points on a sphere facing the eye, α = 40 (the whole colour);
- ``alpha 1e6 near the highlight``: normals within 1.4e-3 rad of the
  highlight's, α = 10⁶ (the specular term);
- ``grazing light``: ``n·l`` from 1e-6 to 1e-3 (the diffuse term);
- ``far from the origin``: the ordinary scene moved to (1e4, 1e4, 1e4)
  (the whole colour).

The error is the relative error ``|x − x_ref| / |x_ref|`` of the term the
case stresses; the time is the time (fastest of the repeats) to shade a million such points,
and for mpmath the time per point times a million.
"""

from __future__ import annotations

import time

import numpy as np

from phonglab import core
from phonglab.accuracy.timing import interleaved_times

__all__ = ["CASES", "make_case", "phong_mp", "run"]

#: case name -> term whose error is reported
CASES = {
    "ordinary": "color",
    "alpha 1e6 near the highlight": "specular",
    "grazing light": "diffuse",
    "far from the origin": "color",
}

EYE = np.array([0.0, 0.0, 4.0])
LIGHT = np.array([2.0, 2.5, 3.0])
FAR = np.array([1e4, 1e4, 1e4])


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _facing_points(rng, count):
    """Points on the unit sphere that face both the eye and the light."""
    out = []
    while sum(len(o) for o in out) < count:
        p = _unit(rng.normal(size=(4 * count, 3)))
        ok = (np.einsum("ij,ij->i", p, _unit(EYE - p)) > 0.2) & (np.einsum("ij,ij->i", p, _unit(LIGHT - p)) > 0.2)
        out.append(p[ok])
    return np.concatenate(out)[:count]


def make_case(name: str, count: int, seed: int = 0) -> dict:
    """The points, normals, eye, light and material of one case (float64).

    Returns
    -------
    dict
        ``points``, ``normals`` (count, 3); ``eye``, ``light`` (3,);
        ``material`` (a core Material, scalar coefficients).
    """
    rng = np.random.default_rng(seed)
    p = _facing_points(rng, count)
    eye, light = EYE.copy(), LIGHT.copy()
    material = core.Material(ka=0.1, kd=0.6, ks=0.5, shininess=40.0)
    n = p.copy()
    if name == "alpha 1e6 near the highlight":
        # normals tilted from the highlight's normal h by 1e-6 .. 1.4e-3 rad
        h = _unit(_unit(light - p) + _unit(eye - p))
        side = _unit(np.cross(h, rng.normal(size=(count, 3))))
        eps = rng.uniform(1e-6, 1.4e-3, size=(count, 1))
        n = np.cos(eps) * h + np.sin(eps) * side
        material = core.Material(ka=0.0, kd=0.0, ks=1.0, shininess=1e6)
    elif name == "grazing light":
        # normals nearly perpendicular to l: n·l = sin δ, δ from 1e-6 to 1e-3
        l = _unit(light - p)
        perp = _unit(np.cross(l, rng.normal(size=(count, 3))))
        delta = np.exp(rng.uniform(np.log(1e-6), np.log(1e-3), size=(count, 1)))
        n = np.cos(delta) * perp + np.sin(delta) * l
        material = core.Material(ka=0.0, kd=1.0, ks=0.0, shininess=1.0)
    elif name == "far from the origin":
        p, eye, light = p + FAR, eye + FAR, light + FAR
    elif name != "ordinary":
        raise ValueError(f"case: must be one of {', '.join(CASES)}, got {name!r}")
    return {"points": p, "normals": n, "eye": eye, "light": light, "material": material}


def _lights(case):
    return (core.AmbientLight(intensity=1.0), core.PointLight(position=tuple(case["light"])))


def shade_case(case: dict, dtype) -> core.Shading:
    """Shade a case with the core in ``dtype`` (inputs stored in that dtype first)."""
    return core.shade(
        case["points"].astype(dtype),
        case["normals"].astype(dtype),
        material=case["material"],
        lights=_lights(case),
        eye=tuple(float(x) for x in np.asarray(case["eye"], dtype)),
    )


def phong_mp(point, normal, eye, light, material: core.Material, *, digits: int = 50) -> dict:
    """The Phong model at one point in ``digits``-digit arithmetic (first RGB channel).

    A white ambient light and a white point light of intensity 1, no
    attenuation. Returns ``{"diffuse", "specular", "color"}`` as mpmath numbers.
    """
    import mpmath

    with mpmath.workdps(digits):
        mpf = mpmath.mpf

        def vec(a):
            return [mpf(float(x)) for x in a]

        def sub(a, b):
            return [x - y for x, y in zip(a, b)]

        def dot(a, b):
            return sum(x * y for x, y in zip(a, b))

        def unit(a):
            size = mpmath.sqrt(dot(a, a))
            return [x / size for x in a]

        p, n = vec(point), unit(vec(normal))
        l = unit(sub(vec(light), p))
        v = unit(sub(vec(eye), p))
        nl = dot(n, l)
        r = [2 * nl * ni - li for ni, li in zip(n, l)]
        rv = dot(r, v)
        ka, kd, ks = mpf(material.ka[0]), mpf(material.kd[0]), mpf(material.ks[0])
        alpha = mpf(material.shininess)
        diffuse = kd * max(nl, 0)
        specular = ks * rv**alpha if (nl > 0 and rv > 0) else mpf(0)
        return {"diffuse": +diffuse, "specular": +specular, "color": ka + diffuse + specular}


def _tile(case: dict, count: int) -> dict:
    reps = -(-count // len(case["points"]))
    out = dict(case)
    out["points"] = np.tile(case["points"], (reps, 1))[:count]
    out["normals"] = np.tile(case["normals"], (reps, 1))[:count]
    return out


def run(*, points: int = 200, timed_points: int = 1_000_000, repeats: int = 3, progress=None) -> dict:
    """The precision study: errors of each case, times per million points.

    Parameters
    ----------
    points : int
        Points per case compared with the mpmath reference.
    timed_points : int
        Points shaded per timed call of the core.
    repeats : int
        Timed repeats (the fastest is reported).

    Returns
    -------
    dict
        ``rows``: one per (case, precision) with ``case``, ``term``,
        ``precision`` ("float32", "float64", "mpmath 50 digits"),
        ``max_rel_error``, ``median_rel_error`` and ``time_per_million`` (s).
    """
    rows = []
    for name, term in CASES.items():
        if progress:
            progress(f"precision: {name}")
        case = make_case(name, points)
        # the 50-digit reference, timed per point
        start = time.perf_counter()
        ref = np.array([
            float(phong_mp(p, n, case["eye"], case["light"], case["material"])[term])
            for p, n in zip(case["points"], case["normals"])
        ])
        mp_seconds = (time.perf_counter() - start) / len(ref)
        big = _tile(case, timed_points)
        seconds = interleaved_times({dtype: (lambda dtype=dtype: shade_case(big, dtype))
                                     for dtype in (np.float32, np.float64)}, repeats)
        for dtype in (np.float32, np.float64):
            value = getattr(shade_case(case, dtype), term)[:, 0].astype(np.float64)
            rel = np.abs(value - ref) / np.abs(ref)
            rows.append({
                "case": name, "term": term, "precision": np.dtype(dtype).name,
                "max_rel_error": float(rel.max()), "median_rel_error": float(np.median(rel)),
                "time_per_million": seconds[dtype] * 1e6 / timed_points,
            })
        rows.append({
            "case": name, "term": term, "precision": "mpmath 50 digits",
            "max_rel_error": 0.0, "median_rel_error": 0.0, "time_per_million": mp_seconds * 1e6,
        })
    return {
        "name": "precision",
        "title": "Precision: float32 and float64 against 50-digit arithmetic",
        "reference": (f"the Phong model in 50-digit mpmath on the float64 inputs, {points} points per case; "
                      "error = relative error of the term the case stresses"),
        "rows": rows,
    }
