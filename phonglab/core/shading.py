"""The fast kernel: Phong and Blinn-Phong shading of many points.

Directions point *away from the surface point*: ``n`` the unit normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``.

.. math::

    I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
        + k_s \\circ I_{s,l} \\max(0, r\\cdot v)^{\\alpha} \\right]

Blinn-Phong uses ``n·h`` in place of ``r·v``. Specular is exactly zero
wherever ``n·l ≤ 0``. ``f_l`` is the distance attenuation times the spotlight
factor (:mod:`phonglab.core.physics`).

:func:`shade` executes a :class:`~phonglab.core.Plan`, so a skipped effect
costs nothing; planned and full evaluation agree to within an ulp. The points
are shaded in blocks held components first, ``(3, m)``, so every component is
one contiguous row. Names in the loop: ``dist`` is a light's distance,
``d_cos`` is ``1 − cos`` of the specular angle (``1 − r·v`` or ``1 − n·h``),
the form :func:`~phonglab.core.vectors.cos_power` raises to ``α``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .checks import as_points, check_lights, check_material, check_visibility, refuse_nonfinite, viewer
from .microfacet import fresnel_f0, ggx_alpha, ggx_distribution, smith_visibility_nl
from .model import DirectionalLight, InvalidValue, Material
from .physics import attenuation, face_forward, spot_factor
from .plan import LightPlan, Plan, plan_effects
from .record import ambient_intensity
from .vectors import const_row, cos_power, dot_c, normalize_c, one_minus_cos_c, unit_direction, working_dtype

__all__ = ["Shading", "shade"]

#: Points shaded per block: small enough that a block's temporaries stay in cache.
CHUNK = 32768


@dataclass(frozen=True)
class Shading:
    """Per-term result of :func:`shade`; every field has shape ``(..., 3)``.

    ``ambient`` and ``emission`` are constant over the points, and a term the
    plan skipped is zero everywhere: those are returned as read-only broadcast
    views. ``color`` is always a fresh array: the sum of the four terms,
    unclamped (values above 1 are over-exposed, not wrong).
    """

    ambient: np.ndarray
    diffuse: np.ndarray
    specular: np.ndarray
    emission: np.ndarray
    color: np.ndarray


def shade(
    points,
    normals,
    *,
    material: Material,
    lights,
    eye=None,
    view_direction=None,
    model: str = "phong",
    two_sided: bool = False,
    plan: Plan | str = "auto",
    visibility=None,
) -> Shading:
    """Shade points with the Phong or Blinn-Phong model, term by term.

    Parameters
    ----------
    points, normals : array_like, shape (..., 3)
        Surface points and their normals (any length; renormalised here, a
        zero normal receives no direct light). They broadcast together and
        must be finite where they are read: the points are read only for a
        light with a position or a local viewer (directional lights and an
        infinite viewer make the sum the same at every position).
    material : Material
    lights : sequence of Light
    eye : 3 floats, optional
        A local viewer: ``v = normalize(eye − p)``.
    view_direction : 3 floats, optional
        An infinite viewer: ``v = normalize(view_direction)`` everywhere.
    model : {"phong", "blinn-phong"}
    two_sided : bool
        Negate normals that face away from the eye (``n·v < 0``).
    plan : Plan, "auto" or "full"
        Which effects to compute: "auto" plans them with :func:`~phonglab.core.plan_effects`,
        "full" evaluates everything (the reference).
    visibility : mapping int -> array_like, optional
        Shadows: for a light's index in ``lights``, 1 (True) at each point the
        light reaches and 0 (False) where something blocks it, broadcasting to
        the points' shape without its last axis. A blocked light adds neither
        diffuse nor specular light there. Lights left out (and None) are not
        blocked anywhere. Who blocks what is decided by a ray caster above the
        core; the core only applies it.

    Returns
    -------
    Shading
        ``ambient``, ``diffuse``, ``specular``, ``emission`` and ``color``,
        each of shape ``(..., 3)`` in float32 when both inputs are float32,
        else float64.

    Notes
    -----
    .. math::

        I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
            + k_s \\circ I_{s,l} \\max(0, c_l)^{\\alpha} \\right]

    with ``c_l = r·v`` (Phong, ``r = 2(n·l)n − l``) or ``c_l = n·h`` (Blinn-Phong,
    ``h = normalize(l + v)``). Conventions and guards:

    - specular is exactly 0 where ``n·l ≤ 0``, at every α including 0;
    - ``c_l`` is clamped to [0, 1] and computed as ``1 − |a − b|²/2``, the
      power as ``exp(α·log1p(−d))``, accurate at α = 10⁶, or for an integer
      α ≤ :data:`~phonglab.core.vectors.SQUARING_MAX` by repeated squaring
      (within 2α ulps);
    - a zero-length ``n`` or ``l`` (e.g. a light on the point) contributes no
      diffuse or specular light; a zero ``v`` (the eye on the point) or ``h``
      (``l = −v``) no specular light;
    - the light factor ``f_l`` is :func:`~phonglab.core.attenuation` (distance
      floored at 1e-6, capped at 1e12) times :func:`~phonglab.core.spot_factor`
      (cone test with a few ulps of slack); the two-sided flip is
      :func:`~phonglab.core.face_forward`;
    - with ``visibility``, ``f_l`` is multiplied by the light's 0 or 1 at the
      point (``S_l``, the shadow term of the rendering equation's
      visibility): times 1 leaves every bit as it was, so a light given as
      visible everywhere shades exactly as one left out.

    :func:`~phonglab.core.shade_reference` is the same model written one
    light at a time, as in the lesson; the tests hold this kernel to it.

    Examples
    --------
    >>> import phonglab as pl
    >>> s = pl.shade([[0, 0, 1.0]], [[0, 0, 1.0]], eye=(0, 0, 5),
    ...              material=pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10),
    ...              lights=[pl.DirectionalLight(direction=(0, 0, 1))])
    >>> s.color.round(6).tolist()
    [[1.0, 1.0, 1.0]]
    """
    check_material(material)
    lights = check_lights(lights)
    eye, view_direction = viewer(eye, view_direction)
    points = as_points("points", points)
    normals = as_points("normals", normals)
    try:
        shape = np.broadcast_shapes(points.shape, normals.shape)
    except ValueError:
        raise InvalidValue("normals", f"array of shape {normals.shape}",
                           f"must broadcast with points of shape {points.shape}") from None
    if isinstance(plan, str):
        if plan not in ("auto", "full"):
            raise InvalidValue("plan", plan, "must be a Plan, 'auto' or 'full'")
        plan = plan_effects(material, lights, eye=eye, view_direction=view_direction,
                            two_sided=two_sided, model=model, full=plan == "full")
    elif not isinstance(plan, Plan):
        raise InvalidValue("plan", plan, "must be a Plan, 'auto' or 'full'")
    elif plan.material != material or plan.light_objects != lights or plan.model != model:
        raise InvalidValue("plan", "a plan for another material, lights or model",
                           "must be made by plan_effects() for this material, these lights and model")

    dtype = working_dtype(points, normals)
    n_points = math.prod(shape[:-1])
    P = np.broadcast_to(points, shape).reshape(-1, 3)
    N = np.broadcast_to(normals, shape).reshape(-1, 3)
    visibility = check_visibility(visibility, lights, shape[:-1])

    const = _Constants(material, lights, plan, eye, view_direction, dtype, points, normals)
    if visibility is not None:
        # each blocked light's 0 or 1 per point, in the working dtype, as one row
        const.seen = {i: seen.reshape(-1).astype(dtype) for i, seen in visibility.items()}
    no_term = np.zeros(3, dtype)
    # results are held channel first, (3, n): every write below is a contiguous row
    diffuse = np.empty((3, n_points), dtype) if plan.diffuse else None
    specular = np.empty((3, n_points), dtype) if plan.specular else None
    base = (const.ambient + const.emission)[:, None]  # the same at every point
    color = np.empty((3, n_points), dtype)
    if plan.lights:
        for start in range(0, n_points, CHUNK):
            stop = min(start + CHUNK, n_points)
            diffuse_block = None if diffuse is None else diffuse[:, start:stop]
            specular_block = None if specular is None else specular[:, start:stop]
            _shade_block(P[start:stop], N[start:stop], const, plan, diffuse_block, specular_block, start, stop)
            # colour = (diffuse + specular) + (ambient + emission), while the block is in cache
            _add_color(diffuse_block, specular_block, base, color[:, start:stop])
    else:
        color[...] = base

    def per_point(term, rgb):
        # (3, n) -> (..., 3) views; constant or skipped terms are read-only broadcast views
        return np.broadcast_to(rgb, shape) if term is None else term.T.reshape(shape)

    return Shading(
        ambient=per_point(None, const.ambient),
        diffuse=per_point(diffuse, no_term),
        specular=per_point(specular, no_term),
        emission=per_point(None, const.emission),
        color=per_point(color, None),
    )


# ---------------------------------------------------------------------------
# what the loop reads: constants per call and per light, vectors per block


@dataclass(frozen=True)
class _LightConstants:
    """One light's constants in the working dtype; vectors are (3, 1) columns."""

    plan: LightPlan
    kd_id: np.ndarray | None  # k_d ∘ I_d, when diffuse is computed
    ks_is: np.ndarray | None  # k_s ∘ I_s, when specular is computed
    # Cook–Torrance: the diffuse colour and the specular lobe's two parts, F = F₀ + (1 − F₀)(1 − v·h)⁵
    ct_diffuse: np.ndarray | None = None  # k_d ∘ I_d ∘ (1 − m)(1 − F₀)
    ct_f0: np.ndarray | None = None  # k_s ∘ I_s ∘ F₀
    ct_grazing: np.ndarray | None = None  # k_s ∘ I_s ∘ (1 − F₀)
    # a directional light
    l: np.ndarray | None = None  # the unit direction to the light, the same at every point
    l_plus_v: np.ndarray | None = None  # l + v, with an infinite viewer
    h: np.ndarray | None = None  # the unit half vector, with an infinite viewer
    h_zero: bool = False  # ... which is zero: l = −v
    # a point or spot light
    position: np.ndarray | None = None
    attenuation: tuple[float, float, float] = (1.0, 0.0, 0.0)  # (a, b, c)
    # a spot light
    axis: np.ndarray | None = None  # the unit axis, from the light outwards
    cutoff: float = 180.0
    exponent: float = 0.0


