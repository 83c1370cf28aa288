"""The Cook–Torrance microfacet model: GGX distribution, height-correlated Smith visibility, Schlick's Fresnel.

Directions point *away from the surface point*, as everywhere in the core:
``n`` the unit normal, ``l`` towards the light, ``v`` towards the eye and
``h = normalize(l + v)`` the half vector, the normal of the microfacets that
mirror ``l`` into ``v``.

For one light the model reflects

.. math::

    L_o = \\pi \\left[ k_d \\circ I_d \\, \\frac{(1 - F)(1 - m)}{\\pi}
          + k_s \\circ I_s \\, D \\, V \\, F \\right] (n \\cdot l)

where ``m`` is ``metallic``, ``k_d`` the base colour, ``k_s`` a scale of the
specular lobe (1 is physical) and

- :func:`ggx_distribution`: ``D = α² / (π ((n·h)²(α² − 1) + 1)²)``, the
  GGX (Trowbridge–Reitz) distribution of microfacet normals, ``α = roughness²``;
- :func:`smith_visibility`: ``V = G₂ / (4 (n·l)(n·v))`` for the
  height-correlated Smith masking-shadowing of GGX,
  ``V = 0.5 / ((n·l) √((n·v)²(1 − α²) + α²) + (n·v) √((n·l)²(1 − α²) + α²))``;
- :func:`schlick_fresnel`: ``F = F₀ + (1 − F₀)(1 − v·h)⁵`` per channel, with
  ``F₀`` = 0.04 for a dielectric and the base colour for a metal, mixed by
  ``metallic`` (:func:`fresnel_f0`).

**Radiance convention.** The factor π in front is the π of a punctual light,
folded in as real-time engines fold it: a light of intensity ``I`` gives a
surface the irradiance ``π I (n·l)`` in these units. So a white Lambertian
surface lit head-on by a unit light reflects 1, exactly as Phong's ``k_d = 1``
does, and the two models can be set side by side with the same lights.

**Guards.** The model is one-sided: both terms are exactly 0 where
``n·l ≤ 0`` or ``n·v ≤ 0`` (the shading kernels apply the two-sided rule
first, as for Phong). ``roughness`` is clamped below at
:data:`MIN_ROUGHNESS` (so ``α ≥ 0.045² ≈ 2·10⁻³``), which keeps ``D`` finite
(at most ``1/(π α²) ≈ 7.8·10⁴``) in float32 as in float64. ``1 − (n·h)²`` is
computed from ``d = 1 − n·h`` as ``d(2 − d)``, and ``d`` itself as
``|n − h|²/2`` by the callers, so ``D`` keeps its relative precision at the
peak of a sharp lobe, where ``1 − (n·h)²`` would cancel. The visibility is
used as ``(n·l)·V`` (:func:`smith_visibility_nl`), which stays finite as
``n·l`` or ``n·v`` reach 0.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "MIN_ROUGHNESS",
    "DIELECTRIC_F0",
    "ggx_alpha",
    "ggx_distribution",
    "smith_visibility",
    "smith_visibility_nl",
    "schlick_fresnel",
    "fresnel_f0",
    "phong_normalisation",
]

#: The smallest perceptual roughness the model uses (a smaller one is raised to it): α ≥ 0.045².
#: A perfect mirror (roughness 0) would make ``D`` a Dirac delta that no sampled surface shows.
MIN_ROUGHNESS = 0.045

#: ``F₀`` of a dielectric: about 4 % of light is reflected head-on from glass, water or plastic.
DIELECTRIC_F0 = 0.04


def ggx_alpha(roughness: float) -> float:
    """The GGX width ``α = max(roughness, MIN_ROUGHNESS)²`` from the perceptual roughness in [0, 1].

    Examples
    --------
    >>> ggx_alpha(0.5)
    0.25
    >>> ggx_alpha(0.0) == MIN_ROUGHNESS ** 2
    True
    """
    r = max(float(roughness), MIN_ROUGHNESS)
    return r * r


def ggx_distribution(d_nh, alpha: float):
    """The GGX (Trowbridge–Reitz) normal distribution ``D`` from ``d_nh = 1 − n·h``.

    Parameters
    ----------
    d_nh : ndarray
        ``1 − n·h`` in [0, 1] (``n·h ≥ 0``), best computed as ``|n − h|²/2``.
    alpha : float
        The width ``α`` (:func:`ggx_alpha`), ``α > 0``.

    Returns
    -------
    ndarray
        ``D`` in the dtype of ``d_nh``.

    Notes
    -----
    .. math:: D = \\frac{\\alpha^2}{\\pi \\left((n\\cdot h)^2 (\\alpha^2 - 1) + 1\\right)^2}
              = \\frac{\\alpha^2}{\\pi \\left(s + (1 - s)\\,\\alpha^2\\right)^2},
              \\quad s = 1 - (n\\cdot h)^2 = d(2 - d)

    The second form adds two non-negative numbers, so nothing cancels.
    ``∫ D (n·h) dω_h = 1`` over the hemisphere.

    Examples
    --------
    >>> float(ggx_distribution(np.float64(0.0), 0.25) * np.pi * 0.25**2)  # head-on: 1/(π α²)
    1.0
    """
    d = np.asarray(d_nh)
    dtype = d.dtype if d.dtype.kind == "f" else np.dtype(np.float64)
    d = d.astype(dtype, copy=False)
    one = dtype.type(1)
    a2 = dtype.type(alpha * alpha)
    s = d * (dtype.type(2) - d)  # sin² of the angle between n and h
    denom = s + (one - s) * a2
    return a2 / (dtype.type(math.pi) * denom * denom)


def smith_visibility(nl, nv, alpha: float):
    """The height-correlated Smith–GGX visibility ``V = G₂ / (4 (n·l)(n·v))``, for ``n·l, n·v > 0``.

    Notes
    -----
    .. math:: V = \\frac{1/2}{(n\\cdot l)\\sqrt{(n\\cdot v)^2 (1 - \\alpha^2) + \\alpha^2}
              + (n\\cdot v)\\sqrt{(n\\cdot l)^2 (1 - \\alpha^2) + \\alpha^2}}

    Head-on (``n·l = n·v = 1``) it is 1/4. The shading kernels use
    :func:`smith_visibility_nl`, ``(n·l)·V``, which stays finite at grazing
    angles; this form is for the readout and the tests.

    Examples
    --------
    >>> float(smith_visibility(np.float64(1.0), np.float64(1.0), 0.25))
    0.25
    """
    nl, nv, lam_l, lam_v, dtype = _smith_roots(nl, nv, alpha)
    return dtype.type(0.5) / (nl * lam_v + nv * lam_l)


def _smith_roots(nl, nv, alpha: float):
    """``(n·l, n·v, √((n·l)²(1 − α²) + α²), √((n·v)²(1 − α²) + α²), dtype)`` for the visibility."""
    nl, nv = np.asarray(nl), np.asarray(nv)
    dtype = np.result_type(nl, nv, np.float32)
    a2 = dtype.type(alpha * alpha)
    one = dtype.type(1)
    return nl, nv, np.sqrt(nl * nl * (one - a2) + a2), np.sqrt(nv * nv * (one - a2) + a2), dtype


def smith_visibility_nl(nl, nv, alpha: float):
    """``(n·l)·V``: the visibility times the cosine it multiplies, finite for every ``n·l, n·v > 0``.

    Notes
    -----
    .. math:: (n\\cdot l)\\,V = \\frac{1/2}{\\sqrt{(n\\cdot v)^2 (1 - \\alpha^2) + \\alpha^2}
              + (n\\cdot v)\\sqrt{(n\\cdot l)^2 (1 - \\alpha^2) + \\alpha^2} \\,/\\, (n\\cdot l)}

    The first root is at least ``α``, so the result is at most ``1/(2α)``;
    as ``n·l → 0`` the second term grows without bound (to inf at worst)
    and the result goes to 0, never NaN. The caller gates ``n·l ≤ 0`` and
    ``n·v ≤ 0`` to exactly 0.
    """
    nl, nv, lam_l, lam_v, dtype = _smith_roots(nl, nv, alpha)
    one = dtype.type(1)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        ratio = np.where(nl > 0, nv * lam_l / np.where(nl > 0, nl, one), np.inf)
        return dtype.type(0.5) / (lam_v + ratio)


def fresnel_f0(base_color, metallic: float) -> np.ndarray:
    """Head-on reflectance ``F₀ = min(1, 0.04 (1 − m) + k_d m)`` per channel (``m`` = metallic, ``k_d`` the base colour).

    A surface reflects at most all the light: a base colour above 1 (allowed,
    as for Phong's ``k_d``) gives F₀ = 1, never a Fresnel above 1 and with it a
    negative diffuse weight ``(1 − F)(1 − m)``.

    Examples
    --------
    >>> fresnel_f0((1.0, 0.5, 0.0), 1.0).tolist(), fresnel_f0((1.0, 0.5, 0.0), 0.0).tolist()
    ([1.0, 0.5, 0.0], [0.04, 0.04, 0.04])
    """
    base = np.asarray(base_color, np.float64)
    m = float(metallic)
    return np.minimum(DIELECTRIC_F0 * (1 - m) + base * m, 1.0)


def schlick_fresnel(d_vh, f0):
    """Schlick's Fresnel ``F = F₀ + (1 − F₀)(1 − v·h)⁵`` from ``d_vh = 1 − v·h``.

    Parameters
    ----------
    d_vh : ndarray, shape (...)
        ``1 − v·h`` in [0, 1].
    f0 : array_like, shape (3,)
        Head-on reflectance per channel (:func:`fresnel_f0`).

    Returns
    -------
    ndarray, shape (..., 3)
        In the dtype of ``d_vh``.

    Examples
    --------
    >>> schlick_fresnel(np.float64(1.0), (0.04, 0.04, 0.04)).tolist()  # grazing: all light reflected
    [1.0, 1.0, 1.0]
    """
    d = np.asarray(d_vh)
    dtype = d.dtype if d.dtype.kind == "f" else np.dtype(np.float64)
    d = d.astype(dtype, copy=False)
    f0 = np.asarray(f0, np.float64).astype(dtype)
    d2 = d * d
    w = (d2 * d2 * d)[..., None]  # (1 − v·h)⁵
    return f0 + (dtype.type(1) - f0) * w


def phong_normalisation(shininess: float) -> float:
    """The factor ``(α + 2)/(2π)`` that makes the Phong lobe ``(r·v)^α (n·l)`` conserve energy.

    Notes
    -----
    .. math:: \\int_{\\Omega} \\frac{\\alpha + 2}{2\\pi} \\cos^{\\alpha}\\theta \\, \\cos\\theta \\, d\\omega = 1

    so a normalised lobe seen along the normal reflects exactly the light that
    arrives, at every ``α``; plain Phong reflects ``2/(α + 1)`` of it there.

    Examples
    --------
    >>> round(phong_normalisation(0.0) * math.pi, 12)
    1.0
    """
    return (float(shininess) + 2.0) / (2.0 * math.pi)
