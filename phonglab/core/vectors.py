"""Vector kernels of the Phong model, written for numerical safety.

Convention: every direction is a unit vector pointing *away from the surface
point* — ``l`` towards the light, ``v`` towards the eye, ``n`` the outward
normal, ``r`` the mirror image of ``l`` about ``n``, ``h`` halfway between
``l`` and ``v``.

Public functions take ``(..., 3)`` arrays and broadcast over the leading axes.
Internally the shading loop keeps components first, ``(3, n)``, so each
component is a contiguous row; the ``*_c`` functions work on that layout and
the public ones are thin wrappers over them, so both share one arithmetic.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["normalize", "dot", "reflect", "one_minus_cos", "cos_power", "unit_direction", "working_dtype",
           "SQUARING_MAX"]

#: Largest integer shininess raised to its power by repeated squaring. Above it,
#: and for every fractional α, the power is ``exp(α·log1p(−d))``. Squaring is about
#: four times cheaper; its error grows like 2α ulps (≤ 256 ulps at 128: 1.5e-5
#: relative in float32, 3e-14 in float64), while exp/log stays within a few ulps
#: of the highlight at any α, up to 10⁶.
SQUARING_MAX = 128


def working_dtype(*arrays) -> np.dtype:
    """The float dtype shading runs in: float32 if every input is float32, else float64.

    Integer and float64 inputs compute in float64; float16 is promoted to float32.
    """
    return np.result_type(*[np.asarray(a).dtype for a in arrays], np.float32)


def unit_direction(direction, dtype) -> np.ndarray:
    """A fixed direction (a light's, its axis, the viewer's) as a unit vector, shape (3,).

    Normalised in float64 before the cast to ``dtype``, so a direction like
    ``(0, 0, 1e-148)`` does not underflow to zero in float32.
    """
    return normalize_c(np.asarray(direction, np.float64))[0].astype(dtype)


def _fast_range(dtype):
    """Sums of squares inside this open interval need no rescaling.

    Below ``tiny / eps`` the squares of the components may have lost bits to
    gradual underflow; at ``max`` they have overflowed.
    """
    info = np.finfo(dtype)
    return info.tiny / info.eps, info.max


# ---------------------------------------------------------------------------
# components-first kernels: arrays of shape (3, ...)


def dot_c(a, b):
    """``a·b`` for components-first arrays ``(3, ...)``."""
    out = a[0] * b[0]
    out += a[1] * b[1]
    out += a[2] * b[2]
    return out


def normalize_c(v, *, out=None, before_rescaling=None):
    """Unit vectors and lengths of components-first vectors ``(3, ...)``.

    Returns ``(unit, length)``. Zero vectors give a zero unit vector and length 0.
    Vectors whose sum of squares is safely inside the float range use the
    direct formula; the others (1e±20 in float32, 1e±160 in float64,
    subnormal, zero) are rescaled by their largest component first. The
    choice is made per vector, so a vector's result never depends on which
    other vectors share the call.

    Every sum of squares strictly inside the direct range also proves every
    component finite (NaN and inf fail the range test). A caller that must
    refuse non-finite input passes a ``before_rescaling`` that checks its
    input and raises; it runs only when some vector left the direct range, so
    clean input pays no separate finiteness pass.
    """
    v = np.asarray(v)
    x, y, z = v[0], v[1], v[2]
    with np.errstate(over="ignore", under="ignore"):  # out-of-range sums are detected below
        ss = x * x
        ss += y * y
        ss += z * z
    lo, hi = _fast_range(v.dtype)
    if ss.size == 0 or (ss.min() > lo and ss.max() < hi):
        # direct: |v| = sqrt(x² + y² + z²) everywhere
        length = np.sqrt(ss, out=ss if isinstance(ss, np.ndarray) else None)
        # 1/length by division: the same correctly rounded value as np.reciprocal, and faster
        return np.multiply(v, np.divide(v.dtype.type(1), length), out=out), length
    if before_rescaling is not None:
        before_rescaling()
    if v.ndim == 1:
        return _normalize_scaled_c(v, out=out)
    # the direct formula where it is safe, rescaling only the other vectors
    bad = ~((ss > lo) & (ss < hi))
    fixed, fixed_length = _normalize_scaled_c(v[:, bad])  # before out= may overwrite v
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        length = np.sqrt(ss)
        unit = np.multiply(v, np.divide(v.dtype.type(1), length), out=out)
    unit[:, bad] = fixed
    length[bad] = fixed_length
    return unit, length


def _normalize_scaled_c(v, *, out=None):
    # scale by the largest |component| so the sum of squares lies in [1, 3]
    m = np.maximum(np.maximum(np.abs(v[0]), np.abs(v[1])), np.abs(v[2]))
    zero = m == 0
    m_safe = np.where(zero, np.ones((), v.dtype), m)
    u = v / m_safe
    s = np.sqrt(dot_c(u, u))
    # zero-length guard: a zero vector stays zero, never 0/0
    inv = np.where(zero, np.zeros((), v.dtype), np.reciprocal(np.where(zero, np.ones((), v.dtype), s)))
    with np.errstate(over="ignore"):
        length = m * s  # may overflow to inf only for vectors near the float maximum
    return np.multiply(u, inv, out=out), length


def reflect_c(l, n, nl=None):
    """``r = 2(n·l)n − l`` for components-first arrays."""
    if nl is None:
        nl = dot_c(n, l)
    return (2 * nl) * n - l


def one_minus_cos_c(a, b):
    """``1 − a·b`` for unit vectors, as ``|a − b|² / 2``.

    The direct ``1 − a·b`` loses every digit when the vectors are nearly
    parallel; the half squared distance keeps full relative precision there,
    which is where a large shininess looks.
    """
    d = a - b
    return dot_c(d, d) * d.dtype.type(0.5)


def log1p_neg(d, *, out=None):
    """``log(1 − d)`` for ``d`` in [0, 1], accurate to 2 ulps even for tiny ``d``.

    Notes
    -----
    With ``u = fl(1 − d)``, the rounding error ``c = (1 − u) − d`` is exact
    (both subtractions are exact by Sterbenz's lemma where ``u ≥ 1/2``, and
    ``u`` is exact below), and

    .. math:: \\log(1 - d) = \\log(u + c) \\approx \\log u + c

    loses only ``c·d``, far below an ulp of the result. It uses NumPy's
    vectorised ``log``, several times faster than ``np.log1p`` on float32;
    checked against mpmath to 2 ulps. ``d = 1`` gives −inf.
    """
    u = np.subtract(1, d, dtype=d.dtype)
    c = np.subtract(1, u)
    c -= d  # the rounding error of u
    with np.errstate(divide="ignore"):
        out = np.log(u, out=out if out is not None else u)
    out += c
    return out


def cos_power(d_cos, lit, shininess):
    """``max(0, cos)^α`` from ``d_cos = 1 − cos``, zero where ``lit`` is False.

    Parameters
    ----------
    d_cos : ndarray
        ``1 − cos`` of the angle, from :func:`one_minus_cos`, ``d_cos ≥ 0``;
        ``cos`` is clamped to [0, 1] before the power. Modified in place.
    lit : ndarray of bool
        Where the term applies (``n·l > 0``); exactly 0 elsewhere, and where
        ``cos ≤ 0``.
    shininess : float
        The exponent α ≥ 0.

    Notes
    -----
    .. math:: \\max(0, \\cos)^{\\alpha} = \\exp(\\alpha \\, \\mathrm{log1p}(-d_{cos}))

    ``log1p`` keeps the relative precision of tiny ``d_cos``, so α = 10⁶ near the
    highlight is as accurate as α = 10. An integer α up to :data:`SQUARING_MAX`
    is instead raised by repeated squaring of ``1 − d_cos``: a few multiplications
    in place of a log and an exp, at most about 2α ulps from the exact power.
    α = 0 gives exactly 1 wherever ``lit`` and ``cos > 0`` (x⁰ = 1); the ``lit``
    gate still makes the term exactly 0 on the unlit side, so no α lights the
    back of a surface.
    """
    dtype = np.asarray(d_cos).dtype
    # α in the working precision, kept finite: 0·(−inf) or inf·0 would be NaN
    alpha = dtype.type(min(float(shininess), float(np.finfo(dtype).max)))
    if alpha == 0:  # α = 0, or so small it rounds to 0: x⁰ = 1 wherever lit and cos > 0
        return (lit & (d_cos < 1)).astype(dtype)
    if float(shininess).is_integer() and shininess <= SQUARING_MAX:
        return _power_by_squaring(d_cos, lit, int(shininess))
    np.minimum(d_cos, const_row(1, d_cos.shape, dtype), out=d_cos)  # clamp cos to [0, 1]
    t = log1p_neg(d_cos)  # -inf at d_cos = 1: exp gives exactly 0
    with np.errstate(over="ignore", under="ignore"):  # a huge α·log may reach -inf: exp gives 0
        t *= alpha
        np.exp(t, out=t)
    t *= lit
    return t


def _power_by_squaring(d_cos, lit, k):
    """``max(0, 1 − d_cos)^k`` for an integer ``k ≥ 1``, gated by ``lit``; reuses ``d_cos``."""
    dtype = d_cos.dtype
    c = np.subtract(dtype.type(1), d_cos, out=d_cos)
    np.maximum(c, const_row(0, c.shape, dtype), out=c)  # clamp cos to [0, 1]
    c *= lit  # exactly 0 where unlit: 0^k = 0
    # square c for each bit of k, multiplying the squares of the set bits together
    result = None
    while True:
        if k & 1:
            if result is None:
                result = c  # c is not squared in place after this
            else:
                result *= c
        k >>= 1
        if not k:
            return result
        with np.errstate(under="ignore"):  # tiny powers flush to 0, as the exact ones would round
            c = np.multiply(c, c, out=None if c is result else c)


@functools.lru_cache(maxsize=16)
def _const_row_cached(value, shape, dtype):
    row = np.full(shape, value, dtype)
    row.flags.writeable = False
    return row


def const_row(value, shape, dtype):
    """A read-only array of ``value`` of this shape.

    ``np.maximum(x, 0)`` with a scalar runs NumPy's slow broadcast loop; with a
    full array of zeros it runs the vectorised one, three times faster. The
    rows are cached per block size.
    """
    return _const_row_cached(float(value), tuple(shape), np.dtype(dtype))


# ---------------------------------------------------------------------------
# public (..., 3) wrappers


def _c(a):
    """The component-major view of a ``(..., 3)`` array: ``(3, ...)``.

    ``np.moveaxis`` gives the same view, but its argument checks cost more
    than a one-point call of the reference kernel's vector steps (the
    readout's trace at the probe makes about twenty such calls).
    """
    a = np.asarray(a)
    return a.transpose((a.ndim - 1, *range(a.ndim - 1)))


def _last(a):
    """The inverse of :func:`_c`: ``(3, ...)`` to ``(..., 3)``."""
    return a.transpose((*range(1, a.ndim), 0))


def _check3(name, a):
    a = np.asarray(a)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"{name}: must be an array of shape (..., 3), got shape {a.shape}")
    if a.dtype.kind != "f":  # np.issubdtype(a.dtype, np.floating), without its cost per call
        a = a.astype(np.float64)
    return a


def normalize(v, *, return_length=False):
    """Unit vectors along ``v``.

    Parameters
    ----------
    v : array_like, shape (..., 3)
    return_length : bool, keyword-only
        Also return ``|v|``, shape ``(...)``.

    Returns
    -------
    unit : ndarray, shape (..., 3), same float dtype as ``v``
    length : ndarray, shape (...), only if ``return_length``

    Notes
    -----
    .. math:: \\hat v = v / |v|, \\qquad \\hat 0 = 0

    Guard: a zero vector normalises to the zero vector (it then contributes no
    light), never NaN. Vectors too long or too short for ``x² + y² + z²`` in
    the working precision are rescaled by their largest component first.

    Examples
    --------
    >>> normalize([3.0, 0.0, 4.0])
    array([0.6, 0. , 0.8])
    """
    v = _check3("v", v)
    unit, length = normalize_c(_c(v).copy())
    unit = _last(unit)
    return (unit, length) if return_length else unit


def dot(a, b):
    """``a·b`` over the last axis of two ``(..., 3)`` arrays.

    Notes
    -----
    .. math:: a \\cdot b = a_x b_x + a_y b_y + a_z b_z

    For unit vectors this is the cosine of the angle between them.

    Examples
    --------
    >>> float(dot([1.0, 2.0, 3.0], [4.0, 5.0, 6.0]))
    32.0
    """
    a, b = np.broadcast_arrays(_check3("a", a), _check3("b", b))
    return dot_c(_c(a), _c(b))


def reflect(l, n):
    """Mirror ``l`` about the unit normal ``n``: ``r = 2(n·l)n − l``.

    Both point away from the surface; for unit ``l`` and ``n``, ``|r| = 1`` and
    reflecting twice gives ``l`` back.

    Notes
    -----
    .. math:: r = 2 (n \\cdot l)\\, n - l

    Examples
    --------
    >>> reflect([1.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    array([-1.,  0.,  1.])
    """
    l, n = np.broadcast_arrays(_check3("l", l), _check3("n", n))
    return _last(reflect_c(_c(l), _c(n)))


def one_minus_cos(a, b):
    """``1 − a·b`` for unit vectors ``a``, ``b``, computed as ``|a − b|²/2``.

    Notes
    -----
    .. math:: 1 - a \\cdot b = \\tfrac12 |a - b|^2 \\quad (|a| = |b| = 1)

    Exact in relative terms for nearly parallel vectors, where ``1 − a·b``
    cancels catastrophically.
    """
    a, b = np.broadcast_arrays(_check3("a", a), _check3("b", b))
    return one_minus_cos_c(_c(a), _c(b))