class _Constants:
    """What the per-point loop needs, precomputed once in the working dtype."""

    def __init__(self, material, lights, plan, eye, view_direction, dtype, points, normals):
        self.dtype = dtype
        self.model = plan.model
        ka = np.asarray(material.ka)
        self.ambient = (ka * ambient_intensity(lights)).astype(dtype) if plan.ambient else np.zeros(3, dtype)
        self.emission = np.asarray(material.emission, dtype) if plan.emission else np.zeros(3, dtype)
        self.shininess = material.shininess
        self.eye = None if eye is None else np.asarray(eye, dtype)[:, None]
        self.view = None
        if view_direction is not None:
            self.view = _unit(view_direction, dtype)
        kd, ks = np.asarray(material.kd), np.asarray(material.ks)
        self.cook_torrance = plan.model == "cook-torrance"
        if self.cook_torrance:
            self.alpha = ggx_alpha(material.roughness)
            self.f0 = fresnel_f0(material.kd, material.metallic)
            self.metallic = material.metallic
        # Cook–Torrance needs v for its diffuse term too (the Fresnel weight and the n·v gate)
        self.needs_view = plan.specular or plan.two_sided or (self.cook_torrance and bool(plan.lights))
        self.needs_points = (self.needs_view and eye is not None) or any(
            not isinstance(lights[lp.index], DirectionalLight) for lp in plan.lights)
        # the arrays the loop reads, checked for NaN and inf by refuse_nonfinite
        self.inputs = (("points", points), ("normals", normals)) if self.needs_points else (("normals", normals),)
        self.inputs_checked = False
        self.lights = [self._light(lp, lights[lp.index], plan, kd, ks) for lp in plan.lights]
        self.seen = None  # light index -> its visibility row (0 or 1 per point), when shadows are given

    def _light(self, lp, lt, plan, kd, ks) -> _LightConstants:
        dtype = self.dtype
        kd_id = (kd * np.asarray(lt.diffuse_rgb)).astype(dtype)[:, None] if plan.diffuse else None
        ks_is = (ks * np.asarray(lt.specular_rgb)).astype(dtype)[:, None] if plan.specular else None
        if self.cook_torrance:
            return self._cook_torrance_light(lp, lt, plan, kd, ks)
        if isinstance(lt, DirectionalLight):
            l = _unit(lt.direction, dtype)
            if not (plan.constant_view and lp.constant_l):
                return _LightConstants(plan=lp, kd_id=kd_id, ks_is=ks_is, l=l)
            # an infinite viewer too: l + v and h are the same at every point
            l_plus_v = l + self.view
            h = normalize_c(l_plus_v)[0]
            return _LightConstants(plan=lp, kd_id=kd_id, ks_is=ks_is, l=l, l_plus_v=l_plus_v, h=h,
                                   h_zero=not h.any())
        position = np.asarray(lt.position, dtype)[:, None]
        if not lp.spot:
            return _LightConstants(plan=lp, kd_id=kd_id, ks_is=ks_is, position=position,
                                   attenuation=lt.attenuation)
        return _LightConstants(plan=lp, kd_id=kd_id, ks_is=ks_is, position=position, attenuation=lt.attenuation,
                               axis=_unit(lt.direction, dtype), cutoff=lt.cutoff, exponent=lt.exponent)

    def _cook_torrance_light(self, lp, lt, plan, kd, ks) -> _LightConstants:
        """A light's constants for Cook–Torrance: its colours folded with ``F₀`` and ``metallic``."""
        dtype = self.dtype

        def column(rgb):
            return np.asarray(rgb, np.float64).astype(dtype)[:, None]

        i_d, i_s = np.asarray(lt.diffuse_rgb), np.asarray(lt.specular_rgb)
        terms = dict(
            kd_id=column(kd * i_d) if plan.diffuse else None,
            ks_is=column(ks * i_s) if plan.specular else None,
            ct_diffuse=column(kd * i_d * (1 - self.metallic) * (1 - self.f0)) if plan.diffuse else None,
            ct_f0=column(ks * i_s * self.f0) if plan.specular else None,
            ct_grazing=column(ks * i_s * (1 - self.f0)) if plan.specular else None,
        )
        if isinstance(lt, DirectionalLight):
            l = _unit(lt.direction, dtype)
            if not (plan.constant_view and lp.constant_l):
                return _LightConstants(plan=lp, l=l, **terms)
            h = normalize_c(l + self.view)[0]
            return _LightConstants(plan=lp, l=l, l_plus_v=l + self.view, h=h, h_zero=not h.any(), **terms)
        position = np.asarray(lt.position, dtype)[:, None]
        if not lp.spot:
            return _LightConstants(plan=lp, position=position, attenuation=lt.attenuation, **terms)
        return _LightConstants(plan=lp, position=position, attenuation=lt.attenuation,
                               axis=_unit(lt.direction, dtype), cutoff=lt.cutoff, exponent=lt.exponent, **terms)

    def refuse_nonfinite(self):
        """Check the inputs the loop reads for NaN and inf, once per call.

        The loop's normalisations prove clean blocks finite for free; this
        runs only when one of them meets a vector outside the direct range
        (NaN, inf, zero, tiny or huge).
        """
        if not self.inputs_checked:
            for name, a in self.inputs:
                refuse_nonfinite(name, a)
            self.inputs_checked = True


