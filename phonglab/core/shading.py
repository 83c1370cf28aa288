"""Phong and Blinn-Phong shading of many points, and the vectors at one point.

Directions point *away from the surface point*: ``n`` the unit normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``.

.. math::

    I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
        + k_s \\circ I_{s,l} \\max(0, r\\cdot v)^{\\alpha} \\right]

Blinn-Phong uses ``n·h`` in place of ``r·v``. Specular is exactly zero
wherever ``n·l ≤ 0``. ``f_l`` is the distance attenuation times the spotlight
factor (see :class:`~phonglab.core.model.PointLight`, :class:`~phonglab.core.model.SpotLight`).

A :class:`Plan` says which parts of that sum a material and set of lights
actually need; :func:`shade` executes it, so a skipped effect costs nothing.
Planned and full evaluation agree to within an ulp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .model import (
    ATTENUATION_MAX,
    DISTANCE_FLOOR,
    AmbientLight,
    DirectionalLight,
    InvalidValue,
    Light,
    Material,
    PointLight,
    SpotLight,
    _vec3,
)
from .vectors import (
    const_row,
    cos_power,
    dot_c,
    normalize_c,
    one_minus_cos_c,
    reflect_c,
    working_dtype,
)

__all__ = ["MODELS", "Plan", "LightPlan", "plan_effects", "Shading", "shade", "ProbeVectors", "vectors"]

MODELS = ("phong", "blinn-phong")

#: Points shaded per block: small enough that a block's temporaries stay in cache.
CHUNK = 32768

#: Slack of the spot cone test ``cos(angle) >= cos(cutoff)``, in ulps of the working dtype.
SPOT_SLACK_ULPS = 4


# ---------------------------------------------------------------------------
# the plan


@dataclass(frozen=True)
class LightPlan:
    """Per-point work for one non-ambient light.

    ``index`` is the light's position in the ``lights`` sequence.
    """

    index: int
    constant_l: bool  # directional: L is the same at every point
    attenuation: bool  # evaluate a + b d + c d²
    spot: bool  # evaluate the spot cone


@dataclass(frozen=True)
class Plan:
    """Which effects shading computes, and why each one is skipped.

    Made by :func:`plan_effects` for one material and set of lights; pass it to
    :func:`shade` with that same material and lights.

    Attributes
    ----------
    computed, skipped : tuple of (effect, reason)
        Human-readable verdicts, in the order of the model's equation.
    """

    ambient: bool
    emission: bool
    diffuse: bool
    specular: bool
    constant_view: bool
    two_sided: bool
    lights: tuple[LightPlan, ...]
    computed: tuple[tuple[str, str], ...] = ()
    skipped: tuple[tuple[str, str], ...] = ()
    full: bool = False
    # what the plan was made for, checked by shade()
    material: Material | None = field(default=None, repr=False)
    light_objects: tuple = field(default=(), repr=False)
    model: str = "phong"


def _fmt(rgb) -> str:
    return "(" + ", ".join(f"{c:g}" for c in rgb) + ")"


def _is_zero(rgb) -> bool:
    return not any(rgb)


def plan_effects(
    material: Material,
    lights,
    *,
    eye=None,
    view_direction=None,
    two_sided: bool = False,
    model: str = "phong",
    full: bool = False,
) -> Plan:
    """Decide which effects of the model a scene needs.

    Parameters
    ----------
    material : Material
    lights : sequence of Light
    eye, view_direction : 3 floats, keyword-only
        A local viewer at ``eye``, or an infinite viewer looking along
        ``-view_direction`` (exactly one of the two).
    two_sided : bool
    model : {"phong", "blinn-phong"}
    full : bool
        Plan the full evaluation: every term, every light, per-point vectors,
        attenuation even when it is 1. Used as the reference the planned
        evaluation must match.

    Returns
    -------
    Plan

    Notes
    -----
    Skips only what contributes exactly nothing or exactly the same value:

    - ambient when ``k_a ∘ I_a = 0``; emission when ``k_e = 0``;
    - a light whose diffuse and specular intensities are both 0;
    - diffuse when ``k_d = 0`` (or no light has a diffuse intensity), specular
      likewise with ``k_s``; with neither, no per-light work at all;
    - attenuation when it is ``(1, 0, 0)``; the spot cone at cutoff 180;
    - per-point ``L`` for directional lights, per-point ``V`` for an infinite
      viewer (and so ``H`` for both);
    - the two-sided flip unless asked for.
    """
    if model not in MODELS:
        raise InvalidValue("model", model, f"must be one of {', '.join(MODELS)}")
    lights = tuple(lights)
    infinite = eye is None
    ia = [0.0, 0.0, 0.0]
    for light in lights:
        if isinstance(light, AmbientLight):
            ia = [a + b for a, b in zip(ia, light.ambient_rgb)]
    ambient_rgb = tuple(k * i for k, i in zip(material.ka, ia))
    direct = [(i, lt) for i, lt in enumerate(lights) if not isinstance(lt, AmbientLight)]

    computed: list[tuple[str, str]] = []
    skipped: list[tuple[str, str]] = []

    def verdict(on: bool, effect: str, why_on: str, why_off: str) -> bool:
        (computed if on else skipped).append((effect, why_on if on else why_off))
        return on

    if full:
        plans = tuple(
            LightPlan(i, False, not isinstance(lt, DirectionalLight), isinstance(lt, SpotLight) and lt.is_cone)
            for i, lt in direct
        )
        computed.append(("everything", "full evaluation: every term, every light, per-point vectors"))
        return Plan(True, True, bool(plans), bool(plans), False, two_sided, plans,
                    tuple(computed), (), True, material, lights, model)

    ambient = verdict(
        not _is_zero(ambient_rgb), "ambient",
        f"k_a ∘ I_a = {_fmt(ambient_rgb)}, the same at every point",
        "k_a is 0" if _is_zero(material.ka) else "no ambient light",
    )
    emission = verdict(not _is_zero(material.emission), "emission",
                       f"k_e = {_fmt(material.emission)}", "k_e is 0")

    reaching = []
    for i, lt in direct:
        if _is_zero(lt.diffuse_rgb) and _is_zero(lt.specular_rgb):
            skipped.append((f"light {i}", "its intensity is 0: it adds nothing"))
        else:
            reaching.append((i, lt))
    any_id = any(not _is_zero(lt.diffuse_rgb) for _, lt in reaching)
    any_is = any(not _is_zero(lt.specular_rgb) for _, lt in reaching)

    diffuse = verdict(
        bool(reaching) and any_id and not _is_zero(material.kd), "diffuse",
        "k_d > 0 and a light reaches the surface",
        "no light reaches the surface" if not reaching else
        ("k_d is 0 in every channel" if _is_zero(material.kd) else "no light has a diffuse intensity"),
    )
    specular = verdict(
        bool(reaching) and any_is and not _is_zero(material.ks), "specular",
        f"k_s > 0 and a light reaches the surface ({model}, α = {material.shininess:g})",
        "no light reaches the surface" if not reaching else
        ("k_s is 0 in every channel" if _is_zero(material.ks) else "no light has a specular intensity"),
    )
    if not (diffuse or specular):
        skipped.append(("per-light work", "neither diffuse nor specular is needed: no light is evaluated per point"))
        reaching = []

    plans = []
    for i, lt in reaching:
        directional = isinstance(lt, DirectionalLight)
        if directional:
            computed.append((f"light {i}: constant L", "a directional light has the same L at every point"))
            attenuation = spot = False
        else:
            attenuation = verdict(
                lt.attenuation != (1.0, 0.0, 0.0), f"light {i}: attenuation",
                f"1/(a + b·d + c·d²) with (a, b, c) = {_fmt(lt.attenuation)}",
                "(a, b, c) = (1, 0, 0) is 1 at every distance",
            )
            spot = isinstance(lt, SpotLight) and verdict(
                lt.is_cone, f"light {i}: spot cone",
                f"cutoff {lt.cutoff:g}°, exponent {lt.exponent:g}",
                "cutoff 180° is a plain point light",
            )
        plans.append(LightPlan(i, directional, attenuation, spot))

    constant_view = bool(plans) and infinite
    if plans:
        verdict(infinite, "constant V",
                "infinite viewer: V is the same at every point",
                "a local viewer: V is normalised per point")
        if specular and model == "blinn-phong" and infinite:
            for lp in plans:
                if lp.constant_l:
                    computed.append((f"light {lp.index}: constant H", "directional light and infinite viewer"))
    flip = verdict(bool(plans) and two_sided, "two-sided flip",
                   "normals facing away from the eye are negated",
                   "two-sided lighting is off" if not two_sided else "no light is evaluated per point")
    return Plan(ambient, emission, diffuse, specular, constant_view, flip, tuple(plans),
                tuple(computed), tuple(skipped), False, material, lights, model)


# ---------------------------------------------------------------------------
# shading


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


def _as_points(name, a):
    """``a`` as an array of shape (..., 3) of real numbers; finiteness is checked as it is read."""
    a = np.asarray(a)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InvalidValue(name, f"array of shape {a.shape}", "must be an array of shape (..., 3)")
    if not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)):
        raise InvalidValue(name, f"array of dtype {a.dtype}", "must hold real numbers")
    return a


def _refuse_nonfinite(name, a):
    """Raise InvalidValue naming the first NaN or inf in ``a``, if there is one."""
    if a.size and not np.isfinite(a).all():
        bad = np.argwhere(~np.isfinite(a))[0]
        raise InvalidValue(name, f"{a[tuple(bad)]} at index {tuple(int(i) for i in bad)}",
                           "must be finite (no NaN or inf)")


def _viewer(eye, view_direction):
    if (eye is None) == (view_direction is None):
        raise InvalidValue("eye", eye, "give exactly one of eye= (a local viewer) or "
                           "view_direction= (an infinite viewer)")
    if eye is not None:
        return _vec3("eye", eye), None
    return None, _vec3("view_direction", view_direction, nonzero=True)


def _check_lights(lights):
    lights = tuple(lights)
    for i, lt in enumerate(lights):
        if not isinstance(lt, Light):
            raise InvalidValue(f"lights[{i}]", lt, "must be a phonglab light (AmbientLight, PointLight, "
                                                    "DirectionalLight, SpotLight)")
    return lights


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
        Which effects to compute: "auto" plans them with :func:`plan_effects`,
        "full" evaluates everything (the reference).

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
    - attenuation uses ``max(d, 1e-6)`` and is capped at 1e12.

    Examples
    --------
    >>> import phonglab as pl
    >>> s = pl.shade([[0, 0, 1.0]], [[0, 0, 1.0]], eye=(0, 0, 5),
    ...              material=pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10),
    ...              lights=[pl.DirectionalLight(direction=(0, 0, 1))])
    >>> s.color.round(6).tolist()
    [[1.0, 1.0, 1.0]]
    """
    if not isinstance(material, Material):
        raise InvalidValue("material", material, "must be a phonglab Material")
    lights = _check_lights(lights)
    eye, view_direction = _viewer(eye, view_direction)
    points = _as_points("points", points)
    normals = _as_points("normals", normals)
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

    const = _Constants(material, lights, plan, eye, view_direction, dtype, points, normals)
    no_term = np.zeros(3, dtype)
    # results are held channel first, (3, n): every write below is a contiguous row
    diffuse = np.empty((3, n_points), dtype) if plan.diffuse else None
    specular = np.empty((3, n_points), dtype) if plan.specular else None
    base = (const.ambient + const.emission)[:, None]  # the same at every point
    color = np.empty((3, n_points), dtype)
    if plan.lights:
        for start in range(0, n_points, CHUNK):
            stop = min(start + CHUNK, n_points)
            d = None if diffuse is None else diffuse[:, start:stop]
            s = None if specular is None else specular[:, start:stop]
            _shade_block(P[start:stop], N[start:stop], const, plan, model, d, s)
            # colour = (diffuse + specular) + (ambient + emission), while the block is in cache
            _add_color(d, s, base, color[:, start:stop])
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


