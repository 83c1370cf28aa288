"""Rectangular area lights over a Lambertian surface: exact, point and Monte Carlo.

A point light is an idealisation: real lamps have a size. This module
computes the light a *finite* rectangle sends to a diffuse surface four ways,
so their accuracy and cost can be compared:

- :func:`area_irradiance` with ``method="exact"``: the closed form for a polygon
  (Lambert's formula, see :func:`polygon_irradiance`), exact up to rounding;
- ``method="point"``: the whole light concentrated at its centre;
- ``method="uniform"``: a Monte Carlo estimate from ``N`` points drawn
  uniformly on the light;
- ``method="stratified"``: the same with the light cut into ``N`` cells and
  one point drawn in each cell.

Directions point *away from the surface point*, as everywhere in phonglab:
``n`` is the surface normal and ``x → y`` points from the shaded point ``x``
to a point ``y`` on the light.

Units follow the Phong model: the diffuse term is ``k_d ∘ I_d ∘ E``, where
``E`` is the light's irradiance (for a point light of intensity ``I`` with
inverse-square attenuation, ``E = I cos θ / d²``). The light's ``intensity``
is its on-axis radiant intensity ``I₀ = L A`` (radiance ``L`` times area
``A``), so far away it acts like a point light of that intensity whose
brightness falls off as the cosine of the angle off its axis (a Lambertian
emitter). Area lights have no specular term here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .model import MAX_INTENSITY, InvalidValue, Material, _number, _rgb, vec3
from .vectors import working_dtype

__all__ = [
    "AREA_METHODS",
    "AreaLight",
    "polygon_irradiance",
    "area_irradiance",
    "area_diffuse",
    "strata_shape",
]

#: methods of :func:`area_irradiance`, cheapest first
AREA_METHODS = ("point", "uniform", "stratified", "exact")

#: Monte Carlo evaluates at most this many (point, sample) pairs at once
_MC_BLOCK = 1 << 20


@dataclass(frozen=True, kw_only=True)
class AreaLight:
    """A one-sided rectangular light of uniform radiance.

    Parameters
    ----------
    position : 3 floats
        The centre of the rectangle.
    edge_u, edge_v : 3 floats
        Its two full edge vectors (not parallel, not zero). The corners are
        ``position ± edge_u/2 ± edge_v/2``.
    color : float or RGB triple, default white
    intensity : float >= 0, default 1
        The on-axis radiant intensity ``I₀ = L A`` (radiance times area).

    Notes
    -----
    The light emits on the side of its normal ``m = (u × v) / |u × v|``, so
    ``edge_u = (1, 0, 0)``, ``edge_v = (0, 0, 1)`` makes a 1 × 1 ceiling
    panel shining down (``m = (0, -1, 0)``). Points behind its plane receive
    nothing.
    """

    position: tuple[float, float, float]
    edge_u: tuple[float, float, float] = (1.0, 0.0, 0.0)
    edge_v: tuple[float, float, float] = (0.0, 0.0, 1.0)
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    intensity: float = 1.0

    def __post_init__(self):
        for name in ("position", "edge_u", "edge_v"):
            object.__setattr__(self, name, vec3(f"AreaLight.{name}", getattr(self, name),
                                                 nonzero=name != "position"))
        object.__setattr__(self, "color", _rgb("AreaLight.color", self.color))
        object.__setattr__(self, "intensity", _number("AreaLight.intensity", self.intensity, maximum=MAX_INTENSITY))
        cross = np.cross(self.edge_u, self.edge_v)
        scale = math.hypot(*self.edge_u) * math.hypot(*self.edge_v)
        if not np.linalg.norm(cross) > 1e-12 * scale:
            raise InvalidValue("AreaLight.edge_v", self.edge_v,
                               f"must not be parallel to edge_u {self.edge_u} (the rectangle has no area)")

    @property
    def area(self) -> float:
        """``A = |u × v|``."""
        return float(np.linalg.norm(np.cross(self.edge_u, self.edge_v)))

    @property
    def normal(self) -> np.ndarray:
        """The unit normal ``m`` on the emitting side, float64 (3,)."""
        cross = np.cross(self.edge_u, self.edge_v)
        return cross / np.linalg.norm(cross)

    @property
    def radiance(self) -> float:
        """``L = I₀ / A``."""
        return self.intensity / self.area

    @property
    def vertices(self) -> np.ndarray:
        """The 4 corners, counter-clockwise about the normal ``m``, float64 (4, 3)."""
        c, u, v = (np.asarray(a, dtype=np.float64) for a in (self.position, self.edge_u, self.edge_v))
        return np.stack([c - u / 2 - v / 2, c + u / 2 - v / 2, c + u / 2 + v / 2, c - u / 2 + v / 2])

    @property
    def diffuse_rgb(self) -> tuple[float, float, float]:
        """The colour times the intensity, like the point lights' ``I_d``."""
        return tuple(self.intensity * c for c in self.color)  # type: ignore[return-value]


