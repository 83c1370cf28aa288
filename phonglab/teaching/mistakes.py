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
three :class:`~phonglab.core.Steps` swapped for a wrong one.

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
from phonglab.core.reference import lambert, specular_lobe, unit_normal  # noqa: F401  (the correct steps, shown here)

__all__ = [
    "Mistake",
    "MISTAKES",
    "get_mistake",
    "no_clamp_diffuse",
    "ungated_specular",
    "unnormalised_normals",
    "zero_shininess",
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


def specular_lobe_ungated(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^α`` wherever ``c > 0``, whatever the sign of ``n·l``.

    Correct: :func:`specular_lobe`, which is 0 where ``n·l ≤ 0``.
    """
    return np.where(c > 0, np.maximum(c, 0) ** shininess, 0)


def specular_lobe_zero_exponent(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^0``, which is 1 at every lit point (0^0 = 1 too).

    Correct: :func:`specular_lobe`, with the material's α.
    """
    return np.where(nl > 0, np.maximum(c, 0) ** 0.0, 0)


def _with_step(points, normals, shade_args, **step):
    """The reference kernel with one step replaced; ``plan=`` is accepted and ignored."""
    shade_args.pop("plan", None)  # every term is evaluated
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