class _Constants:
    """What the per-point loop needs, precomputed once in the working dtype."""

    def __init__(self, material, lights, plan, eye, view_direction, dtype, points, normals):
        dt = dtype.type
        self.dtype = dtype
        ia = np.zeros(3)
        for lt in lights:
            if isinstance(lt, AmbientLight):
                ia += lt.ambient_rgb
        ka = np.asarray(material.ka)
        self.ambient = (ka * ia).astype(dtype) if plan.ambient else np.zeros(3, dtype)
        self.emission = np.asarray(material.emission, dtype) if plan.emission else np.zeros(3, dtype)
        self.shininess = material.shininess
        self.eye = None if eye is None else np.asarray(eye, dtype)[:, None]
        self.view = None
        if view_direction is not None:
            self.view = _unit(view_direction, dtype)
        kd, ks = np.asarray(material.kd), np.asarray(material.ks)
        self.needs_view = plan.specular or plan.two_sided
        self.needs_points = (self.needs_view and eye is not None) or any(
            not isinstance(lights[lp.index], DirectionalLight) for lp in plan.lights)
        # the arrays the loop reads, checked for NaN and inf by refuse_nonfinite
        self.inputs = (("points", points), ("normals", normals)) if self.needs_points else (("normals", normals),)
        self.inputs_checked = False
        self.lights = []
        for lp in plan.lights:
            lt = lights[lp.index]
            item = {"plan": lp}
            item["kd_id"] = (kd * np.asarray(lt.diffuse_rgb)).astype(dtype)[:, None] if plan.diffuse else None
            item["ks_is"] = (ks * np.asarray(lt.specular_rgb)).astype(dtype)[:, None] if plan.specular else None
            if isinstance(lt, DirectionalLight):
                item["l"] = _unit(lt.direction, dtype)
                item["h"] = None
                if plan.constant_view and lp.constant_l:
                    item["l+v"] = item["l"] + self.view
                    item["h"] = normalize_c(item["l+v"])[0]
                    item["h_zero"] = not item["h"].any()  # l = −v
            else:
                item["position"] = np.asarray(lt.position, dtype)[:, None]
                a, b, c = lt.attenuation
                item["attenuation"] = (dt(a), dt(b), dt(c))
            if lp.spot:
                item["axis"] = _unit(lt.direction, dtype)
                # cone test with a few ulps of slack: a point on the cone counts as inside
                item["cos_cutoff"] = dt(math.cos(math.radians(lt.cutoff)) - SPOT_SLACK_ULPS * np.finfo(dtype).eps)
                item["exponent"] = dt(lt.exponent)
            self.lights.append(item)

    def refuse_nonfinite(self):
        """Check the inputs the loop reads for NaN and inf, once per call.

        The loop's normalisations prove clean blocks finite for free; this
        runs only when one of them meets a vector outside the direct range
        (NaN, inf, zero, tiny or huge).
        """
        if not self.inputs_checked:
            for name, a in self.inputs:
                _refuse_nonfinite(name, a)
            self.inputs_checked = True