# ---------------------------------------------------------------------------
# the exact closed form


def _edge_term(a, b, n):
    """``Θ (n·γ)`` for the edge from ``a`` to ``b`` (vectors from the shaded point).

    ``Θ`` is the angle between ``a`` and ``b`` (``atan2(|a×b|, a·b)``, accurate
    for small and large angles) and ``γ = (a × b)/|a × b|``. An edge seen
    end-on (``a × b = 0``) subtends nothing and adds 0.
    """
    c = np.cross(a, b)
    size = np.linalg.norm(c, axis=-1)
    theta = np.arctan2(size, np.einsum("...i,...i->...", a, b))
    nc = np.einsum("...i,...i->...", n, c)
    ok = size > 0
    return np.where(ok, theta * nc / np.where(ok, size, 1), 0)


def polygon_irradiance(points, normals, vertices):
    """The cosine-weighted solid angle of a convex polygon seen from each point.

    Parameters
    ----------
    points, normals : array_like, shape (..., 3)
        Shaded points and their unit normals (they broadcast together).
    vertices : array_like, shape (k, 3)
        A planar convex polygon, its corners counter-clockwise about the
        normal of its emitting side.

    Returns
    -------
    ndarray, shape (...)
        ``∫ max(0, n·ω) dω`` over the directions ``ω`` in which the front of
        the polygon is seen; multiply by the radiance ``L`` for the
        irradiance. Float32 when both inputs are float32, else float64.

    Notes
    -----
    The irradiance from an emitter of uniform radiance ``L`` is

    .. math:: E(x) = L \\int_{\\Omega} \\max(0, n \\cdot \\omega) \\, d\\omega .

    For a polygon seen entirely above the tangent plane the integrand is just
    ``n·ω``, so ``E = L n·Φ`` with the *vector irradiance* ``Φ = ∫ ω dω``
    over the polygon's image on the unit sphere. That image and the point
    ``x`` bound a solid cone ``K`` of unit radius. The outward unit normal
    integrates to zero over any closed surface, and the surface of ``K`` is
    the spherical patch (normal ``ω``, area element ``dω``) plus one flat
    circular sector per edge: the edge from corner ``p_i`` to ``p_{i+1}``,
    seen as the unit vectors ``v_i = (p_i - x)/|p_i - x|`` and ``v_{i+1}``,
    spans a sector of angle ``Θ_i`` and area ``Θ_i / 2`` lying in the plane
    with unit normal ``γ_i``. Hence (Lambert, *Photometria*, 1760; in vector
    form Arvo, 1995)

    .. math::

        \\int_{\\Omega} \\omega \\, d\\omega = -\\frac12 \\sum_i \\Theta_i \\, \\gamma_i,
        \\qquad
        \\Theta_i = \\angle(v_i, v_{i+1}), \\qquad
        \\gamma_i = \\frac{v_i \\times v_{i+1}}{|v_i \\times v_{i+1}|},

    with the corners counter-clockwise about the emitter's normal (seen from
    its front), for which ``γ_i`` is the sector's outward normal; so

    .. math:: E(x) = -\\frac{L}{2} \\sum_i \\Theta_i \\, (n \\cdot \\gamma_i).

    Seen from behind, the same corners wind the other way and the sum changes
    sign, so ``max(0, ·)`` of it makes the emitter one-sided. Unnormalised
    ``p_i − x`` give the same ``Θ_i`` and ``γ_i``.

    Horizon: where part of the polygon lies below the tangent plane
    (``n·(p − x) < 0``) the integrand ``max(0, n·ω)`` is not ``n·ω``, so the
    polygon is first clipped to the plane. A convex polygon crosses the plane
    at most once each way: each edge keeps its part above the plane, and one
    edge is added along the plane from the exit point to the entry point. A
    corner exactly on the plane counts as below it.

    Examples
    --------
    A unit square at height 1, centred above the point:

    >>> square = [[-.5, -.5, 1], [-.5, .5, 1], [.5, .5, 1], [.5, -.5, 1]]  # ccw about -z
    >>> round(float(polygon_irradiance([0, 0, 0.0], [0, 0, 1.0], square)), 6)
    0.752275
    """
    points, normals = np.asarray(points), np.asarray(normals)
    dtype = working_dtype(points, normals)
    shape = np.broadcast_shapes(points.shape, normals.shape)
    x = np.broadcast_to(points, shape).reshape(-1, 3).astype(dtype)
    n = np.broadcast_to(normals, shape).reshape(-1, 3).astype(dtype)
    p = np.asarray(vertices, dtype=dtype)

    # corners seen from each point, and their heights above its tangent plane
    w = p[None, :, :] - x[:, None, :]  # (P, k, 3)
    height = np.einsum("pi,pki->pk", n, w)
    above = height > 0
    a, b = w, np.roll(w, -1, axis=1)
    ha, hb = height, np.roll(height, -1, axis=1)
    above_a, above_b = above, np.roll(above, -1, axis=1)

    # where each edge crosses the plane (only used where it does)
    crossing_edge = above_a != above_b
    t = np.where(crossing_edge, ha / np.where(crossing_edge, ha - hb, 1), 0)
    cross_point = a + t[..., None] * (b - a)

    # each edge's part above the plane: a→b, a→exit, entry→b or nothing
    start = np.where((above_a | ~above_b)[..., None], a, cross_point)
    end = np.where((above_b | ~above_a)[..., None], b, cross_point)
    keep = above_a | above_b
    n_k = n[:, None, :]
    total = np.where(keep, _edge_term(start, end, n_k), 0).sum(axis=1)

    # the edge along the horizon, from the exit point to the entry point
    exits = above_a & ~above_b
    entries = ~above_a & above_b
    exit_point = (cross_point * exits[..., None]).sum(axis=1)
    entry_point = (cross_point * entries[..., None]).sum(axis=1)
    closing = exits.any(axis=1) & entries.any(axis=1)
    total += np.where(closing, _edge_term(exit_point, entry_point, n), 0)

    # one-sided emitter: the back of the polygon gives a negative sum
    result = np.maximum(-0.5 * total, 0).astype(dtype)
    return result.reshape(shape[:-1])


