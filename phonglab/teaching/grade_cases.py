"""The graded exercise's cases: what each group tests, at which tolerance, for how many points.

Every case is one surface point: ``point``, ``normal``, ``eye``, a material
and a list of lights. The expected colour is not stored: it is
:func:`phonglab.core.shade` of those inputs (one-sided Phong, a local viewer
at ``eye``, float64), computed when the student is graded.

A case passes when every channel of the student's colour is within
``atol + rtol·|expected|`` of the expected one. Each group's tolerance is
justified next to it: a float64 evaluation of the model makes a few dozen
roundings of relative size ``u = 2⁻⁵³ ≈ 1.1e-16`` each, so any sound order of
operations lands within about ``1e-14`` of the core, except where the
shininess ``α`` amplifies the rounding of ``r·v``: ``δ(c^α)/c^α ≈ α·δc``.
Every mistake the grader diagnoses moves the result by ``1e-3`` or more.

The directions in the comments follow the package convention: ``n`` the
normal, ``l`` towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phonglab import core as pl

__all__ = ["Case", "Group", "GROUPS", "frame"]


@dataclass(frozen=True)
class Case:
    """One point to shade: the inputs of the student's ``shade`` and what it tests."""

    what: str
    point: tuple[float, float, float]
    normal: tuple[float, float, float]
    eye: tuple[float, float, float]
    material: pl.Material
    lights: tuple


@dataclass(frozen=True)
class Group:
    """Cases that test one part of the model, worth ``points`` together.

    A group's score is ``points × passed / len(cases)``.
    """

    key: str
    title: str
    points: float
    rtol: float
    atol: float
    why: str  # the tolerance's justification, printed in the report's notes
    cases: tuple[Case, ...]


def _t(v) -> tuple[float, float, float]:
    return tuple(float(x) for x in v)


