"""The white furnace: how much of the light arriving at a surface each model sends back.

A white furnace surrounds a surface with uniform light of radiance 1 from
every direction. What the surface reflects towards the eye is its
*directional albedo*

.. math:: \\rho(v) = \\int_{\\Omega} f(l, v) \\, (n\\cdot l) \\, d\\omega_l ,

the fraction of the arriving energy sent back. A model that conserves
energy keeps ``ρ ≤ 1`` for every view; a model that makes light gives
``ρ > 1`` somewhere.

- **Cook–Torrance** (:mod:`phonglab.core.microfacet`), a white metal
  (``F = 1``): ``ρ ≤ 1``, and less than 1 at high roughness, because a
  single-scattering microfacet model drops the light that bounces between
  microfacets. With ``α = 1`` and view along the normal it is exactly
  ``1 − ln 2 ≈ 0.307``; for any view at ``α = 1`` it is
  ``1 − μ ln((1 + μ)/μ)``, ``μ = n·v`` (:func:`ggx_albedo_alpha1`).
- **Phong** with ``k_s = 1`` reflects ``(r·v)^α`` for a unit light, so its
  BRDF is ``(r·v)^α / (π n·l)`` and, head-on, ``ρ = 2/(α + 1)``: more light
  than arrives for every ``α < 1``.
- **Energy-normalised Phong** multiplies the lobe by
  :func:`~phonglab.core.microfacet.phong_normalisation` ``(α + 2)/(2π)`` and
  keeps the ``n·l``: ``ρ = 1`` head-on and below 1 elsewhere.

This is the core's because it is the models' physics (how much light
each creates or loses), used by the tests, the furnace plot and lesson 13.
The integrals are deterministic quadratures, importance-mapped so that a
sharp lobe is resolved: Gauss–Legendre in the sampling variable of each
lobe (the GGX distribution of half vectors, or ``cos^α`` around the mirror
direction), uniform in the azimuth, where the integrand is periodic.
Each evaluates the core's own functions for the lobe.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .microfacet import ggx_alpha, ggx_distribution, phong_normalisation, smith_visibility_nl

__all__ = ["directional_albedo", "ggx_albedo_alpha1", "FURNACE_MODELS"]

#: The lobes the furnace measures.
FURNACE_MODELS = ("cook-torrance", "phong", "phong-normalised")


@functools.lru_cache(maxsize=8)
def _nodes(n_xi: int, n_phi: int):
    """Quadrature nodes and weights over [0, 1] × [0, 2π), the weights summing to 1."""
    x, w = np.polynomial.legendre.leggauss(n_xi)
    xi, w_xi = (x + 1) / 2, w / 2
    phi = (np.arange(n_phi) + 0.5) * (2 * math.pi / n_phi)
    XI, PHI = np.meshgrid(xi, phi, indexing="ij")
    W = np.repeat(w_xi[:, None] / n_phi, n_phi, axis=1)
    return XI.ravel(), PHI.ravel(), W.ravel()


def _frame(axis):
    """Two unit vectors perpendicular to the unit ``axis`` and to each other."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(axis, helper)
    t /= np.linalg.norm(t)
    return t, np.cross(axis, t)


def _around(axis, cos_t, phi):
    """Unit vectors at angle ``acos(cos_t)`` from ``axis``, at azimuth ``phi``."""
    t, b = _frame(axis)
    sin_t = np.sqrt(np.maximum(0.0, 1.0 - cos_t * cos_t))
    return (cos_t[:, None] * axis + (sin_t * np.cos(phi))[:, None] * t + (sin_t * np.sin(phi))[:, None] * b)


