"""The reference kernel: the Phong model written as the lesson writes it.

.. math::

    I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
        + k_s \\circ I_{s,l} \\max(0, c_l)^{\\alpha} \\right]

with ``c_l = r·v`` (Phong, ``r = 2(n·l)n − l``) or ``c_l = n·h`` (Blinn-Phong,
``h = normalize(l + v)``), and ``f_l`` the distance attenuation times the
spotlight factor. Directions point *away from the surface point*: ``n`` the
normal, ``l`` towards the light, ``v`` towards the eye.

:func:`shade_reference` is this sum, one light at a time, in a few readable
lines; it *is* the model. The fast kernel :func:`~phonglab.core.shade`
computes the same sum in blocks, with planned shortcuts and more careful
arithmetic, and the tests hold it to this one.

Nine steps of the sum are parameters (:class:`Steps`): the normal, the
direction and distance to a light, the direction to the eye, the mirror
vector, the spotlight factor, the ambient term, the diffuse weight and the
specular weight. Their correct forms are :func:`unit_normal`,
:func:`light_vector`, :func:`view_vector`, :func:`~phonglab.core.reflect`,
:func:`spot_cone`, :func:`ambient_term`, :func:`lambert` and
:func:`specular_lobe`;
:mod:`phonglab.teaching.mistakes` swaps one of them for a classic wrong
version to show what that bug looks like.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .checks import (as_points, check_lights, check_material, check_model, check_visibility, refuse_nonfinite,
                     viewer)
from .microfacet import DIELECTRIC_F0, ggx_alpha
from .model import AmbientLight, DirectionalLight, Material, SpotLight
from .physics import attenuation, face_forward, facing_away, spot_factor
from .record import ambient_intensity, bind, make_light_record, make_record, names_in
from .shading import Shading
from .vectors import dot, normalize, reflect, unit_direction, working_dtype

__all__ = ["Steps", "shade_reference", "unit_normal", "lambert", "specular_lobe", "light_vector", "view_vector",
           "spot_cone", "ambient_term"]


# ---------------------------------------------------------------------------
# the replaceable steps, in their correct form


def unit_normal(normals):
    """The normal step: renormalise, ``n = normalize(n)`` (a zero normal stays zero)."""
    return normalize(normals)


def lambert(nl):
    """The diffuse weight: ``max(0, n·l)``; a light behind the surface adds nothing."""
    return np.maximum(nl, 0)


lambert.formula = ("max0", "n·l")


def specular_lobe(nl, c, shininess):
    """The specular weight: ``max(0, c)^α`` where ``n·l > 0`` and ``c > 0``, else 0.

    ``c`` is ``r·v`` or ``n·h``. The ``n·l > 0`` gate keeps a light behind
    the surface from making a highlight; ``c > 0`` makes the weight 0, not 1,
    where ``c ≤ 0`` at α = 0.
    """
    lit = (nl > 0) & (c > 0)
    return np.where(lit, np.maximum(c, 0) ** shininess, 0)


specular_lobe.formula = ("if", ("n·l", "c"), ("pow", ("max0", "c"), "α"))


def light_vector(to_light):
    """The direction to a positioned light: ``l = normalize(position − p)`` and the distance ``d``.

    ``to_light`` is ``position − p``, shape ``(..., 3)``; returns ``(l, d)``.
    """
    return normalize(to_light, return_length=True)


def view_vector(points, eye):
    """The direction to the eye, from the point: ``v = normalize(eye − p)``."""
    return normalize(eye - points)


def spot_cone(cos_axis, *, cutoff, exponent):
    """The spotlight factor: ``max(0, −l·s)^e`` inside the cone ``−l·s ≥ cos(cutoff)``, else 0.

    The cutoff is an angle in degrees, compared through its cosine
    (:func:`~phonglab.core.spot_factor`).
    """
    return spot_factor(cos_axis, cutoff=cutoff, exponent=exponent)


def ambient_term(ka_ia, f_lights):
    """The ambient term ``k_a ∘ I_a``: the same at every point, whatever the lights' attenuation.

    ``f_lights`` lists each positioned light's ``f``, shape ``(..., 1)``; the
    correct ambient term does not use them.
    """
    return ka_ia


ambient_term.formula = ("mul", "k_a", "I_a")


@dataclass(frozen=True)
class Steps:
    """The steps of :func:`shade_reference` that can be replaced.

    Attributes
    ----------
    normal : callable ``normals -> n``
        Turns the given normals, shape ``(..., 3)``, into the ``n`` of the
        sum. Default :func:`unit_normal`.
    light : callable ``position − p -> (l, d)``
        The direction ``l`` and distance ``d`` to a point or spot light.
        Default :func:`light_vector`.
    view : callable ``(points, eye) -> v``
        The direction to a local viewer. Default :func:`view_vector`.
    mirror : callable ``(l, n) -> r``
        The mirror vector of Phong. Default :func:`~phonglab.core.reflect`.
    spot : callable ``(cos_axis, *, cutoff, exponent) -> factor``
        The spotlight factor from ``−l·s``. Default :func:`spot_cone`.
    ambient : callable ``(ka_ia, f_lights) -> ambient``
        The ambient term from ``k_a ∘ I_a`` (shape (3,)) and the positioned
        lights' ``f``. Default :func:`ambient_term`.
    diffuse_weight : callable ``nl -> weight``
        The factor of ``k_d ∘ I_d`` from ``n·l``, shape ``(...)``. Default
        :func:`lambert`.
    specular_weight : callable ``(nl, c, shininess) -> weight``
        The factor of ``k_s ∘ I_s`` from ``n·l``, ``c`` (``r·v`` or ``n·h``)
        and α. Default :func:`specular_lobe`.

    A step may say which formula it computes in a ``formula`` attribute
    (:mod:`phonglab.core.record`; ``c`` stands for the model's cosine): the
    record's terms show it, so a replaced step shows its own formula. The
    weights and the ambient step have one; the vector steps need none (the
    record keeps the vectors they returned).
    """

    normal: Callable = unit_normal
    light: Callable = light_vector
    view: Callable = view_vector
    mirror: Callable = reflect
    spot: Callable = spot_cone
    ambient: Callable = ambient_term
    diffuse_weight: Callable = lambert
    specular_weight: Callable = specular_lobe


def shade_reference(
    points,
    normals,
    *,
    material: Material,
    lights,
    eye=None,
    view_direction=None,
    model: str = "phong",
    two_sided: bool = False,
    steps: Steps = Steps(),
    trace: bool = False,
    visibility=None,
):
    """The Phong or Blinn-Phong model evaluated the plain way, one light at a time.

    Parameters
    ----------
    points, normals : array_like, shape (..., 3)
        Surface points and their normals (any length: the normal step
        renormalises them), finite, broadcasting together.
    material : Material
    lights : sequence of Light
    eye, view_direction : 3 floats, keyword-only
        A local viewer at ``eye`` (``v = normalize(eye − p)``), or an infinite
        one, ``v = normalize(view_direction)`` (exactly one of the two).
    model : {"phong", "blinn-phong", "cook-torrance"}
        Cook–Torrance (:mod:`phonglab.core.microfacet`) uses the normal,
        light, view, spot, ambient and diffuse-weight steps; the mirror and
        specular-weight steps belong to the Phong lobe.
    two_sided : bool
        Turn normals that face away from the eye towards it
        (:func:`~phonglab.core.face_forward`).
    steps : Steps
        The replaceable steps; the default is the model.
    trace : bool
        Also return the :class:`~phonglab.core.Record` of what was used:
        every vector, factor, cosine, weight and term, per light.
    visibility : mapping int -> array_like, optional
        Shadows, as for :func:`~phonglab.core.shade`: for a light's index,
        1 where it reaches the point and 0 where something blocks it. A
        blocked light adds nothing there; the record keeps ``lit`` for each
        light given, and its terms are gated by it.

    Returns
    -------
    Shading, or (Shading, Record) with ``trace``
        Every term computed, each of shape ``(..., 3)``; float32 when both
        inputs are float32, else float64. The record's values have the
        points' shape (and a last axis of 3 for vectors and colours).

    Notes
    -----
    .. math::

        I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l}
            \\max(0, n\\cdot l) + k_s \\circ I_{s,l} \\max(0, c_l)^{\\alpha} \\right]

    ``f_l`` is :func:`~phonglab.core.attenuation` times
    :func:`~phonglab.core.spot_factor` (1 for a directional light),
    ``r`` is :func:`~phonglab.core.reflect`. Specular is 0 where ``n·l ≤ 0``.
    A zero normal, or a zero ``l``, ``v`` or ``h``, gives zero cosines and so
    no direct light. The cosine ``c_l`` is computed directly, so for a large
    α near the highlight this kernel is less accurate than
    :func:`~phonglab.core.shade` (about ``α`` ulps of the specular term).

    The record's terms are formulas (:mod:`phonglab.core.record`): each
    step's ``formula`` attribute, where it has one, else the name of the
    value it returned (``diffuse weight``, ``specular weight``, ``ambient``).
    A light given in ``visibility`` has each term inside the gate
    ``("if", ("lit",), term)``: 0 in its shadow.

    Examples
    --------
    >>> import phonglab as pl
    >>> s = pl.shade_reference([[0, 0, 1.0]], [[0, 0, 1.0]], eye=(0, 0, 5),
    ...                        material=pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10),
    ...                        lights=[pl.DirectionalLight(direction=(0, 0, 1))])
    >>> s.diffuse.round(6).tolist(), s.specular.round(6).tolist()
    ([[0.5, 0.5, 0.5]], [[0.5, 0.5, 0.5]])
    >>> s, record = pl.shade_reference([[0, 0, 1.0]], [[0, 0, 1.0]], eye=(0, 0, 5), trace=True,
    ...                                material=pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10),
    ...                                lights=[pl.DirectionalLight(direction=(0, 1, 1))])
    >>> light = record.lights[0]
    >>> round(float(light["n·l"][0]), 4), light.terms["diffuse"]
    (0.7071, ('mul', 'f', 'k_d', 'I_d', ('max0', 'n·l')))
    """
    check_material(material)
    lights = check_lights(lights)
    eye, view_direction = viewer(eye, view_direction)
    check_model(model)
    points, normals = as_points("points", points), as_points("normals", normals)
    refuse_nonfinite("points", points)
    refuse_nonfinite("normals", normals)
    dtype = working_dtype(points, normals)
    points, normals = np.broadcast_arrays(points.astype(dtype), normals.astype(dtype))
    per_point, per_rgb = points.shape[:-1], points.shape
    visibility = check_visibility(visibility, lights, per_point) or {}

    # the normal, and the direction to the eye
    n = steps.normal(normals)
    if eye is not None:
        v = steps.view(points, np.asarray(eye, dtype))
    else:
        v = np.broadcast_to(unit_direction(view_direction, dtype), points.shape)
    flipped = np.zeros(per_point, bool)
    if two_sided:
        flipped = facing_away(n, v)
        n = face_forward(n, v)

    # ambient and emission: the same at every point
    ia = ambient_intensity(lights)
    ka_ia = np.asarray(material.ka) * ia
    emission = np.broadcast_to(np.asarray(material.emission, dtype), points.shape)

    diffuse = np.zeros(points.shape, dtype)
    specular = np.zeros(points.shape, dtype)
    f_lights = []  # each positioned light's f, for the ambient step
    records = []
    cosine = "r·v" if model == "phong" else "n·h"
    for index, light in enumerate(lights):
        if isinstance(light, AmbientLight):
            continue
        values = {}
        # the direction to the light, and f_l = attenuation × spot
        if isinstance(light, DirectionalLight):
            l = np.broadcast_to(unit_direction(light.direction, dtype), points.shape)
            f = np.ones(points.shape[:-1], dtype)
            values.update(l=l)
        else:
            l, dist = steps.light(np.asarray(light.position, dtype) - points)
            f = attenuation(dist, light.attenuation)
            values.update(l=l, d=dist, attenuation=f)
            if isinstance(light, SpotLight):
                axis = unit_direction(light.direction, dtype)
                f_spot = steps.spot(-dot(l, axis), cutoff=light.cutoff, exponent=light.exponent)
                f = f * f_spot
                values.update(spot=f_spot)
        values.update(f=f)
        f = f[..., None]
        if not isinstance(light, DirectionalLight):
            f_lights.append(f)
        nl = dot(n, l)

        # diffuse: k_d ∘ I_d times the diffuse weight
        kd_id = np.asarray(material.kd) * np.asarray(light.diffuse_rgb)
        w_d = steps.diffuse_weight(nl)
        term_d = (f * kd_id * w_d[..., None]).astype(dtype)
        # the shadow: a blocked light adds nothing at the point
        lit = visibility.get(index)

        if model == "cook-torrance":
            # Cook–Torrance: the diffuse term is weighted by (1 − F)(1 − m), the specular one is π D V F (n·l)
            term_d, term_s, ct = _cook_torrance(n, l, v, nl, f, w_d, material, light, dtype)
            term_d, term_s = _shadowed(lit, term_d, term_s, dtype)
            diffuse += term_d
            specular += term_s
            if trace:
                values.update(ct)
                values.update({"I_d": np.broadcast_to(np.asarray(light.diffuse_rgb, dtype), per_rgb),
                               "I_s": np.broadcast_to(np.asarray(light.specular_rgb, dtype), per_rgb),
                               "diffuse weight": w_d, "diffuse": term_d, "specular": term_s,
                               "adds": term_d + term_s})
                terms = {"diffuse": ("if", ("n·v",), ("mul", "f", "k_d", "I_d", "k_D",
                                                      _formula(steps.diffuse_weight, "diffuse weight"))),
                         "specular": ("if", ("n·l", "n·v"), ("mul", "f", "k_s", "I_s", "π", "D", "V", "F", "n·l"))}
                if lit is not None:
                    values["lit"] = lit
                    terms = {name: ("if", ("lit",), formula) for name, formula in terms.items()}
                known = set(values) | _SHARED | {"π", "m", "α_GGX", "F₀"}
                terms = {name: _usable(formula, known, name) for name, formula in terms.items()}
                records.append(make_light_record(index, _kind(light), {k: _cast(a, dtype) for k, a in values.items()},
                                                 terms, factors=COOK_TORRANCE_FACTORS))
            continue

        # specular: k_s ∘ I_s times the specular weight of c = r·v or n·h
        if model == "phong":
            r = steps.mirror(l, n)
            c = dot(r, v)
        else:
            h = normalize(l + v)
            c = dot(n, h)
        ks_is = np.asarray(material.ks) * np.asarray(light.specular_rgb)
        w_s = steps.specular_weight(nl, c, material.shininess)
        term_s = (f * ks_is * w_s[..., None]).astype(dtype)

        term_d, term_s = _shadowed(lit, term_d, term_s, dtype)
        diffuse += term_d
        specular += term_s

        if trace:
            # the other model's vector and cosine too: the page shows r, h, r·v and n·h
            if model == "phong":
                h = normalize(l + v)
                values.update({"n·l": nl, "r": r, "r·v": c, "h": h, "n·h": dot(n, h)})
            else:
                r = steps.mirror(l, n)
                values.update({"n·l": nl, "r": r, "r·v": dot(r, v), "h": h, "n·h": c})
            values.update({
                "I_d": np.broadcast_to(np.asarray(light.diffuse_rgb, dtype), per_rgb),
                "I_s": np.broadcast_to(np.asarray(light.specular_rgb, dtype), per_rgb),
                "diffuse weight": w_d, "specular weight": w_s,
                "diffuse": term_d, "specular": term_s, "adds": term_d + term_s,
            })
            terms = {"diffuse": ("mul", "f", "k_d", "I_d", _formula(steps.diffuse_weight, "diffuse weight")),
                     "specular": ("mul", "f", "k_s", "I_s",
                                  bind(_formula(steps.specular_weight, "specular weight"), {"c": cosine}))}
            if lit is not None:
                values["lit"] = lit
                terms = {name: ("if", ("lit",), formula) for name, formula in terms.items()}
            known = set(values) | _SHARED
            terms = {name: _usable(formula, known, name) for name, formula in terms.items()}
            records.append(make_light_record(index, _kind(light), {k: _cast(a, dtype) for k, a in values.items()},
                                             terms))

    # ambient: k_a ∘ I_a, the same at every point
    ambient = np.broadcast_to(steps.ambient(ka_ia, f_lights).astype(dtype), points.shape)
    color = ambient + emission + diffuse + specular
    shading = Shading(ambient=ambient, diffuse=diffuse, specular=specular, emission=emission, color=color)
    if not trace:
        return shading
    shared = {
        "n": n, "v": v, "n·v": dot(n, v), "flipped": flipped,
        "α": np.full(per_point, material.shininess, dtype),
        **({"π": np.full(per_point, np.pi, dtype), "m": np.full(per_point, material.metallic, dtype),
            "α_GGX": np.full(per_point, ggx_alpha(material.roughness), dtype),
            "F₀": np.broadcast_to(_f0(material).astype(dtype), per_rgb)} if model == "cook-torrance" else {}),
        **{name: np.broadcast_to(np.asarray(k, dtype), per_rgb)
           for name, k in (("k_a", material.ka), ("k_d", material.kd), ("k_s", material.ks),
                           ("k_e", material.emission), ("I_a", ia))},
    }
    if f_lights:
        shared["f_lamp"] = f_lights[0][..., 0]
    shared.update(ambient=ambient, emission=emission)
    terms = {"ambient": _usable(_formula(steps.ambient, "ambient"), set(shared), "ambient"), "emission": "k_e"}
    values = {k: _cast(a, dtype) for k, a in shared.items()}
    return shading, make_record(model, values, terms, records)


#: the record's own values, which every light's formulas may read too
_SHARED = {"n", "v", "n·v", "flipped", "α", "k_a", "k_d", "k_s", "k_e", "I_a"}

#: Cook–Torrance's factors, each a formula over the record's names, as the lesson writes them
#: (D and V only where the light and the eye are both above the surface: elsewhere the term is 0)
COOK_TORRANCE_FACTORS = {
    "D": ("if", ("n·l", "n·v"), ("div", ("pow", "α_GGX", 2),
          ("mul", "π", ("pow", ("add", ("mul", ("pow", "n·h", 2), ("sub", ("pow", "α_GGX", 2), 1)), 1), 2)))),
    "V": ("if", ("n·l", "n·v"), ("div", 1, ("mul", 2, ("add",
                       ("mul", "n·l", ("pow", ("add", ("mul", ("pow", "n·v", 2), ("sub", 1, ("pow", "α_GGX", 2))),
                                               ("pow", "α_GGX", 2)), 0.5)),
                       ("mul", "n·v", ("pow", ("add", ("mul", ("pow", "n·l", 2), ("sub", 1, ("pow", "α_GGX", 2))),
                                               ("pow", "α_GGX", 2)), 0.5)))))),
    "F": ("add", "F₀", ("mul", ("sub", 1, "F₀"), ("pow", ("sub", 1, "v·h"), 5))),
    "k_D": ("mul", ("sub", 1, "F"), ("sub", 1, "m")),
}


def _shadowed(lit, term_d, term_s, dtype):
    """A light's two terms, 0 where its shadow ray was blocked (``lit`` False; None: no shadows)."""
    if lit is None:
        return term_d, term_s
    return (np.where(lit[..., None], term_d, 0).astype(dtype), np.where(lit[..., None], term_s, 0).astype(dtype))