# ---------------------------------------------------------------------------
# the point approximation and Monte Carlo


def _point_kernel(light: AreaLight, x, n, y):
    """``max(0, cos θ_x) max(0, cos θ_y) / d²`` for light points ``y`` (..., 3)."""
    m = light.normal.astype(x.dtype)
    d = y - x
    dist2 = np.einsum("...i,...i->...", d, d)
    cos_x = np.einsum("...i,...i->...", n, d)  # times d
    cos_y = -np.einsum("...i,...i->...", m, d)  # times d
    ok = (cos_x > 0) & (cos_y > 0) & (dist2 > 0)
    safe = np.where(ok, dist2, 1)
    return np.where(ok, cos_x * cos_y / (safe * safe), 0)


def strata_shape(samples: int) -> tuple[int, int]:
    """The ``(rows, columns)`` grid of cells used by stratified sampling.

    ``rows`` is the largest divisor of ``samples`` not above ``√samples``, so
    there are exactly ``samples`` cells (a perfect square gives a square
    grid; a prime gives thin strips, which still stratify).

    Examples
    --------
    >>> strata_shape(64), strata_shape(12), strata_shape(7)
    ((8, 8), (3, 4), (1, 7))
    """
    rows = max(d for d in range(1, math.isqrt(samples) + 1) if samples % d == 0)
    return rows, samples // rows


