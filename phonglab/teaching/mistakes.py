"""Common mistakes: deliberately wrong versions of the Phong shading.

Every function in this module makes **one** classic bug on purpose, so a
lesson can show what that bug looks like next to the correct picture. They
exist for teaching only: :mod:`phonglab.core` never imports this module, and
nothing here is used to draw a correct image.

Each variant takes the inputs of :func:`phonglab.core.shade` (``points``,
``normals``, ``material``, ``lights``, ``eye`` or ``view_direction``,
``model``, ``two_sided``) and returns the same :class:`phonglab.core.Shading`.
Each is the core's reference kernel, :func:`phonglab.core.shade_reference`
(the model written one light at a time), with one line changed: one of its
:class:`~phonglab.core.Steps` swapped for a wrong one.

=========================  ===================================================
step                       correct version / wrong version
=========================  ===================================================
the normal                 ``n = normalize(n)`` / used as interpolated
the diffuse weight         ``max(0, n·l)`` / ``n·l``
the specular weight        ``max(0, c)^α`` where ``n·l > 0`` / no ``n·l`` gate;
                           ``α`` replaced by 0
=========================  ===================================================

The reference kernel agrees with the fast one to rounding error; the tests
hold each mistake to that: it differs from the core exactly where its bug
bites and agrees everywhere else.

Directions point *away from the surface point*: ``n`` the normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``, and ``c`` is ``r·v`` (Phong) or ``n·h`` (Blinn-Phong).
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Callable

import numpy as np

from phonglab.core.reference import Steps, shade_reference
from phonglab.core.reference import (  # noqa: F401  (the correct steps, shown here)
    ambient_term,
    lambert,
    light_vector,
    specular_lobe,
    spot_cone,
    unit_normal,
    view_vector,
)
from phonglab.core.vectors import dot, normalize, reflect  # noqa: F401  (reflect: the correct mirror step)

__all__ = [
    "Mistake",
    "MISTAKES",
    "get_mistake",
    "no_clamp_diffuse",
    "ungated_specular",
    "unnormalised_normals",
    "zero_shininess",
    "reflect_wrong_way",
    "unnormalised_light",
    "unnormalised_view",
    "view_from_eye",
    "attenuated_ambient",
    "spot_cutoff_in_degrees",
    "power_before_max",
    "zero_to_the_zero",
]


# ---------------------------------------------------------------------------
# the three steps that the mistakes get wrong, each next to its correct form
# (the correct ones are the reference kernel's defaults, imported above:
# unit_normal, lambert, specular_lobe)


def raw_normal(normals):
    """WRONG normal: used as it comes, even when it is shorter than 1 (correct: :func:`unit_normal`)."""
    return normals


def lambert_unclamped(nl):
    """WRONG diffuse weight: ``n·l``, negative where the light is behind the surface (correct: :func:`lambert`)."""
    return nl


lambert_unclamped.formula = "n·l"


def specular_lobe_ungated(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^α`` wherever ``c > 0``, whatever the sign of ``n·l``.

    Correct: :func:`specular_lobe`, which is 0 where ``n·l ≤ 0``.
    """
    return np.where(c > 0, np.maximum(c, 0) ** shininess, 0)


specular_lobe_ungated.formula = ("if", ("c",), ("pow", ("max0", "c"), "α"))


