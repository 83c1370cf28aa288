"""The vectors of the model at one surface point, for arrows and readouts.

Directions point *away from the surface point*: ``n`` the unit normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``. :func:`vectors` computes them with the same kernels
and light factors as :func:`~phonglab.core.shade`, so the arrows and numbers
a lesson shows are those of the picture.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .checks import viewer
from .model import AmbientLight, DirectionalLight, InvalidValue, Light, SpotLight, vec3
from .physics import attenuation, face_forward, facing_away, spot_factor
from .vectors import dot_c, normalize_c, reflect_c

__all__ = ["ProbeVectors", "vectors"]


@dataclass(frozen=True)
class ProbeVectors:
    """The vectors of the model at one surface point, all unit, float64.

    ``nl``, ``rv`` and ``nh`` are the raw cosines (not clamped), so a negative
    ``nl`` shows the light is behind the surface. ``distance`` is None for a
    directional light; ``attenuation`` and ``spot`` are the factors ``f_l``
    is made of.
    """

    n: np.ndarray
    l: np.ndarray
    r: np.ndarray
    v: np.ndarray
    h: np.ndarray
    nl: float
    rv: float
    nh: float
    distance: float | None
    attenuation: float
    spot: float
    flipped: bool


def vectors(point, normal, *, light: Light, eye=None, view_direction=None, two_sided: bool = False) -> ProbeVectors:
    """Unit N, L, R, V, H and the cosines n·l, r·v, n·h at one point.

    Parameters
    ----------
    point, normal : 3 floats
    light : PointLight, DirectionalLight or SpotLight
    eye, view_direction : 3 floats, keyword-only (exactly one)
    two_sided : bool
        Negate the normal if it faces away from the eye (``flipped`` says so).

    Returns
    -------
    ProbeVectors

    Notes
    -----
    .. math:: r = 2(n\\cdot l)n - l, \\qquad h = \\frac{l + v}{|l + v|}

    Uses the same kernels and light factors (:func:`~phonglab.core.attenuation`,
    :func:`~phonglab.core.spot_factor`, :func:`~phonglab.core.face_forward`)
    as :func:`~phonglab.core.shade`, in float64.

    Examples
    --------
    >>> import phonglab as pl
    >>> pv = pl.vectors((0, 0, 0), (0, 0, 1), eye=(0, 0, 3),
    ...                 light=pl.DirectionalLight(direction=(1, 0, 1)))
    >>> pv.r.round(4).tolist(), round(pv.nl, 4)
    ([-0.7071, 0.0, 0.7071], 0.7071)
    """
    if isinstance(light, AmbientLight) or not isinstance(light, Light):
        raise InvalidValue("light", light, "must be a point, directional or spot light "
                           "(ambient light has no direction)")
    eye, view_direction = viewer(eye, view_direction)
    # one point as components-first (3, 1) columns, the layout of the shading kernel
    p = np.asarray(vec3("point", point))[:, None]
    n, _ = normalize_c(np.asarray(vec3("normal", normal))[:, None])
    if eye is not None:
        v, _ = normalize_c(np.asarray(eye)[:, None] - p)
    else:
        v, _ = normalize_c(np.asarray(view_direction)[:, None])
    # two-sided: the normal turned towards the eye
    flipped = bool(two_sided and facing_away(n, v, axis=0)[0])
    if two_sided:
        n = face_forward(n, v, axis=0)
    # the light's direction, distance and factor f_l = attenuation × spot
    f_att = f_spot = 1.0
    if isinstance(light, DirectionalLight):
        l, _ = normalize_c(np.asarray(light.direction)[:, None])
        distance = None
    else:
        l, dist = normalize_c(np.asarray(light.position)[:, None] - p)
        distance = float(dist[0])
        f_att = float(attenuation(dist, light.attenuation)[0])
        if isinstance(light, SpotLight) and light.is_cone:
            axis, _ = normalize_c(np.asarray(light.direction)[:, None])
            cos_axis = np.negative(dot_c(l, axis))  # the axis against the ray light -> point
            f_spot = float(spot_factor(cos_axis, cutoff=light.cutoff, exponent=light.exponent)[0])
    r = reflect_c(l, n)
    h, _ = normalize_c(l + v)
    return ProbeVectors(
        n=n[:, 0], l=l[:, 0], r=r[:, 0], v=v[:, 0], h=h[:, 0],
        nl=float(dot_c(n, l)[0]), rv=float(dot_c(r, v)[0]), nh=float(dot_c(n, h)[0]),
        distance=distance, attenuation=f_att, spot=f_spot, flipped=flipped,
    )
