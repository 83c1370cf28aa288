"""The light factors and the two-sided flip: each formula and guard written once.

Every caller uses these: the fast kernel (:func:`~phonglab.core.shade`), the
vectors at a probe (:func:`~phonglab.core.vectors`), the reference kernel
(:func:`~phonglab.core.shade_reference`), the teaching mistakes and the
scene's area light. The mirror vector ``r = 2(n·l)n − l`` is
:func:`~phonglab.core.reflect`.

Directions point *away from the surface point*: ``n`` the normal, ``l``
towards the light, ``v`` towards the eye. :func:`attenuation` and
:func:`spot_factor` work elementwise, so they take arrays of any shape; the
two functions that take vectors (:func:`facing_away`, :func:`face_forward`)
take ``axis=``, the axis holding the three components: ``-1`` for ``(..., 3)``
arrays, ``0`` for the fast kernel's components-first ``(3, n)`` blocks.
"""

from __future__ import annotations

import math

import numpy as np

from .model import ATTENUATION_MAX, DISTANCE_FLOOR
from .vectors import const_row, dot_c

__all__ = ["SPOT_SLACK_ULPS", "attenuation", "face_forward", "facing_away", "spot_cos_limit", "spot_factor"]

#: Slack of the spot cone test ``cos(angle) >= cos(cutoff)``, in ulps (machine
#: epsilons) of the working dtype: a point on the cone counts as inside.
SPOT_SLACK_ULPS = 4


def _float_dtype(a) -> np.dtype:
    dtype = np.asarray(a).dtype
    return dtype if np.issubdtype(dtype, np.floating) else np.dtype(np.float64)


# ---------------------------------------------------------------------------
# two-sided lighting


def facing_away(n, v, *, axis: int = -1):
    """Where the normal faces away from the eye: ``n·v < 0``.

    Parameters
    ----------
    n, v : array_like
        Normals and directions towards the eye (any length: only the sign of
        ``n·v`` matters), broadcasting together, components along ``axis``.
    axis : int, keyword-only
        The axis of length 3 holding the components.

    Returns
    -------
    ndarray of bool
        The broadcast shape without ``axis``.

    Notes
    -----
    .. math:: \\text{away} = n \\cdot v < 0

    The test is strict: a normal at right angles to the view (``n·v = 0``),
    and a zero normal or view vector, is not flipped.

    Examples
    --------
    >>> facing_away([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]], [0.0, 0.0, 1.0]).tolist()
    [False, True]
    """
    n, v = np.moveaxis(np.asarray(n), axis, 0), np.moveaxis(np.asarray(v), axis, 0)
    return dot_c(n, v) < 0


def face_forward(n, v, *, axis: int = -1, out=None):
    """The normal turned towards the eye: ``−n`` where ``n·v < 0``, else ``n``.

    Parameters
    ----------
    n, v : array_like
        Normals and directions towards the eye (any length), broadcasting
        together, components along ``axis``.
    axis : int, keyword-only
        The axis of length 3 holding the components: -1 for ``(..., 3)``, 0
        for components-first ``(3, ...)``.
    out : ndarray, optional, keyword-only
        Where to write the result (may be ``n`` itself: flipped in place).

    Returns
    -------
    ndarray
        ``n`` broadcast with ``v``, in ``n``'s dtype, negated where it faces
        away from the eye.

    Notes
    -----
    Two-sided lighting: the back of a surface is lit as if it were the front.

    .. math:: n' = \\begin{cases} -n & n \\cdot v < 0 \\\\ n & \\text{otherwise} \\end{cases}

    Negation is exact, so ``n'`` has the length of ``n``; the test is that of
    :func:`facing_away` (``n·v = 0`` keeps ``n``).

    Examples
    --------
    >>> face_forward([0.48, 0.6, -0.64], [0.0, 0.0, 1.0]).tolist()
    [-0.48, -0.6, 0.64]
    """
    n = np.asarray(n)
    away = facing_away(n, v, axis=axis)
    # n times -1 or 1: exact, and faster than a masked negation
    one = n.dtype.type(1)
    sign = np.expand_dims(np.where(away, -one, one), axis)
    return np.multiply(n, sign, out=out)


# ---------------------------------------------------------------------------
# the light factor f_l = attenuation × spot