def specular_lobe_zero_exponent(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^0``, which is 1 at every lit point (0^0 = 1 too).

    Correct: :func:`specular_lobe`, with the material's α.
    """
    return np.where(nl > 0, np.maximum(c, 0) ** 0.0, 0)


specular_lobe_zero_exponent.formula = ("if", ("n·l",), ("pow", ("max0", "c"), 0))


def reflect_reversed(l, n):
    """WRONG mirror vector: ``r = l − 2(n·l)n``, the true ``r`` turned round (correct: ``reflect``)."""
    return l - 2 * dot(n, l)[..., None] * n


def light_vector_raw(to_light):
    """WRONG light vector: ``l = position − p`` as it is, longer or shorter than 1 (correct: :func:`light_vector`)."""
    return to_light, np.sqrt(np.sum(to_light * to_light, axis=-1))


def view_vector_raw(points, eye):
    """WRONG view vector: ``v = eye − p``, not normalised (correct: :func:`view_vector`)."""
    return eye - points


def view_from_eye_step(points, eye):
    """WRONG view vector: ``v = normalize(p − eye)``, from the eye to the point (correct: :func:`view_vector`)."""
    return normalize(points - eye)


def ambient_attenuated(ka_ia, f_lights):
    """WRONG ambient term: ``f · k_a ∘ I_a`` with the first lamp's ``f`` (correct: :func:`ambient_term`)."""
    return ka_ia * f_lights[0] if f_lights else ka_ia


ambient_attenuated.formula = ("mul", "f_lamp", "k_a", "I_a")  # with no lamp the record shows the value


def spot_cone_degrees(cos_axis, *, cutoff, exponent):
    """WRONG spotlight cone: ``−l·s ≥ cutoff``, a cosine against an angle in degrees (correct: :func:`spot_cone`).

    ``cutoff = 180`` stays a plain point light, as in the correct step.
    """
    if cutoff == 180:
        return np.ones_like(cos_axis)
    return np.where(cos_axis >= cutoff, np.maximum(cos_axis, 0) ** exponent, 0).astype(cos_axis.dtype)


def specular_lobe_power_first(nl, c, shininess):
    """WRONG specular weight: ``max(0, c^α)`` where ``n·l > 0``: the power before the max.

    For an even α, ``c^α > 0`` where ``c < 0`` too; for an odd α it is
    negative there and the max removes it; for a fractional α the power of a
    negative ``c`` is not a real number (NaN here, taken as 0 by ``fmax``).
    Correct: :func:`specular_lobe`, ``max(0, c)^α``.
    """
    with np.errstate(invalid="ignore"):
        return np.where(nl > 0, np.fmax(c ** shininess, 0), 0)


specular_lobe_power_first.formula = ("if", ("n·l",), ("max0", ("pow", "c", "α")))


def specular_lobe_zero_power(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^α`` where ``n·l > 0``, with no ``c > 0`` test: 1 where ``c ≤ 0`` at α = 0.

    For α > 0 it equals the correct weight; at α = 0, ``0^0 = 1`` lights
    every lit point. Correct: :func:`specular_lobe`, 0 where ``c ≤ 0``.
    """
    return np.where(nl > 0, np.maximum(c, 0) ** shininess, 0)


specular_lobe_zero_power.formula = ("if", ("n·l",), ("pow", ("max0", "c"), "α"))


def _with_step(points, normals, shade_args, **step):
    """The reference kernel with one step replaced; ``plan=`` is accepted and ignored."""
    shade_args.pop("plan", None)  # every term is evaluated
    with np.errstate(over="ignore"):  # a wrong length raised to α may overflow: inf is what the bug gives
        return shade_reference(points, normals, steps=Steps(**step), **shade_args)


# ---------------------------------------------------------------------------
# the mistakes


def no_clamp_diffuse(points, normals, **shade_args):
    """Diffuse light without ``max(0, ·)``: negative light on the dark side.

    **What is wrong.** The diffuse weight is ``n·l`` itself::

        diffuse = kd * Id * dot(n, l)                 # wrong

    Where the light is behind the surface, ``n·l < 0`` and the "light"
    added is negative: it subtracts from the ambient light and from every
    other lamp, so the dark side turns black instead of softly lit, and a
    second light is cancelled where the first one is behind.

    **The correct line.** A surface facing away from a light receives none
    of it::

        diffuse = kd * Id * max(0, dot(n, l))         # right

    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, diffuse_weight=lambert_unclamped)


def ungated_specular(points, normals, **shade_args):
    """Specular light without the ``n·l > 0`` gate: highlights on the unlit side.

    **What is wrong.** The highlight is computed wherever the mirror (or
    half) vector points towards the eye, even when the light is behind the
    surface::

        specular = ks * Is * max(0, dot(r, v)) ** alpha      # wrong

    With ``n·l < 0``, ``r = 2(n·l)n − l`` can still point at the eye (and
    ``h`` of Blinn-Phong even more often), so a surface in its own shadow
    shows a highlight: a bright spot or a glow past the terminator, lit by a
    light that cannot reach it.

    **The correct line.** Only a lit point can reflect the light::

        specular = ks * Is * max(0, dot(r, v)) ** alpha if dot(n, l) > 0 else 0   # right

    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, specular_weight=specular_lobe_ungated)


def unnormalised_normals(points, normals, **shade_args):
    """Interpolated normals used without renormalising: dark faceted patches.

    **What is wrong.** Per-pixel shading interpolates the vertex normals
    across each triangle, and the blend of unit vectors is shorter than 1
    inside the triangle (the more the vertex normals differ, the shorter).
    Used as it is::

        n = b0 * n0 + b1 * n1 + b2 * n2               # wrong: |n| < 1 inside

    ``n·l`` shrinks with ``|n|``, so the middle of every triangle is darker
    than its corners and the mesh shows up as a pattern of dark facets; ``r``
    is no longer a unit vector either, so ``r·v`` stays below 1 and a sharp
    highlight dims or vanishes altogether.

    **The correct line.** Renormalise after interpolating::

        n = normalize(b0 * n0 + b1 * n1 + b2 * n2)    # right

    The mistake shows only where ``normals`` are not unit vectors: in
    per-pixel shading, with the interpolated (not renormalised) normals.
    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, normal=raw_normal)