def _unit(direction, dtype):
    """A light's or viewer's fixed direction as a (3, 1) unit vector.

    Normalised in float64 before the cast, so a direction like (0, 0, 1e-148)
    does not underflow to zero in float32.
    """
    return normalize_c(np.asarray(direction, np.float64)[:, None])[0].astype(dtype)


def _attenuation_factor(dist, coeffs, dtype):
    """``1 / max(a + b d + c d², 1/ATTENUATION_MAX)`` with ``d`` floored at DISTANCE_FLOOR."""
    a, b, c = coeffs
    d = np.maximum(dist, const_row(DISTANCE_FLOOR, dist.shape, dtype))
    # only the non-zero terms: 0·inf would be NaN for a light at infinity
    den = np.full_like(d, a)
    with np.errstate(over="ignore"):
        if c:
            den += d * (b + c * d) if b else c * d * d
        elif b:
            den += b * d
    np.maximum(den, const_row(1.0 / ATTENUATION_MAX, den.shape, dtype), out=den)
    return np.divide(dtype.type(1), den, out=den)


def _shade_block(points, normals, const, plan, model, diffuse_out, specular_out):
    """Shade one block of points, writing the (3, n) diffuse and specular blocks.

    Vectors are held components first, (3, n), so every component is one
    contiguous row; the sums over lights go straight into the outputs.
    """
    dtype = const.dtype
    zero = dtype.type(0)
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

    # two-sided: negate normals facing away from the eye
    if plan.two_sided:
        n *= np.where(dot_c(n, v) < 0, dtype.type(-1), dtype.type(1))

    first = True
    for item in const.lights:
        lp = item["plan"]
        # direction to the light, and its distance for attenuation
        if "l" in item:
            l = item["l"] if lp.constant_l else np.broadcast_to(item["l"], shape).copy()
            dist = None
        else:
            l, dist = normalize_c(np.subtract(item["position"], p), before_rescaling=refuse)
        nl = dot_c(n, l)
        lit = nl > zero

        f = _attenuation_factor(dist, item["attenuation"], dtype) if lp.attenuation else None
        if lp.spot:
            # spot cone: cos of the angle between the axis and light -> point
            c = dot_c(l, item["axis"])
            np.negative(c, out=c)
            inside = c >= item["cos_cutoff"]
            s = np.power(np.maximum(c, const_row(0, c.shape, dtype), out=c), item["exponent"], out=c)
            s *= inside
            f = s if f is None else np.multiply(f, s, out=f)

        if plan.diffuse:
            w = np.maximum(nl, const_row(0, nl.shape, dtype))
            if f is not None:
                w *= f
            _accumulate(diffuse_out, w, item["kd_id"], first)

        if plan.specular:
            t = _specular_power(n, l, v, nl, lit, item, const, model, v_zero, v_len)
            if f is not None:
                t *= f
            _accumulate(specular_out, t, item["ks_is"], first)
        first = False