@dataclass(frozen=True)
class _Surface:
    """One block of points as every light sees them; vectors are (3, m) or (3, 1)."""

    p: np.ndarray | None  # the points, when a light or the viewer has a position
    n: np.ndarray  # unit normals, turned towards the eye when two-sided
    v: np.ndarray | None  # unit vectors to the eye, when specular or two-sided needs them
    v_len: np.ndarray | None  # |eye − p|, for a local viewer
    v_zero: bool  # the eye sits on some point: v = 0 there
    nv: np.ndarray | None = None  # n·v, for Cook–Torrance


def _unit(direction, dtype):
    """A light's or viewer's fixed direction as a (3, 1) unit column (see :func:`unit_direction`)."""
    return unit_direction(direction, dtype)[:, None]


# ---------------------------------------------------------------------------
# one block


def _shade_block(points, normals, const, plan, diffuse_out, specular_out, start=0, stop=None):
    """Shade one block of points (``start:stop`` of all), writing the (3, m) diffuse and specular blocks.

    The sums over lights go straight into the outputs.
    """
    dtype = const.dtype
    shape = (3, len(normals))
    refuse = const.refuse_nonfinite  # NaN or inf in the inputs shows up as a vector out of range
    p = None
    if const.needs_points:  # a local viewer or a light with a position
        p = np.empty(shape, dtype)
        np.copyto(p, points.T, casting="unsafe")
    n = np.empty(shape, dtype)
    np.copyto(n, normals.T, casting="unsafe")
    n, _ = normalize_c(n, out=n, before_rescaling=refuse)

    # the view vector: constant for an infinite viewer, else per point
    v = v_len = None
    v_zero = False
    if not const.needs_view:
        pass  # diffuse only and one-sided: V is never used
    elif const.eye is not None:
        v, v_len = normalize_c(np.subtract(const.eye, p), before_rescaling=refuse)
        v_zero = v_len.min() == 0  # the eye on a surface point: no specular there
    elif plan.constant_view:
        v = const.view
    else:  # the full evaluation keeps a per-point copy
        v = np.broadcast_to(const.view, shape).copy()

    # two-sided: the normals turned towards the eye
    if plan.two_sided:
        face_forward(n, v, axis=0, out=n)
    nv = dot_c(n, v) if const.cook_torrance and v is not None else None
    surface = _Surface(p=p, n=n, v=v, v_len=v_len, v_zero=v_zero, nv=nv)

    first = True
    for light in const.lights:
        lp = light.plan
        # direction to the light, and its distance for attenuation
        if light.l is not None:
            l = light.l if lp.constant_l else np.broadcast_to(light.l, shape).copy()
            dist = None
        else:
            l, dist = normalize_c(np.subtract(light.position, p), before_rescaling=refuse)
        nl = dot_c(n, l)

        # the light factor f_l = attenuation × spot; None where it is 1
        f = attenuation(dist, light.attenuation) if lp.attenuation else None
        if lp.spot:
            cos_axis = dot_c(l, light.axis)
            np.negative(cos_axis, out=cos_axis)  # the axis against the ray light -> point
            f_spot = spot_factor(cos_axis, cutoff=light.cutoff, exponent=light.exponent, out=cos_axis)
            f = f_spot if f is None else np.multiply(f, f_spot, out=f)
        if const.seen is not None and lp.index in const.seen:
            # the shadow: f_l times 0 where the light is blocked, 1 where it reaches the point
            seen = const.seen[lp.index][start:stop]
            f = seen if f is None else np.multiply(f, seen, out=f)

        if const.cook_torrance:
            _cook_torrance(surface, l, nl, f, light, const, plan, diffuse_out, specular_out, first)
            first = False
            continue

        if plan.diffuse:
            # diffuse: k_d ∘ I_d · f_l · max(0, n·l)
            w = np.maximum(nl, const_row(0, nl.shape, dtype))
            if f is not None:
                w *= f
            _accumulate(diffuse_out, w, light.kd_id, first)

        if plan.specular:
            # specular: k_s ∘ I_s · f_l · max(0, r·v)^α, gated by n·l > 0
            t = _specular_power(surface, l, nl, light, const)
            if f is not None:
                t *= f
            _accumulate(specular_out, t, light.ks_is, first)
        first = False