def directional_albedo(model: str, view_angle: float, *, roughness: float = 0.5, shininess: float = 1.0,
                       n_xi: int = 384, n_phi: int = 384) -> float:
    """The directional albedo ``ρ(v)`` of a white surface of ``model``, seen ``view_angle`` degrees off the normal.

    Parameters
    ----------
    model : {"cook-torrance", "phong", "phong-normalised"}
        A white metal (``F = 1``, specular lobe only) for Cook–Torrance; the
        specular lobe with ``k_s = 1`` for the two Phong forms.
    view_angle : float
        Degrees from the normal, in [0, 90).
    roughness, shininess : float, keyword-only
        The lobe's width: perceptual roughness for Cook–Torrance, ``α`` for Phong.
    n_xi, n_phi : int, keyword-only
        Quadrature nodes in the lobe's sampling variable and in the azimuth.

    Returns
    -------
    float
        ``∫ f (n·l) dω``: 1 for a perfect white reflector, more when the model makes light.

    Examples
    --------
    >>> round(directional_albedo("cook-torrance", 0.0, roughness=1.0), 4)  # 1 − ln 2
    0.3069
    >>> round(directional_albedo("phong", 0.0, shininess=0.5), 3)  # 2/(α + 1): light made
    1.333
    """
    if model not in FURNACE_MODELS:
        raise ValueError(f"model: must be one of {', '.join(FURNACE_MODELS)}, got {model!r}")
    if not 0.0 <= view_angle < 90.0:
        raise ValueError(f"view_angle: must be in [0, 90) degrees, got {view_angle!r}")
    theta = math.radians(view_angle)
    n = np.array([0.0, 0.0, 1.0])
    v = np.array([math.sin(theta), 0.0, math.cos(theta)])
    xi, phi, w = _nodes(n_xi, n_phi)

    if model == "cook-torrance":
        # half vectors distributed as D(h)(n·h): cos²θ_h = (1 − ξ)/(1 + (α² − 1)ξ)
        alpha = ggx_alpha(roughness)
        a2 = alpha * alpha
        cos_h = np.sqrt((1 - xi) / (1 + (a2 - 1) * xi))
        h = _around(n, cos_h, phi)
        vh = h @ v
        l = 2 * vh[:, None] * h - v
        nl, nv = l @ n, float(n @ v)
        ok = (nl > 0) & (vh > 0)
        # f (n·l) / pdf(l), pdf(l) = D (n·h) / (4 v·h); D cancels, F = 1 for a white metal
        g = np.where(ok, smith_visibility_nl(np.where(ok, nl, 1.0), np.full_like(nl, nv), alpha)
                     * 4 * vh / cos_h, 0.0)
        return float(np.sum(w * g))

    # Phong: l distributed as cos^α around the mirror direction m of v, pdf (α + 1)/(2π) cos^α ψ
    a = float(shininess)
    m = 2 * (n @ v) * n - v
    cos_psi = xi ** (1.0 / (a + 1.0))
    l = _around(m, cos_psi, phi)
    nl = l @ n
    lit = nl > 0
    if model == "phong":
        # f (n·l) = (r·v)^α / π: the ratio to the pdf is 2/(α + 1)
        g = np.where(lit, 2.0 / (a + 1.0), 0.0)
    else:
        # f (n·l) = (α + 2)/(2π) (r·v)^α (n·l)
        g = np.where(lit, phong_normalisation(a) * 2 * math.pi / (a + 1.0) * nl, 0.0)
    return float(np.sum(w * g))


def ggx_albedo_alpha1(view_angle: float) -> float:
    """The closed form of the white-metal albedo at ``α = 1``: ``1 − μ ln((1 + μ)/μ)``, ``μ = cos(view_angle)``.

    At ``α = 1`` the GGX distribution is uniform, ``D = 1/π``, and the
    height-correlated Smith term is ``G₂ = 2 μ_l μ / (μ_l + μ)``, so
    ``ρ = ½ ∫₀¹ μ_l / (μ + μ_l) dμ_l · 2``.

    Examples
    --------
    >>> round(ggx_albedo_alpha1(0.0), 6) == round(1 - math.log(2), 6)
    True
    """
    mu = math.cos(math.radians(view_angle))
    return 1.0 - mu * math.log((1.0 + mu) / mu)