def _kind(light) -> str:
    return "directional" if isinstance(light, DirectionalLight) else (
        "spot" if isinstance(light, SpotLight) else "point")


def _f0(material) -> np.ndarray:
    """``F₀ = min(1, 0.04 (1 − m) + k_d m)`` per channel: at most all the light, head-on."""
    return np.minimum(DIELECTRIC_F0 * (1 - material.metallic) + np.asarray(material.kd) * material.metallic, 1.0)


def _cook_torrance(n, l, v, nl, f, w_d, material, light, dtype):
    """One light's Cook–Torrance diffuse and specular terms, written as the lesson writes them.

    .. math::

        D = \\frac{\\alpha^2}{\\pi ((n\\cdot h)^2(\\alpha^2 - 1) + 1)^2}, \\quad
        V = \\frac{1/2}{(n\\cdot l)\\sqrt{(n\\cdot v)^2(1 - \\alpha^2) + \\alpha^2}
            + (n\\cdot v)\\sqrt{(n\\cdot l)^2(1 - \\alpha^2) + \\alpha^2}}, \\quad
        F = F_0 + (1 - F_0)(1 - v\\cdot h)^5

    diffuse ``f k_d ∘ I_d ∘ (1 − F)(1 − m) w_d`` where ``n·v > 0``, specular
    ``f k_s ∘ I_s ∘ π D V F (n·l)`` where ``n·l > 0`` and ``n·v > 0``. The
    direct forms lose precision near the peak of a sharp lobe, where
    ``(n·h)²(α² − 1) + 1`` cancels to ``α²``: the fast kernel
    (:func:`~phonglab.core.shade`) computes ``1 − (n·h)²`` from
    ``|n − h|²/2`` and stays accurate there.

    Returns ``(diffuse, specular, values)``, the values under the record's names.
    """
    alpha = ggx_alpha(material.roughness)
    a2 = alpha * alpha
    h = normalize(l + v)
    nv, nh, vh = dot(n, v), dot(n, h), dot(v, h)
    lit_v = nv > 0
    lit = (nl > 0) & lit_v
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
        vis = 0.5 / (nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2))
    f0 = _f0(material)
    fresnel = f0 + (1 - f0) * ((1 - vh) ** 5)[..., None]
    k_diffuse = (1 - fresnel) * (1 - material.metallic)
    kd_id = np.asarray(material.kd) * np.asarray(light.diffuse_rgb)
    ks_is = np.asarray(material.ks) * np.asarray(light.specular_rgb)
    term_d = np.where(lit_v[..., None], f * kd_id * k_diffuse * w_d[..., None], 0).astype(dtype)
    lobe = np.where(lit, np.pi * d * vis * nl, 0)
    term_s = (f * ks_is * fresnel * lobe[..., None]).astype(dtype)
    values = {"n·l": nl, "n·v": nv, "h": h, "n·h": nh, "v·h": vh,
              "D": np.where(lit, d, 0), "V": np.where(lit, vis, 0), "F": fresnel, "k_D": k_diffuse}
    return term_d, term_s, values


def _usable(formula, known, name):
    """``formula``, or the plain name of the recorded result if it reads a value this record lacks."""
    return formula if set(names_in(formula)) <= set(known) | {name} else name


def _formula(step, name):
    """The formula a step computes (its ``formula`` attribute), or the name of its recorded result."""
    return getattr(step, "formula", name)


def _cast(a, dtype):
    """A recorded value as an array in the working dtype (booleans stay booleans)."""
    a = np.asarray(a)
    return a if a.dtype == bool or a.dtype == dtype else a.astype(dtype)