def _specular_power(surface, l, nl, light, const):
    """``max(0, r·v)^α`` (Phong) or ``max(0, n·h)^α`` (Blinn-Phong) for one light.

    Exactly 0 where ``n·l ≤ 0``; ``d_cos = 1 − cos`` is computed as half a
    squared distance, which keeps its relative precision near the highlight.
    """
    dtype = const.dtype
    zero = dtype.type(0)
    n, v = surface.n, surface.v
    # specular, gated by n·l > 0 here and by cos > 0 (d_cos < 1) in cos_power
    lit = nl > zero
    h = None
    h_zero = False
    if const.model == "phong":
        # 1 − r·v = |r − v|²/2 with r − v = 2(n·l)n − (l + v)
        r_minus_v = np.multiply(nl + nl, n)
        r_minus_v -= np.add(l, v) if light.l_plus_v is None else light.l_plus_v
        d_cos = dot_c(r_minus_v, r_minus_v)
        d_cos *= dtype.type(0.5)
    else:
        # 1 − n·h = |n − h|²/2, h = normalize(l + v)
        h, h_zero = light.h, light.h_zero
        if h is None:
            h, h_len = normalize_c(np.add(l, v))
            h_zero = h_len.min() == 0
        d_cos = one_minus_cos_c(n, h)
    # a zero v or h gives d_cos = 1/2, not 1: gate those points out explicitly
    if surface.v_zero:  # the eye on the point: no viewer, no highlight
        lit &= surface.v_len > zero
    if h_zero:  # l = −v: no half vector
        lit &= dot_c(h, h) > zero
    return cos_power(d_cos, lit, const.shininess)