def _specular_power(n, l, v, nl, lit, item, const, model, v_zero, v_len):
    """``max(0, r·v)^α`` or ``max(0, n·h)^α``, exactly 0 where not ``lit`` (n·l > 0)."""
    dtype = const.dtype
    zero = dtype.type(0)
    # specular, gated by n·l > 0 here and by cos > 0 (d = 1 − cos < 1) in cos_power
    if model == "phong":
        # 1 − r·v = |r − v|²/2 with r − v = 2(n·l)n − (l + v)
        lv = item.get("l+v")
        a = np.multiply(nl + nl, n)
        a -= np.add(l, v) if lv is None else lv
        d = dot_c(a, a)
        d *= dtype.type(0.5)
        h_zero = False
    else:
        h = item.get("h")
        h_zero = item.get("h_zero", False)
        if h is None:
            h, h_len = normalize_c(np.add(l, v))
            h_zero = h_len.min() == 0
        d = one_minus_cos_c(n, h)
    # a zero v or h gives d = 1/2, not 1: gate those points out explicitly
    if v_zero:  # the eye on the point: no viewer, no highlight
        lit &= v_len > zero
    if h_zero:  # l = −v: no half vector
        lit &= dot_c(h, h) > zero
    return cos_power(d, lit, const.shininess)