def attenuation(dist, coefficients):
    """Distance attenuation ``1 / (a + b·d + c·d²)`` of a point or spot light.

    Parameters
    ----------
    dist : array_like of float
        Distances from the light to the points, any shape; the result has
        the same float dtype.
    coefficients : (a, b, c)
        Constant, linear and quadratic coefficients, as validated by
        :class:`~phonglab.core.PointLight` (the denominator is positive at
        every distance).

    Returns
    -------
    ndarray
        The factor, at most :data:`~phonglab.core.ATTENUATION_MAX`.

    Notes
    -----
    .. math:: f_{att} = \\frac{1}{\\max(a + b\\,d + c\\,d^2,\\ 1/f_{max})}, \\qquad
              d = \\max(\\mathit{dist},\\ d_{min})

    Guards:

    - the distance floor ``d_min`` = :data:`~phonglab.core.DISTANCE_FLOOR`:
      a light sitting on the point is not at distance 0;
    - the cap ``f_max`` = :data:`~phonglab.core.ATTENUATION_MAX` floors the
      denominator, so the factor stays finite even for ``(0, 0, 1)`` at the floor;
    - only the non-zero terms are summed: ``0·inf`` would be NaN for a light
      at an infinite distance, where the factor is 0 (or ``1/a``).

    The coefficients are taken in the distances' dtype.

    Examples
    --------
    >>> attenuation([0.0, 2.0], (0, 0, 1)).tolist()
    [1000000000000.0, 0.25]
    """
    dist = np.asarray(dist)
    dtype = _float_dtype(dist)
    a, b, c = (dtype.type(x) for x in coefficients)
    # the distance floor: a light on the point is DISTANCE_FLOOR away
    d = np.maximum(dist, const_row(DISTANCE_FLOOR, dist.shape, dtype))
    # a + b d + c d², only the non-zero terms: 0·inf would be NaN for a light at infinity
    den = np.full_like(d, a)
    with np.errstate(over="ignore"):
        if c:
            den += d * (b + c * d) if b else c * d * d
        elif b:
            den += b * d
    # the cap: the denominator is at least 1/ATTENUATION_MAX
    np.maximum(den, const_row(1.0 / ATTENUATION_MAX, den.shape, dtype), out=den)
    return np.divide(dtype.type(1), den, out=den)


def spot_cos_limit(cutoff: float, dtype=np.float64):
    """The spot cone test's threshold: ``cos(cutoff)`` less SPOT_SLACK_ULPS epsilons.

    Parameters
    ----------
    cutoff : float
        Half-angle of the cone in degrees.
    dtype : float dtype
        The working precision; the slack is counted in its epsilons.

    Returns
    -------
    scalar of ``dtype``

    Notes
    -----
    .. math:: \\cos(\\mathrm{cutoff}) - 4\\,\\varepsilon

    A point exactly on the cone has ``cos(angle) = cos(cutoff)`` only up to
    the rounding of the vectors it is computed from; the slack makes it count
    as inside, as the ``>=`` of the model says.

    Examples
    --------
    >>> float(spot_cos_limit(60.0)) < 0.5
    True
    """
    dtype = np.dtype(dtype)
    return dtype.type(math.cos(math.radians(cutoff)) - SPOT_SLACK_ULPS * np.finfo(dtype).eps)


def spot_factor(cos_axis, *, cutoff: float, exponent: float, out=None):
    """The spotlight factor from the cosine of the angle to the cone's axis.

    Parameters
    ----------
    cos_axis : array_like of float
        ``−l·s``: the cosine of the angle between the spot's unit axis ``s``
        and the unit direction ``−l`` from the light to the point; any shape.
    cutoff : float, keyword-only
        Half-angle of the cone in degrees, in (0, 90], or 180 for a plain
        point light.
    exponent : float, keyword-only
        Fall-off towards the rim, ``e ≥ 0``.
    out : ndarray, optional, keyword-only
        Where to write the factor (may be ``cos_axis`` itself).

    Returns
    -------
    ndarray
        The factor in [0, 1], in the float dtype of ``cos_axis``.

    Notes
    -----
    .. math:: f_{spot} = \\begin{cases} \\max(0, -l\\cdot s)^{e} & -l\\cdot s \\ge \\cos(\\mathrm{cutoff}) \\\\
              0 & \\text{otherwise} \\end{cases}

    Guards:

    - the cone test has :data:`SPOT_SLACK_ULPS` of slack
      (:func:`spot_cos_limit`), so a point on the cone counts as inside;
    - ``max(0, ·)`` before the power: at cutoff 90° a point just behind the
      light's plane passes the slackened test with a cosine of about
      ``−1e-15``, whose fractional power would be NaN;
    - ``cutoff = 180`` is a plain point light: the factor is 1 everywhere,
      even straight behind the light.

    Examples
    --------
    >>> spot_factor([1.0, 0.9, 0.5], cutoff=30.0, exponent=2.0).round(4).tolist()
    [1.0, 0.81, 0.0]
    """
    cos_axis = np.asarray(cos_axis)
    dtype = _float_dtype(cos_axis)
    if cutoff == 180:  # a plain point light
        if out is None:
            return np.ones(cos_axis.shape, dtype)
        out[...] = 1
        return out
    # the cone test, before cos_axis may be overwritten by out=
    inside = cos_axis >= spot_cos_limit(cutoff, dtype)
    # max(0, cos)^e inside the cone, 0 outside
    f = np.maximum(cos_axis, const_row(0, cos_axis.shape, dtype), out=out)
    f = np.power(f, dtype.type(exponent), out=f if isinstance(f, np.ndarray) else None)
    f *= inside
    return f