def _cook_torrance(surface, l, nl, f, light, const, plan, diffuse_out, specular_out, first):
    """One light's Cook–Torrance terms (:mod:`~phonglab.core.microfacet`), added to the outputs.

    With ``s = (1 − v·h)⁵`` Schlick's ``F = F₀ + (1 − F₀) s`` is linear in
    ``s``, so each term is a sum of constant colours times per-point weights:

    - diffuse ``k_d ∘ I_d ∘ (1 − m)(1 − F₀) · (1 − s)(n·l) f_l``;
    - specular ``k_s ∘ I_s ∘ (F₀ + (1 − F₀) s) · π D (n·l)V f_l``.

    Both are exactly 0 where ``n·l ≤ 0`` or ``n·v ≤ 0``, and where ``v`` or
    ``h`` is zero (the eye on the point, ``l = −v``).
    """
    dtype = const.dtype
    zero = dtype.type(0)
    n, v, nv = surface.n, surface.v, surface.nv
    # the half vector: constant for a directional light and an infinite viewer
    h, h_zero = light.h, light.h_zero
    if h is None:
        h, h_len = normalize_c(np.add(l, v))
        h_zero = h_len.min() == 0
    # one-sided: both cosines positive
    lit = (nl > zero) & (nv > zero)
    if surface.v_zero:
        lit &= surface.v_len > zero
    if h_zero:
        lit &= dot_c(h, h) > zero
    # Schlick's (1 − v·h)⁵, with 1 − v·h as half a squared distance
    d_vh = one_minus_cos_c(v, h)
    s = d_vh * d_vh
    s *= s
    s *= d_vh
    if plan.diffuse:
        # diffuse: (1 − s)(n·l) f_l, gated
        w = np.where(lit, (dtype.type(1) - s) * nl, zero)
        if f is not None:
            w *= f
        _accumulate(diffuse_out, w, light.ct_diffuse, first)
    if plan.specular:
        # specular: π D (n·l)V f_l, gated; NaN or inf where ungated never reaches the sum
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            lobe = ggx_distribution(one_minus_cos_c(n, h), const.alpha)
            lobe *= smith_visibility_nl(nl, nv, const.alpha)
        w = np.where(lit, lobe * dtype.type(np.pi), zero)
        if f is not None:
            w *= f
        _accumulate(specular_out, w, light.ct_f0, first)
        specular_out += light.ct_grazing * (s * w)


def _accumulate(out, weight, rgb, first):
    """``out (3, m) (+)= rgb (3, 1) · weight (m,)``: one light's term, per channel."""
    if first:
        np.multiply(rgb, weight, out=out)
    else:
        out += rgb * weight


def _add_color(diffuse, specular, base, color_out):
    """``color = (diffuse + specular) + base`` for one block of (3, m) arrays."""
    terms = [t for t in (diffuse, specular) if t is not None]
    if len(terms) == 2:
        np.add(diffuse, specular, out=color_out)
    else:
        np.copyto(color_out, terms[0])
    if base.any():
        color_out += base