def zero_shininess(points, normals, **shade_args):
    """Shininess α = 0: the whole lit side washed out.

    **What is wrong.** The specular exponent is 0, typically a material whose
    shininess was never set or was read as 0 from a file::

        specular = ks * Is * max(0, dot(r, v)) ** 0   # wrong: always 1

    ``x^0 = 1`` for every ``x`` (and ``pow(0, 0)`` is 1 in NumPy and C), so
    every lit point gets the full ``k_s I_s``: there is no highlight any more,
    the whole side facing the light is washed out by a flat, pale layer.

    **The correct line.** Use the material's exponent, α of about 5–10 for
    plastic and 100–200 for metal::

        specular = ks * Is * max(0, dot(r, v)) ** material.shininess   # right

    Parameters and returns are those of :func:`phonglab.core.shade`; the
    material's shininess is ignored.
    """
    return _with_step(points, normals, shade_args, specular_weight=specular_lobe_zero_exponent)


def reflect_wrong_way(points, normals, **shade_args):
    """The mirror vector turned round, ``r = l − 2(n·l)n``: the highlight in the wrong place.

    **What is wrong.** The reflection of ``l`` is written with its sign
    reversed (the textbook formula for the *incoming* direction ``−l``,
    applied to ``l`` that points away from the surface)::

        r = l - 2 * dot(n, l) * n                     # wrong: −r

    ``r·v`` then changes sign: the eye on the true mirror direction sees no
    highlight, and a highlight appears where ``r·v < 0``: for a convex object
    lit from near the eye, a bright rim at the silhouette instead of a spot
    in the middle.

    **The correct line.** ``r`` points away from the surface, like ``l``::

        r = 2 * dot(n, l) * n - l                     # right

    Only the Phong model uses ``r``; Blinn-Phong is unchanged.
    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, mirror=reflect_reversed)


def unnormalised_light(points, normals, **shade_args):
    """The light vector not normalised: brightness that grows with the distance to the lamp.

    **What is wrong.** The direction to a point light is used without
    dividing by its length::

        l = light.position - p                        # wrong: |l| = d

    ``n·l`` is then ``d cos θ``: a lamp 3 units away makes the diffuse light 3
    times too bright, far points brighter than near ones, and ``r`` is no
    longer a unit vector, so the highlight swells or vanishes.

    **The correct line.** A direction is a unit vector::

        l = normalize(light.position - p)             # right

    Directional lights are unchanged (their direction is normalised apart).
    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, light=light_vector_raw)


def unnormalised_view(points, normals, **shade_args):
    """The view vector not normalised: a highlight that grows with the distance to the eye.

    **What is wrong.** The direction to the eye is used without dividing by
    its length::

        v = eye - p                                   # wrong: |v| = distance to the eye

    ``r·v`` is then the distance times the cosine: raised to α it explodes
    (an eye 5 units away makes the peak ``5^α`` times too bright) and the
    highlight becomes a huge saturated blob.

    **The correct line.**::

        v = normalize(eye - p)                        # right

    Parameters and returns are those of :func:`phonglab.core.shade`; an
    infinite viewer is unchanged.
    """
    return _with_step(points, normals, shade_args, view=view_vector_raw)


def view_from_eye(points, normals, **shade_args):
    """The view vector from the eye to the point, ``v = p − eye``: no highlight where it belongs.

    **What is wrong.** ``v`` is taken along the line of sight, from the eye
    towards the surface, instead of away from the surface::

        v = normalize(p - eye)                        # wrong: −v

    ``r·v`` changes sign: where the eye is on the mirror direction the
    highlight disappears, and with lighting from near the eye a highlight
    rim appears at the silhouette instead.

    **The correct line.** Every direction points away from the surface::

        v = normalize(eye - p)                        # right

    Parameters and returns are those of :func:`phonglab.core.shade`; an
    infinite viewer is unchanged.
    """
    return _with_step(points, normals, shade_args, view=view_from_eye_step)