def _accumulate(out, weight, rgb, first):
    """``out (3, n) (+)= rgb (3, 1) · weight (n,)``: one light's term, per channel."""
    if first:
        np.multiply(rgb, weight, out=out)
    else:
        out += rgb * weight


def _add_color(diffuse, specular, base, color_out):
    """``color = (diffuse + specular) + base`` for one block of (3, n) arrays."""
    terms = [t for t in (diffuse, specular) if t is not None]
    if len(terms) == 2:
        np.add(diffuse, specular, out=color_out)
    else:
        np.copyto(color_out, terms[0])
    if base.any():
        color_out += base


# ---------------------------------------------------------------------------
# the vectors at one point


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

    Uses the same kernels as :func:`shade`, in float64.

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
    eye, view_direction = _viewer(eye, view_direction)
    p = np.asarray(_vec3("point", point))[:, None]
    n, _ = normalize_c(np.asarray(_vec3("normal", normal))[:, None])
    if eye is not None:
        v, _ = normalize_c(np.asarray(eye)[:, None] - p)
    else:
        v, _ = normalize_c(np.asarray(view_direction)[:, None])
    flipped = bool(two_sided and dot_c(n, v)[0] < 0)
    if flipped:
        n = -n
    attenuation = spot = 1.0
    if isinstance(light, DirectionalLight):
        l, _ = normalize_c(np.asarray(light.direction)[:, None])
        distance = None
    else:
        l, dist = normalize_c(np.asarray(light.position)[:, None] - p)
        distance = float(dist[0])
        attenuation = float(_attenuation_factor(dist, light.attenuation, np.dtype(np.float64))[0])
        if isinstance(light, SpotLight) and light.is_cone:
            axis, _ = normalize_c(np.asarray(light.direction)[:, None])
            c = float(-dot_c(l, axis)[0])
            inside = c >= math.cos(math.radians(light.cutoff)) - SPOT_SLACK_ULPS * np.finfo(float).eps
            spot = max(c, 0.0) ** light.exponent if inside else 0.0
    r = reflect_c(l, n)
    h, _ = normalize_c(l + v)
    return ProbeVectors(
        n=n[:, 0], l=l[:, 0], r=r[:, 0], v=v[:, 0], h=h[:, 0],
        nl=float(dot_c(n, l)[0]), rv=float(dot_c(r, v)[0]), nh=float(dot_c(n, h)[0]),
        distance=distance, attenuation=attenuation, spot=spot, flipped=flipped,
    )