def _monte_carlo(light: AreaLight, x, n, samples: int, stratified: bool, rng):
    """Mean of ``A · kernel`` over ``samples`` points on the light, per shaded point."""
    count = x.shape[0]
    c = np.asarray(light.position, x.dtype)
    u = np.asarray(light.edge_u, x.dtype)
    v = np.asarray(light.edge_v, x.dtype)
    rows, cols = strata_shape(samples) if stratified else (1, 1)
    block = max(1, _MC_BLOCK // max(count, 1))
    total = np.zeros(count, x.dtype)
    for first in range(0, samples, block):
        k = np.arange(first, min(first + block, samples))
        # a random point in [0, 1)²: anywhere, or inside cell k of the grid
        st = rng.random((count, k.size, 2)).astype(x.dtype)
        if stratified:
            st[..., 0] = (k // cols + st[..., 0]) / rows
            st[..., 1] = (k % cols + st[..., 1]) / cols
        y = c + (st[..., 1:2] - 0.5) * u + (st[..., 0:1] - 0.5) * v
        total += _point_kernel(light, x[:, None, :], n[:, None, :], y).sum(axis=1)
    return total * (light.area / samples)


def area_irradiance(light: AreaLight, points, normals, *, method: str = "exact", samples: int = 64, seed=None):
    """Irradiance ``E`` from an area light at surface points, by one of four methods.

    Parameters
    ----------
    light : AreaLight
    points, normals : array_like, shape (..., 3)
        Shaded points and unit normals; they broadcast together.
    method : {"exact", "point", "uniform", "stratified"}
        ``"exact"``: Lambert's closed form (:func:`polygon_irradiance`);
        ``"point"``: the light concentrated at its centre;
        ``"uniform"``: Monte Carlo with ``samples`` uniform points on the light;
        ``"stratified"``: Monte Carlo with one uniform point in each of
        ``samples`` equal cells (:func:`strata_shape`).
    samples : int >= 1
        Monte Carlo sample count per point (ignored by "exact" and "point").
    seed : int, numpy Generator or None
        Seeds the Monte Carlo draws; the same seed gives the same estimate.

    Returns
    -------
    ndarray, shape (...)
        ``E``, in the units of ``light.intensity``; float32 when both inputs
        are float32, else float64.

    Notes
    -----
    With ``y`` a point on the light, ``d = |y − x|``, ``cos θ_x = n·(y − x)/d``
    and ``cos θ_y = m·(x − y)/d``:

    .. math::

        E(x) = L \\int_A \\frac{\\max(0,\\cos\\theta_x)\\max(0,\\cos\\theta_y)}{d^2}\\,dA_y
             \\approx \\frac{L A}{N} \\sum_{j=1}^{N}
             \\frac{\\max(0,\\cos\\theta_x)\\max(0,\\cos\\theta_y)}{d^2}\\Big|_{y_j}

    which is unbiased for uniform ``y_j`` (error ∝ ``1/√N``) and for one
    uniform ``y_j`` per cell (stratified: smaller, for a smooth integrand
    ∝ ``1/N`` in two dimensions). The point approximation evaluates the
    integrand once, at the centre, with weight ``A``:
    ``E ≈ I₀ \\max(0,\\cos\\theta_x)\\max(0,\\cos\\theta_y) / d²``.
    """
    if not isinstance(light, AreaLight):
        raise InvalidValue("light", light, "must be an AreaLight")
    if method not in AREA_METHODS:
        raise InvalidValue("method", method, f"must be one of {', '.join(AREA_METHODS)}")
    points, normals = np.asarray(points), np.asarray(normals)
    dtype = working_dtype(points, normals)
    shape = np.broadcast_shapes(points.shape, normals.shape)
    x = np.broadcast_to(points, shape).reshape(-1, 3).astype(dtype)
    n = np.broadcast_to(normals, shape).reshape(-1, 3).astype(dtype)
    if method == "exact":
        e = polygon_irradiance(x, n, light.vertices) * dtype.type(light.radiance)
    elif method == "point":
        centre = np.asarray(light.position, dtype)
        e = _point_kernel(light, x, n, centre) * dtype.type(light.intensity)
    else:
        if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
            raise InvalidValue("samples", samples, "must be an integer >= 1")
        rng = np.random.default_rng(seed)
        e = _monte_carlo(light, x, n, int(samples), method == "stratified", rng) * dtype.type(light.radiance)
    return np.asarray(e, dtype).reshape(shape[:-1])


def area_diffuse(points, normals, *, material: Material, light: AreaLight, method: str = "exact",
                 samples: int = 64, seed=None):
    """The diffuse light an area light adds to a Lambertian surface, per RGB channel.

    Parameters
    ----------
    points, normals : array_like, shape (..., 3)
    material : Material
        Only ``kd`` is used.
    light : AreaLight
    method, samples, seed
        As in :func:`area_irradiance`.

    Returns
    -------
    ndarray, shape (..., 3)
        ``k_d ∘ color ∘ E``, in the working dtype; add it to a
        :func:`~phonglab.core.shade` colour.

    Notes
    -----
    .. math:: I_{diffuse} = k_d \\circ c_{light} \\, E(x)

    the area light's counterpart of ``k_d ∘ I_d max(0, n·l) f`` for a point
    light with inverse-square attenuation ``f = 1/d²``.
    """
    e = area_irradiance(light, points, normals, method=method, samples=samples, seed=seed)
    rgb = np.asarray(material.kd) * np.asarray(light.color)
    return e[..., None] * rgb.astype(e.dtype)