def frame(normal, tangent_hint=(1.0, 0.0, 0.0)):
    """Unit ``n`` and a unit tangent ``t`` ⟂ ``n`` (Gram–Schmidt of the hint)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    t = np.asarray(tangent_hint, float)
    t = t - (t @ n) * n
    return n, t / np.linalg.norm(t)


def _towards(p, n, t, degrees, distance):
    """The point at ``distance`` from ``p`` in the plane of ``n`` and ``t``, ``degrees`` from ``n`` towards ``t``."""
    a = math.radians(degrees)
    return _t(np.asarray(p) + distance * (math.cos(a) * n + math.sin(a) * t))


# materials the groups share
PLASTIC = pl.Material(ka=0.1, kd=0.6, ks=0.4, shininess=20)
MATTE = pl.Material(ka=(0.2, 0.3, 0.4), kd=(0.7, 0.5, 0.3), ks=0.0, shininess=1)
SHINY = pl.Material(ka=0.05, kd=0.3, ks=(0.9, 0.8, 0.7), shininess=50, emission=(0.02, 0.0, 0.01))
AMB = pl.AmbientLight(intensity=0.25)
UP, ORIGIN = (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
TILTED = _t(np.array([0.36, 0.48, 0.8]))  # a unit normal off every axis
OFF = (0.5, -1.0, 2.0)  # a point off the origin


def _ambient() -> tuple[Case, ...]:
    m = pl.Material(ka=(0.2, 0.4, 0.6), kd=0.5, ks=0.5, shininess=10)
    eye = (0.0, 0.0, 5.0)
    return (
        Case("one ambient light: ka ∘ Ia", ORIGIN, UP, eye, m, (pl.AmbientLight(intensity=0.5),)),
        Case("two coloured ambient lights add up", OFF, TILTED, eye, m,
             (pl.AmbientLight(color=(1, 0.5, 0), intensity=0.4), pl.AmbientLight(color=(0, 0.5, 1), intensity=0.8))),
        Case("emission is added as it is", ORIGIN, UP, eye,
             pl.Material(ka=(0.2, 0.4, 0.6), kd=0.5, ks=0.5, shininess=10, emission=(0.05, 0.1, 0.0)),
             (pl.AmbientLight(intensity=0.5),)),
        Case("no ambient light: only the emission", ORIGIN, UP, eye,
             pl.Material(ka=0.9, kd=0, ks=0, shininess=1, emission=(0.3, 0.2, 0.1)), ()),
        Case("ambient_rgb uses the light's colour, not its diffuse colour", ORIGIN, UP, eye, m,
             (pl.AmbientLight(color=(0.5, 1, 1), diffuse=(1, 0, 0), specular=(0, 0, 1), intensity=0.6),)),
        Case("a point light adds no ambient light", ORIGIN, UP, eye, m,
             (pl.AmbientLight(intensity=0.3),
              pl.PointLight(position=(0, 0, 3), color=(1, 1, 1), diffuse=(0, 0, 0), specular=(0, 0, 0)))),
    )


def _diffuse() -> tuple[Case, ...]:
    eye = (0.0, 0.0, 5.0)
    n, t = frame(TILTED)
    return (
        Case("light straight above: n·l = 1", ORIGIN, UP, eye, MATTE, (AMB, pl.PointLight(position=(0, 0, 3)))),
        Case("light 60° from the normal: n·l = 1/2", ORIGIN, UP, eye, MATTE,
             (AMB, _point(_towards(ORIGIN, np.array(UP), np.array([1.0, 0, 0]), 60, 2.5)))),
        Case("tilted normal, point off the origin", OFF, TILTED, _towards(OFF, n, t, 10, 4), MATTE,
             (AMB, _point(_towards(OFF, n, t, -35, 3)))),
        Case("light behind the surface: n·l < 0 adds nothing", ORIGIN, UP, eye, MATTE,
             (AMB, pl.PointLight(position=(1, 0.5, -2)))),
        Case("light straight behind: n·l = −1", OFF, TILTED, _towards(OFF, n, t, 20, 4), MATTE,
             (AMB, _point(_t(np.asarray(OFF) - 3 * n)))),
        Case("light in the tangent plane: n·l = 0", ORIGIN, UP, eye, MATTE, (AMB, pl.PointLight(position=(3, 0, 0)))),
        Case("coloured light on a coloured surface", ORIGIN, UP, eye, MATTE,
             (pl.PointLight(position=(1, 1, 2), color=(1.0, 0.8, 0.2), intensity=1.5),)),
        Case("a lit light and one behind: the one behind subtracts nothing", OFF, TILTED,
             _towards(OFF, n, t, 0, 4), MATTE,
             (_point(_towards(OFF, n, t, 40, 3)), _point(_towards(OFF, n, t, 130, 3)))),
    )


def _point(position, **kwargs):
    return pl.PointLight(position=position, **kwargs)


def _specular() -> tuple[Case, ...]:
    ex = np.array([1.0, 0, 0])
    z = np.array(UP)
    m = pl.Material(ka=0.1, kd=0.3, ks=0.6, shininess=10)
    # with the light behind (n·l < 0), r = 2(n·l)n − l still points somewhere: an eye there must see no highlight
    behind = _towards(ORIGIN, z, ex, 135, 3)  # l 135° from n
    r_behind = _towards(ORIGIN, z, -ex, 135, 4)  # the eye along r = 2(n·l)n − l
    grazing_behind = _towards(ORIGIN, z, ex, 95, 3)  # n·l ≈ −0.087
    above_r = _towards(ORIGIN, z, -ex, 80, 5)  # an eye above the surface with r·v > 0
    return (
        Case("eye on the mirror direction: full highlight", ORIGIN, UP, _towards(ORIGIN, z, -ex, 45, 4), m,
             (_point(_towards(ORIGIN, z, ex, 45, 3)),)),
        Case("eye 8° off the mirror direction", ORIGIN, UP, _towards(ORIGIN, z, -ex, 53, 4), m,
             (_point(_towards(ORIGIN, z, ex, 45, 3)),)),
        Case("eye low on the light's side: r·v < 0, no highlight", ORIGIN, UP, _towards(ORIGIN, z, ex, 85, 4), m,
             (_point(_towards(ORIGIN, z, ex, 10, 3)),)),
        Case("light behind, eye along r: the n·l gate gives no highlight", ORIGIN, UP, r_behind, m,
             (AMB, _point(behind))),
        Case("light behind, eye near r, α = 5", ORIGIN, UP, _towards(ORIGIN, z, -ex, 125, 4),
             pl.Material(ka=0.1, kd=0.3, ks=0.6, shininess=5), (AMB, _point(behind))),
        Case("light just behind, eye above the surface with r·v > 0", ORIGIN, UP, above_r, m,
             (AMB, _point(grazing_behind))),
        Case("coloured specular light and ks", OFF, TILTED, _mirror_eye(OFF, TILTED, 30, 4, off=5), SHINY,
             (_point(_towards(OFF, *frame(TILTED), 30, 3), specular=(1.0, 0.5, 0.2)),)),
        Case("specular only (kd = 0), α = 1", ORIGIN, UP, _towards(ORIGIN, z, -ex, 20, 4),
             pl.Material(ka=0, kd=0, ks=0.8, shininess=1), (_point(_towards(ORIGIN, z, ex, 50, 3)),)),
        # max(0, r·v)^α, not max(0, (r·v)^α): with an even α the power of r·v = −0.77 is positive
        Case("eye on the light's side, r·v = cos 140° < 0, α = 2: clamp before the power", ORIGIN, UP,
             _towards(ORIGIN, z, ex, 80, 4), pl.Material(ka=0.1, kd=0.3, ks=0.6, shininess=2),
             (_point(_towards(ORIGIN, z, ex, 60, 3)),)),
    )


def _mirror_eye(p, normal, light_degrees, distance, *, off=0.0, hint=(1.0, 0.0, 0.0)):
    """An eye at ``distance`` along the mirror direction of a light ``light_degrees`` from n, turned by ``off``°."""
    n, t = frame(normal, hint)
    return _towards(p, n, t, -light_degrees + off, distance)


def _reflection() -> tuple[Case, ...]:
    ex, z = np.array([1.0, 0, 0]), np.array(UP)
    m = pl.Material(ka=0.05, kd=0.2, ks=0.7, shininess=50)
    n, t = frame(TILTED, (0.0, 1.0, 0.0))
    return (
        Case("r at 45°: eye on it", ORIGIN, UP, _mirror_eye(ORIGIN, UP, 45, 4), m,
             (_point(_towards(ORIGIN, z, ex, 45, 3)),)),
        Case("r at 45°: eye 5° off it", ORIGIN, UP, _mirror_eye(ORIGIN, UP, 45, 4, off=5), m,
             (_point(_towards(ORIGIN, z, ex, 45, 3)),)),
        Case("tilted normal: eye on r", OFF, TILTED, _mirror_eye(OFF, TILTED, 35, 5, hint=(0, 1, 0)), m,
             (_point(_towards(OFF, n, t, 35, 3)),)),
        Case("eye at the light: r·v = 2(n·l)² − 1 = 1/2", ORIGIN, UP, _towards(ORIGIN, z, ex, 30, 3),
             pl.Material(ka=0.05, kd=0.2, ks=0.7, shininess=2), (_point(_towards(ORIGIN, z, ex, 30, 3)),)),
        Case("eye low on the light's side: r·v < 0 (a reversed r would light it)", ORIGIN, UP,
             _towards(ORIGIN, z, ex, 75, 4), pl.Material(ka=0.05, kd=0.2, ks=0.7, shininess=3),
             (_point(_towards(ORIGIN, z, ex, 60, 3)),)),
        Case("light far away (|position − point| = 10): r from the unit l", ORIGIN, UP,
             _mirror_eye(ORIGIN, UP, 40, 4, off=3), m, (_point(_towards(ORIGIN, z, ex, 40, 10)),)),
        Case("tilted normal, point off the origin, α = 8", OFF, TILTED,
             _mirror_eye(OFF, TILTED, 50, 3, off=-12, hint=(0, 1, 0)),
             pl.Material(ka=0.05, kd=0.2, ks=0.7, shininess=8), (_point(_towards(OFF, n, t, 50, 2)),)),
        Case("light and eye along the normal: r = n = v", OFF, TILTED, _t(np.asarray(OFF) + 4 * n), m,
             (_point(_t(np.asarray(OFF) + 2 * n)),)),
    )


def _shininess() -> tuple[Case, ...]:
    cases = []
    n, t = frame(TILTED, (0.0, 1.0, 0.0))
    light = _point(_towards(OFF, n, t, 30, 3))
    for alpha in (1, 2, 7.5, 20, 64, 128, 129, 1000, 1e4, 1e5, 1e6):
        # the eye where r·v = 0.3^(1/α), so the highlight there is 0.3 of its peak
        off = math.degrees(math.acos(0.3 ** (1 / alpha)))
        m = pl.Material(ka=0.0, kd=0.1, ks=1.0, shininess=alpha)
        cases.append(Case(f"α = {alpha:g}, r·v = 0.3^(1/α): a third of the peak", OFF, TILTED,
                          _mirror_eye(OFF, TILTED, 30, 4, off=off, hint=(0, 1, 0)), m, (light,)))
    cases.append(Case("α = 1e6, eye 1° off r: nothing left", OFF, TILTED,
                      _mirror_eye(OFF, TILTED, 30, 4, off=1, hint=(0, 1, 0)),
                      pl.Material(ka=0.0, kd=0.1, ks=1.0, shininess=1e6), (light,)))
    # r·v < 0 on a lit point: no highlight for any α; an even α tells a power taken before the clamp
    cases.append(Case("α = 2, r·v = cos 110° < 0: no highlight", OFF, TILTED,
                      _mirror_eye(OFF, TILTED, 30, 4, off=110, hint=(0, 1, 0)),
                      pl.Material(ka=0.0, kd=0.1, ks=1.0, shininess=2), (light,)))
    # α = 0: S = 1 where n·l > 0 and r·v > 0, else 0 (0 ** 0 == 1 must not light the rest)
    flat = pl.Material(ka=0.0, kd=0.1, ks=1.0, shininess=0)
    cases.append(Case("α = 0, r·v > 0: the full k_s I_s", OFF, TILTED,
                      _mirror_eye(OFF, TILTED, 30, 4, off=40, hint=(0, 1, 0)), flat, (light,)))
    cases.append(Case("α = 0, r·v < 0 on a lit point: no highlight (0 ** 0 is 1, S is 0)", OFF, TILTED,
                      _mirror_eye(OFF, TILTED, 30, 4, off=110, hint=(0, 1, 0)), flat, (light,)))
    return tuple(cases)


def _attenuation() -> tuple[Case, ...]:
    m = pl.Material(ka=0.1, kd=0.6, ks=0.4, shininess=10)
    eye = (0.0, 0.0, 5.0)
    n, t = frame(TILTED)

    def above(d, abc, **kw):
        return (AMB, pl.PointLight(position=(0, 0, d), attenuation=abc, **kw))

    return (
        Case("(1, 0, 0): no attenuation at d = 2", ORIGIN, UP, eye, m, above(2, (1, 0, 0))),
        Case("inverse square (0, 0, 1) at d = 2", ORIGIN, UP, eye, m, above(2, (0, 0, 1))),
        Case("inverse square at d = 10", ORIGIN, UP, eye, m, above(10, (0, 0, 1))),
        Case("(1, 0.5, 0.25) at d = 3", ORIGIN, UP, eye, m, above(3, (1, 0.5, 0.25))),
        Case("(0, 1, 0) at d = 0.5: f = 2 brightens", ORIGIN, UP, eye, m, above(0.5, (0, 1, 0))),
        Case("(0.2, 0.1, 0.01), oblique, d = 7.3", OFF, TILTED, _towards(OFF, n, t, -20, 4), m,
             (AMB, _point(_towards(OFF, n, t, 35, 7.3), attenuation=(0.2, 0.1, 0.01)))),
        Case("attenuation scales the highlight too", OFF, TILTED, _mirror_eye(OFF, TILTED, 25, 4, off=2), SHINY,
             (_point(_towards(OFF, n, t, 25, 4), attenuation=(0.5, 0.2, 0.05)),)),
        Case("two lights, each with its own distance", ORIGIN, UP, eye, m,
             (AMB, pl.PointLight(position=(0, 0, 2), attenuation=(0, 0, 1)),
              pl.PointLight(position=(3, 0, 4), attenuation=(1, 0.1, 0.02), color=(0.2, 0.4, 1)))),
    )


def _directional() -> tuple[Case, ...]:
    m = PLASTIC
    far = (100.0, -50.0, 20.0)
    n, t = frame(TILTED)
    return (
        Case("direction (0, 0, 5): normalise it", ORIGIN, UP, (1, 0, 5), m, (AMB, pl.DirectionalLight(direction=(0, 0, 5)))),
        Case("direction (1, 2, 2): l = (1, 2, 2)/3", ORIGIN, UP, (0, 0, 5), m,
             (AMB, pl.DirectionalLight(direction=(1, 2, 2)))),
        Case("far from the origin: the same l everywhere", far, UP, (100, -50, 25), m,
             (AMB, pl.DirectionalLight(direction=(1, 2, 2)))),
        Case("the direction points towards the light: from behind, nothing", ORIGIN, UP, (0, 0, 5), m,
             (AMB, pl.DirectionalLight(direction=(0.3, 0, -1)))),
        Case("no attenuation for a directional light", far, TILTED, _t(np.asarray(far) + 5 * n), m,
             (AMB, pl.DirectionalLight(direction=_t(3 * n + t), intensity=0.8))),
        Case("directional highlight at a tilted normal", OFF, TILTED,
             _mirror_eye(OFF, TILTED, 40, 4, off=4), SHINY,
             (pl.DirectionalLight(direction=_t(math.cos(0.698) * n + math.sin(0.698) * t)),)),
        Case("directional and point light together", OFF, TILTED, _towards(OFF, n, t, -10, 4), m,
             (AMB, pl.DirectionalLight(direction=(0, 1, 1), color=(1, 0.9, 0.6)),
              _point(_towards(OFF, n, t, 50, 3), attenuation=(0, 0, 1)))),
    )


def _spot() -> tuple[Case, ...]:
    m = pl.Material(ka=0.1, kd=0.6, ks=0.3, shininess=15)
    eye = (0.0, 2.0, 5.0)

    def at(degrees):  # the point on the plane z = 0 seen from the spot at (0, 0, 4) at this angle
        return (4 * math.tan(math.radians(degrees)), 0.0, 0.0)

    def spot(**kw):
        kw.setdefault("direction", (0, 0, -1))
        return (AMB, pl.SpotLight(position=(0, 0, 4), **kw))

    return (
        Case("inside the cone (14°), exponent 0", at(14), UP, eye, m, spot(cutoff=30)),
        Case("outside the cone (37°)", at(37), UP, eye, m, spot(cutoff=30)),
        Case("just inside the edge (29.99° < 30°)", at(29.99), UP, eye, m, spot(cutoff=30, exponent=2)),
        Case("just outside the edge (30.01° > 30°)", at(30.01), UP, eye, m, spot(cutoff=30, exponent=2)),
        Case("exponent 10 at 20°: cos(20°)^10", at(20), UP, eye, m, spot(cutoff=45, exponent=10)),
        Case("exponent 100 near the axis", at(3), UP, eye, m, spot(cutoff=45, exponent=100)),
        Case("axis not unit length (0, 0, −7)", at(10), UP, eye, m, spot(cutoff=25, exponent=4, direction=(0, 0, -7))),
        Case("tilted axis, point off the axis", (1.0, 1.0, 0.0), UP, eye, m,
             spot(cutoff=40, exponent=3, direction=(0.3, 0.2, -1))),
        Case("cutoff 180 is a point light: lit even behind the axis, exponent ignored", at(20), UP, eye, m,
             spot(cutoff=180, exponent=5, direction=(0, 0, 1))),
        Case("cone and attenuation together", at(15), UP, eye, m,
             spot(cutoff=35, exponent=2, attenuation=(0.5, 0, 0.1))),
    )


def _many() -> tuple[Case, ...]:
    n, t = frame(TILTED)
    lights = (
        pl.AmbientLight(color=(0.2, 0.2, 0.3)),
        pl.AmbientLight(color=(0.1, 0.05, 0.0)),
        _point(_towards(OFF, n, t, 30, 3), color=(1.0, 0.9, 0.8), attenuation=(1, 0.1, 0.01)),
        pl.DirectionalLight(direction=_t(n - t), diffuse=(0.3, 0.4, 1.0), specular=(1, 1, 1), intensity=0.7),
        pl.SpotLight(position=_t(np.asarray(OFF) + 3 * n), direction=_t(-n), cutoff=40, exponent=8,
                     color=(1, 0.2, 0.2)),
        _point(_t(np.asarray(OFF) - 2 * n + t), color=(0.5, 1, 0.5)),  # behind the surface
    )
    rgb = pl.Material(ka=(0.3, 0.2, 0.1), kd=(0.6, 0.4, 0.2), ks=(0.5, 0.6, 0.7), shininess=25,
                      emission=(0.01, 0.02, 0.03))
    return (
        Case("six lights of every kind, RGB material", OFF, TILTED, _mirror_eye(OFF, TILTED, 30, 4, off=3), rgb, lights),
        Case("the same lights, another eye", OFF, TILTED, _towards(OFF, n, t, 10, 6), rgb, lights),
        Case("the same lights, a point nearby", _t(np.asarray(OFF) + 0.3 * t), TILTED,
             _towards(OFF, n, t, -40, 5), rgb, lights),
        Case("separate diffuse and specular colours", ORIGIN, UP, _mirror_eye(ORIGIN, UP, 30, 4, off=2), SHINY,
             (pl.PointLight(position=_towards(ORIGIN, np.array(UP), np.array([1.0, 0, 0]), 30, 3),
                            color=(1, 1, 1), diffuse=(1, 0, 0), specular=(0, 0, 1), intensity=2),)),
        Case("intensity scales both terms", ORIGIN, UP, _mirror_eye(ORIGIN, UP, 45, 4, off=4), PLASTIC,
             (AMB, pl.PointLight(position=(2, 0, 2), intensity=3.5, color=(0.9, 0.7, 0.5)))),
    )


def _hard() -> tuple[Case, ...]:
    ex, z = np.array([1.0, 0, 0]), np.array(UP)
    m = pl.Material(ka=0.1, kd=0.6, ks=0.5, shininess=20)
    eye = (0.0, 1.0, 5.0)
    light = (AMB, pl.PointLight(position=(1, 0.5, 3)))
    graze = (3.0, 0.0, 3e-8)  # n·l = 1e-8: lit, barely
    # the eye along r for that light: r = 2(n·l)n − l
    l = np.asarray(graze) / np.linalg.norm(graze)
    r = 2 * l[2] * z - l
    graze_below = (3.0, 0.0, -3e-8)  # n·l = −1e-8: unlit, barely
    lb = np.asarray(graze_below) / np.linalg.norm(graze_below)
    r_below = 2 * lb[2] * z - lb
    big = pl.Material(ka=0.0, kd=0.0, ks=1.0, shininess=1e6)
    n, t = frame(TILTED, (0.0, 1.0, 0.0))
    return (
        Case("grazing light, n·l = 1e-8: still lit, full highlight on r", ORIGIN, UP, _t(4 * r), m,
             (pl.PointLight(position=graze),)),
        Case("grazing from below, n·l = −1e-8: no highlight even on r", ORIGIN, UP,
             _t(4 * r_below), m, (pl.PointLight(position=graze_below),)),
        Case("normal of length 5: normalise it", ORIGIN, (0.0, 0.0, 5.0), eye, m, light),
        Case("normal of length 1e-3", ORIGIN, (0.0, 0.6e-3, 0.8e-3), eye, m, light),
        Case("normal of length 1e-20", ORIGIN, (0.0, 0.0, 1e-20), eye, m, light),
        Case("normal of length 1e-150", OFF, _t(np.asarray(TILTED) * 1e-150), _towards(OFF, n, t, 20, 4), m,
             (AMB, _point(_towards(OFF, n, t, -30, 3)))),
        Case("a light on the point adds nothing (no division by zero)", OFF, TILTED, _towards(OFF, n, t, 20, 4), m,
             (AMB, _point(OFF), pl.DirectionalLight(direction=_t(n + t)))),
        Case("the eye on the point (v of length 0): no specular light, diffuse as usual", OFF, TILTED, OFF,
             pl.Material(ka=0.1, kd=0.6, ks=0.5, shininess=1), (AMB, _point(_towards(OFF, n, t, 10, 3)))),
        Case("α = 1e6, r·v = 1 − 5e-7: e^−0.5 of the peak", OFF, TILTED,
             _mirror_eye(OFF, TILTED, 30, 4, off=math.degrees(math.acos(1 - 5e-7)), hint=(0, 1, 0)), big,
             (_point(_towards(OFF, n, t, 30, 3)),)),
        Case("α = 1e6 on the peak", ORIGIN, UP, _mirror_eye(ORIGIN, UP, 30, 4), big,
             (_point(_towards(ORIGIN, z, ex, 30, 3)),)),
        Case("α = 1e6 and a second, broad light", OFF, TILTED,
             _mirror_eye(OFF, TILTED, 30, 4, off=math.degrees(math.acos(1 - 2e-6)), hint=(0, 1, 0)),
             pl.Material(ka=0.1, kd=0.2, ks=1.0, shininess=1e6),
             (AMB, _point(_towards(OFF, n, t, 30, 3)), pl.DirectionalLight(direction=_t(n)))),
    )


# The tolerances: |got − expected| <= atol + rtol·|expected| in every channel.
_EXACT_SUMS = ("products and sums of a few non-negative terms: a few ulps (~1e-15 relative); "
               "1e-9 leaves a large margin for any sound order of operations")
GROUPS: tuple[Group, ...] = (
    Group("ambient", "Ambient light and emission", 5, 1e-9, 1e-12, _EXACT_SUMS, _ambient()),
    Group("diffuse", "Diffuse light and Lambert's max(0, n·l)", 10, 1e-9, 1e-12,
          "normalising and one dot product: ~1e-15 relative; 1e-12 absolute where n·l = 0", _diffuse()),
    Group("specular", "Specular light and the n·l > 0 gate", 10, 1e-8, 1e-12,
          "α ≤ 50 amplifies the rounding of r·v (~4e-16) at most 50-fold: ~2e-14", _specular()),
    Group("reflection", "The reflection vector r = 2(n·l)n − l", 10, 1e-8, 1e-12,
          "as for specular: α ≤ 50 times the rounding of r·v", _reflection()),
    Group("shininess", "Shininess α from 0 to 1e6", 15, 1e-6, 1e-12,
          "δ(c^α)/c^α ≈ α·δc: at α = 1e6 and δc ≈ 1e-15 that is 1e-9; 1e-6 allows r·v computed "
          "in any sound way (e.g. without renormalising r); at α = 0 the weight is exactly 0 or 1",
          _shininess()),
    Group("attenuation", "Distance attenuation 1/(a + b·d + c·d²)", 10, 1e-9, 1e-12, _EXACT_SUMS, _attenuation()),
    Group("directional", "Directional lights", 10, 1e-9, 1e-12, _EXACT_SUMS, _directional()),
    Group("spot", "Spotlights: the cone's edge and exponent", 10, 1e-8, 1e-12,
          "cos^e with e ≤ 100 amplifies the rounding of −l·s 100-fold: ~1e-13; the edge cases are "
          "0.01° (cos differs by 9e-5) from the cone, far beyond rounding", _spot()),
    Group("many", "Many lights and RGB", 10, 1e-9, 1e-12, _EXACT_SUMS + " (every term is >= 0: no cancellation)",
          _many()),
    Group("hard", "Hard cases: grazing light, odd normals, a light or the eye on the point, α = 1e6", 10, 1e-6,
          1e-12,
          "α = 1e6 near the peak amplifies the rounding of r·v a million-fold (~1e-9); normals of "
          "length 5 to 1e-150 normalise within a few ulps in float64", _hard()),
)