def attenuated_ambient(points, normals, **shade_args):
    """The lamp's distance attenuation applied to the ambient light too.

    **What is wrong.** The attenuation factor ``f`` multiplies the whole sum,
    ambient term included::

        I = ke + f * (ka * Ia + kd * Id * max(0, dot(n, l)) + ...)   # wrong

    The ambient light stands for light scattered everywhere in the room; it
    does not come from the lamp, so it must not fade with the distance to it.
    With ``f`` applied, far parts of the scene lose their ambient floor and
    turn black, and a close lamp (``f > 1``) brightens the ambient light.

    **The correct line.** Only the lamp's own light is attenuated::

        I = ke + ka * Ia + f * (kd * Id * max(0, dot(n, l)) + ...)   # right

    With several lamps, the first point or spot light's ``f`` is taken.
    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, ambient=ambient_attenuated)


def spot_cutoff_in_degrees(points, normals, **shade_args):
    """The spotlight's cosine compared with its cutoff in degrees: the spot never lights anything.

    **What is wrong.** The cosine of the angle to the axis is compared with
    the cutoff angle itself, in degrees::

        inside = dot(-l, s) >= light.cutoff           # wrong: a cosine against 30 (degrees)

    A cosine is at most 1, so for any cutoff above 1° no point is ever inside
    the cone: the spotlight adds nothing at all (only ``cutoff = 180``, a
    plain point light, still lights).

    **The correct line.** Compare cosines with cosines::

        inside = dot(-l, s) >= cos(radians(light.cutoff))   # right

    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, spot=spot_cone_degrees)


