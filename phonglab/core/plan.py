"""The plan: which parts of the Phong sum a material and set of lights need.

.. math::

    I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
        + k_s \\circ I_{s,l} \\max(0, r\\cdot v)^{\\alpha} \\right]

:func:`plan_effects` decides, from the material, the lights and the viewer
alone, which terms contribute and which vectors are the same at every point;
:func:`~phonglab.core.shade` executes the :class:`Plan`, so a skipped effect
costs nothing. Each verdict comes with a reason a lesson can show.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .checks import check_model
from .model import AmbientLight, DirectionalLight, Material, SpotLight
from .record import ambient_intensity

__all__ = ["Plan", "LightPlan", "plan_effects"]


@dataclass(frozen=True, kw_only=True)
class LightPlan:
    """Per-point work for one non-ambient light.

    Attributes
    ----------
    index : int
        The light's position in the ``lights`` sequence.
    constant_l : bool
        ``l`` is the same at every point (a directional light).
    attenuation : bool
        Evaluate the distance attenuation ``1/(a + b·d + c·d²)``.
    spot : bool
        Evaluate the spot cone.
    """

    index: int
    constant_l: bool
    attenuation: bool
    spot: bool


@dataclass(frozen=True, kw_only=True)
class Plan:
    """Which effects shading computes, and why each one is skipped.

    Made by :func:`plan_effects` for one material and set of lights; pass it to
    :func:`~phonglab.core.shade` with that same material and lights.

    Attributes
    ----------
    ambient, emission, diffuse, specular : bool
        Which terms of the sum are computed (a skipped one is 0 everywhere).
    constant_view : bool
        ``v`` is the same at every point (an infinite viewer).
    two_sided : bool
        Flip the normals that face away from the eye.
    lights : tuple of LightPlan
        The per-point work, one entry per light evaluated.
    computed, skipped : tuple of (effect, reason)
        Human-readable verdicts, in the order of the model's equation.
    full : bool
        The full evaluation, the reference the planned one matches.
    material, light_objects, model
        What the plan was made for; :func:`~phonglab.core.shade` refuses a
        plan made for something else.
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
    material: Material | None = field(default=None, repr=False)
    light_objects: tuple = field(default=(), repr=False)
    model: str = "phong"


def _fmt(rgb) -> str:
    """An RGB triple in a reason, to 3 significant digits as the readout beside it writes its numbers."""
    return "(" + ", ".join(f"{c:.3g}" for c in rgb) + ")"


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
    check_model(model)
    lights = tuple(lights)
    infinite = eye is None
    ambient_rgb = tuple(float(x) for x in np.asarray(material.ka) * ambient_intensity(lights))
    direct = [(i, lt) for i, lt in enumerate(lights) if not isinstance(lt, AmbientLight)]

    computed: list[tuple[str, str]] = []
    skipped: list[tuple[str, str]] = []

    def verdict(on: bool, effect: str, why_on: str, why_off: str) -> bool:
        (computed if on else skipped).append((effect, why_on if on else why_off))
        return on

    if full:
        plans = tuple(
            LightPlan(index=i, constant_l=False, attenuation=not isinstance(lt, DirectionalLight),
                      spot=isinstance(lt, SpotLight) and lt.is_cone)
            for i, lt in direct
        )
        computed.append(("everything", "full evaluation: every term, every light, per-point vectors"))
        return Plan(ambient=True, emission=True, diffuse=bool(plans), specular=bool(plans), constant_view=False,
                    two_sided=two_sided, lights=plans, computed=tuple(computed), skipped=(), full=True,
                    material=material, light_objects=lights, model=model)

    ambient = verdict(
        not _is_zero(ambient_rgb), "ambient",
        f"k_a ∘ I_a = {_fmt(ambient_rgb)}, the same at every point",
        "k_a is 0" if _is_zero(material.ka) else "no ambient light",
    )
    emission = verdict(not _is_zero(material.emission), "emission",
                       f"k_e = {_fmt(material.emission)}", "k_e is 0")

    reaching = []
    for i, lt in direct:
        if not lt.shines:
            skipped.append((f"light {i}", "its intensity is 0: it adds nothing"))
        else:
            reaching.append((i, lt))
    any_id = any(not _is_zero(lt.diffuse_rgb) for _, lt in reaching)
    any_is = any(not _is_zero(lt.specular_rgb) for _, lt in reaching)

    metal = model == "cook-torrance" and material.metallic == 1
    diffuse = verdict(
        bool(reaching) and any_id and not _is_zero(material.kd) and not metal, "diffuse",
        "k_d > 0 and a light reaches the surface",
        "no light reaches the surface" if not reaching else
        ("k_d is 0 in every channel" if _is_zero(material.kd) else
         "a metal (metallic = 1) has no diffuse term" if metal else "no light has a diffuse intensity"),
    )
    lobe = (f"roughness {material.roughness:g}, metallic {material.metallic:g}" if model == "cook-torrance"
            else f"α = {material.shininess:g}")
    specular = verdict(
        bool(reaching) and any_is and not _is_zero(material.ks), "specular",
        f"k_s > 0 and a light reaches the surface ({model}, {lobe})",
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
        plans.append(LightPlan(index=i, constant_l=directional, attenuation=attenuation, spot=spot))

    constant_view = bool(plans) and infinite
    if plans:
        verdict(infinite, "constant V",
                "infinite viewer: V is the same at every point",
                "a local viewer: V is normalised per point")
        if (specular or model == "cook-torrance") and model != "phong" and infinite:
            for lp in plans:
                if lp.constant_l:
                    computed.append((f"light {lp.index}: constant H", "directional light and infinite viewer"))
    if model != "cook-torrance" and (material.roughness, material.metallic) != (0.5, 0.0):
        skipped.append(("roughness, metallic", f"Cook–Torrance's; the {model} model does not use them"))
    elif model == "cook-torrance":
        skipped.append(("shininess", "Phong's exponent; Cook–Torrance's lobe is set by roughness"))
    flip = verdict(bool(plans) and two_sided, "two-sided flip",
                   "normals facing away from the eye are negated",
                   "two-sided lighting is off" if not two_sided else "no light is evaluated per point")
    return Plan(ambient=ambient, emission=emission, diffuse=diffuse, specular=specular,
                constant_view=constant_view, two_sided=flip, lights=tuple(plans),
                computed=tuple(computed), skipped=tuple(skipped), full=False,
                material=material, light_objects=lights, model=model)