def power_before_max(points, normals, **shade_args):
    """The shininess power taken before the max: a ghost highlight where ``r·v < 0``.

    **What is wrong.** The clamp is applied after raising to α::

        specular = ks * Is * max(0, dot(r, v) ** alpha)   # wrong

    Where ``r·v < 0`` an even α makes ``(r·v)^α`` positive: a second, ghost
    highlight appears where ``r`` points away from the eye, for a sphere lit
    from near the eye a bright rim at the silhouette. An odd α hides the
    bug (the power stays negative and the max removes it), and a fractional α
    raises a negative number to a fractional power: NaN, or an error.

    **The correct line.** Clamp the cosine, then raise it::

        specular = ks * Is * max(0, dot(r, v)) ** alpha   # right

    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, specular_weight=specular_lobe_power_first)


def zero_to_the_zero(points, normals, **shade_args):
    """At α = 0, ``max(0, r·v) ** 0`` is 1 also where ``r·v ≤ 0``: specular on the whole lit side.

    **What is wrong.** The clamp alone is trusted to remove the highlight
    where ``r`` points away from the eye::

        specular = ks * Is * max(0, dot(r, v)) ** alpha            # wrong at alpha = 0

    That holds for every α > 0, but at α = 0 the clamped 0 is raised to the
    power 0, and ``0 ** 0`` is 1 (in Python, NumPy and C): every lit point
    gets the full ``k_s I_s``, a flat pale layer over the whole lit side,
    instead of a wash that ends where ``r·v`` reaches 0.

    **The correct line.** Where ``r·v ≤ 0`` the specular weight is 0, for
    every α::

        specular = ks * Is * dot(r, v) ** alpha if dot(r, v) > 0 else 0   # right

    Parameters and returns are those of :func:`phonglab.core.shade`.
    """
    return _with_step(points, normals, shade_args, specular_weight=specular_lobe_zero_power)


@dataclass(frozen=True)
class Mistake:
    """A named common mistake, as a lesson's ``mistake = "..."`` refers to it.

    Attributes
    ----------
    name : str
        The name lessons use, e.g. ``"no-clamp-diffuse"``.
    title : str
        A short heading for the mistake view.
    looks_like : str
        What the student sees, in one sentence.
    wrong, right : str
        The wrong line of code and the correct one.
    shade : callable
        The wrong variant, with the signature of :func:`phonglab.core.shade`.
    needs_raw_normals : bool
        True when the bug shows only if the shader is given the interpolated,
        not renormalised, normals (per-pixel shading).
    """

    name: str
    title: str
    looks_like: str
    wrong: str
    right: str
    shade: Callable
    needs_raw_normals: bool = False


#: every mistake a lesson can show, by name
MISTAKES = {
    m.name: m
    for m in (
        Mistake(
            "no-clamp-diffuse",
            "Diffuse without max(0, ·)",
            "The dark side goes black: negative light cancels the ambient light and the other lamps.",
            "diffuse = kd * Id * dot(n, l)",
            "diffuse = kd * Id * max(0, dot(n, l))",
            no_clamp_diffuse,
        ),
        Mistake(
            "ungated-specular",
            "Specular without the n·l gate",
            "Highlights appear on the side the light cannot reach.",
            "specular = ks * Is * max(0, dot(r, v)) ** alpha",
            "specular = ks * Is * max(0, dot(r, v)) ** alpha if dot(n, l) > 0 else 0",
            ungated_specular,
        ),
        Mistake(
            "unnormalised-normals",
            "Interpolated normals not renormalised",
            "Every triangle is darker in its middle than at its corners, a pattern of dark facets, "
            "and a sharp highlight dims or vanishes.",
            "n = b0 * n0 + b1 * n1 + b2 * n2",
            "n = normalize(b0 * n0 + b1 * n1 + b2 * n2)",
            unnormalised_normals,
            needs_raw_normals=True,
        ),
        Mistake(
            "zero-shininess",
            "Shininess α = 0",
            "No highlight at all: the whole lit side is washed out by a flat, pale layer.",
            "specular = ks * Is * max(0, dot(r, v)) ** 0",
            "specular = ks * Is * max(0, dot(r, v)) ** material.shininess",
            zero_shininess,
        ),
        Mistake(
            "reflect-wrong-way",
            "Reflection vector pointing the wrong way",
            "The highlight is missing where the eye sees the light mirrored, and a bright rim "
            "appears at the silhouette instead.",
            "r = l - 2 * dot(n, l) * n",
            "r = 2 * dot(n, l) * n - l",
            reflect_wrong_way,
        ),
        Mistake(
            "unnormalised-light",
            "Light vector not normalised",
            "The surface is far too bright, brighter the further it is from the lamp, "
            "and the highlight swells or vanishes.",
            "l = light.position - p",
            "l = normalize(light.position - p)",
            unnormalised_light,
        ),
        Mistake(
            "unnormalised-view",
            "View vector not normalised",
            "The highlight blows up into a huge saturated blob (r·v grows with the distance to the eye).",
            "v = eye - p",
            "v = normalize(eye - p)",
            unnormalised_view,
        ),
        Mistake(
            "view-from-eye",
            "View vector from the eye to the point",
            "No highlight where the light is mirrored towards the eye; a bright rim at the silhouette "
            "instead when the lamp is near the eye.",
            "v = normalize(p - eye)",
            "v = normalize(eye - p)",
            view_from_eye,
        ),
        Mistake(
            "attenuated-ambient",
            "Attenuation applied to the ambient light",
            "Parts far from the lamp lose their ambient floor and turn black; a close lamp brightens "
            "the ambient light.",
            "I = ke + f * (ka * Ia + kd * Id * max(0, dot(n, l)) + ...)",
            "I = ke + ka * Ia + f * (kd * Id * max(0, dot(n, l)) + ...)",
            attenuated_ambient,
        ),
        Mistake(
            "spot-cutoff-in-degrees",
            "Spotlight cosine compared with the cutoff in degrees",
            "The spotlight lights nothing at all: a cosine is never above a cutoff of 30 (degrees).",
            "inside = dot(-l, s) >= light.cutoff",
            "inside = dot(-l, s) >= cos(radians(light.cutoff))",
            spot_cutoff_in_degrees,
        ),
        Mistake(
            "power-before-max",
            "Shininess power before the max",
            "A ghost highlight where r points away from the eye (for an even α): a bright rim at the "
            "silhouette of a sphere lit from near the eye.",
            "specular = ks * Is * max(0, dot(r, v) ** alpha)",
            "specular = ks * Is * max(0, dot(r, v)) ** alpha",
            power_before_max,
        ),
        Mistake(
            "zero-to-the-zero",
            "0 ** 0 = 1 at shininess α = 0",
            "At α = 0 the whole lit side gets the full specular layer, also where r points away from the eye.",
            "specular = ks * Is * max(0, dot(r, v)) ** alpha",
            "specular = ks * Is * dot(r, v) ** alpha if dot(r, v) > 0 else 0",
            zero_to_the_zero,
        ),
    )
}


def get_mistake(name: str) -> Mistake:
    """The mistake called ``name``.

    Raises
    ------
    ValueError
        Naming the value and the names allowed, with a did-you-mean hint.

    Examples
    --------
    >>> get_mistake("zero-shininess").title
    'Shininess α = 0'
    """
    try:
        return MISTAKES[name]
    except (KeyError, TypeError):
        allowed = ", ".join(f'"{n}"' for n in MISTAKES)
        close = difflib.get_close_matches(str(name), list(MISTAKES), n=1)
        hint = f'; did you mean "{close[0]}"?' if close else ""
        raise ValueError(f"mistake: must be one of {allowed}, got {name!r}{hint}") from None

