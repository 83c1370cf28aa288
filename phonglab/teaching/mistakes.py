"""Common mistakes: deliberately wrong versions of the Phong shading.

Every function in this module makes **one** classic bug on purpose, so a
lesson can show what that bug looks like next to the correct picture. They
exist for teaching only: :mod:`phonglab.core` never imports this module, and
nothing here is used to draw a correct image.

Each variant takes the inputs of :func:`phonglab.core.shade` (``points``,
``normals``, ``material``, ``lights``, ``eye`` or ``view_direction``,
``model``, ``two_sided``) and returns the same :class:`phonglab.core.Shading`.
They all run one plain, textbook evaluation of the model (:func:`textbook`),
built from the core's public vector functions (``normalize``, ``reflect``,
``dot``), with one of its three steps swapped for a wrong one:

=========================  ===================================================
step                       correct version / wrong version
=========================  ===================================================
the normal                 ``n = normalize(n)`` / used as interpolated
the diffuse weight         ``max(0, n·l)`` / ``n·l``
the specular weight        ``max(0, c)^α`` where ``n·l > 0`` / no ``n·l`` gate;
                           ``α`` replaced by 0
=========================  ===================================================

With none of the steps swapped, :func:`textbook` agrees with the core to
rounding error; the tests hold each mistake to that: it differs from the core
exactly where its bug bites and agrees everywhere else.

Directions point *away from the surface point*: ``n`` the normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``, and ``c`` is ``r·v`` (Phong) or ``n·h`` (Blinn-Phong).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from phonglab import core as pl

__all__ = [
    "Mistake",
    "MISTAKES",
    "get_mistake",
    "no_clamp_diffuse",
    "ungated_specular",
    "unnormalised_normals",
    "zero_shininess",
    "textbook",
]


# ---------------------------------------------------------------------------
# the three steps that the mistakes get wrong, each next to its correct form


def unit_normal(normals):
    """Correct: renormalise the normal before using it, ``n = normalize(n)``."""
    return pl.normalize(normals)


def raw_normal(normals):
    """WRONG: use the normal as it comes, even when it is shorter than 1."""
    return normals


def lambert(nl):
    """Correct diffuse weight: ``max(0, n·l)``; a light behind the surface adds nothing."""
    return np.maximum(nl, 0)


def lambert_unclamped(nl):
    """WRONG diffuse weight: ``n·l``, negative where the light is behind the surface."""
    return nl


def specular_lobe(nl, c, shininess):
    """Correct specular weight: ``max(0, c)^α`` where ``n·l > 0`` and ``c > 0``, else 0."""
    lit = (nl > 0) & (c > 0)
    return np.where(lit, np.maximum(c, 0) ** shininess, 0)


def specular_lobe_ungated(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^α`` wherever ``c > 0``, whatever the sign of ``n·l``."""
    return np.where(c > 0, np.maximum(c, 0) ** shininess, 0)


def specular_lobe_zero_exponent(nl, c, shininess):
    """WRONG specular weight: ``max(0, c)^0``, which is 1 at every lit point (0^0 = 1 too)."""
    return np.where(nl > 0, np.maximum(c, 0) ** 0.0, 0)


# ---------------------------------------------------------------------------
# one textbook evaluation of the model, with the steps as parameters


def _viewer(eye, view_direction):
    if (eye is None) == (view_direction is None):
        raise ValueError("eye: give exactly one of eye= (a local viewer) or view_direction= (an infinite viewer)")
    return eye, view_direction


def _light_factor(light, distance, l):
    """``f_l``: distance attenuation times the spotlight factor (1 for a directional light)."""
    if isinstance(light, pl.DirectionalLight):
        return 1.0
    a, b, c = light.attenuation
    d = np.maximum(distance, pl.DISTANCE_FLOOR)
    f = 1.0 / np.maximum(a + b * d + c * d * d, 1.0 / pl.ATTENUATION_MAX)
    if isinstance(light, pl.SpotLight) and light.is_cone:
        # cosine of the angle between the spot's axis and the ray light -> point
        cos_axis = -pl.dot(l, pl.normalize(np.asarray(light.direction, dtype=l.dtype)))
        inside = cos_axis >= math.cos(math.radians(light.cutoff))
        f = f * np.where(inside, np.maximum(cos_axis, 0) ** light.exponent, 0)
    return f


def textbook(
    points,
    normals,
    *,
    material,
    lights,
    eye=None,
    view_direction=None,
    model="phong",
    two_sided=False,
    plan=None,
    normal_step: Callable = unit_normal,
    diffuse_step: Callable = lambert,
    specular_step: Callable = specular_lobe,
):
    """The Phong model evaluated the plain way, one light at a time.

    Parameters
    ----------
    points, normals : array_like, shape (..., 3)
    material : phonglab.core.Material
    lights : sequence of phonglab.core lights
    eye, view_direction : 3 floats, keyword-only
        A local viewer at ``eye`` or an infinite one along ``view_direction``
        (exactly one of them).
    model : {"phong", "blinn-phong"}
    two_sided : bool
        Negate normals facing away from the eye (``n·v < 0``).
    plan : ignored
        Accepted so a caller can pass the arguments it gives
        :func:`phonglab.core.shade`; every term is always evaluated here.
    normal_step, diffuse_step, specular_step : callable
        The three steps a mistake may replace (see the module docstring).

    Returns
    -------
    phonglab.core.Shading
        Float32 when both ``points`` and ``normals`` are float32, else float64.

    Notes
    -----
    .. math::

        I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l}
            \\max(0, n\\cdot l) + k_s \\circ I_{s,l} \\max(0, c_l)^{\\alpha} \\right]

    With the default steps this is the correct model, and matches
    :func:`phonglab.core.shade` to rounding error.
    """
    del plan  # every term is evaluated
    eye, view_direction = _viewer(eye, view_direction)
    if model not in pl.MODELS:
        raise ValueError(f"model: must be one of {', '.join(pl.MODELS)}, got {model!r}")
    points, normals = np.asarray(points), np.asarray(normals)
    dtype = np.result_type(points.dtype, normals.dtype, np.float32)
    points, normals = np.broadcast_arrays(points.astype(dtype), normals.astype(dtype))

    # the normal, and the direction to the eye
    n = normal_step(normals)
    if eye is not None:
        v = pl.normalize(np.asarray(eye, dtype) - points)
    else:
        v = np.broadcast_to(pl.normalize(np.asarray(view_direction, dtype)), points.shape)
    if two_sided:
        # two-sided: negate the normals that face away from the eye
        n = np.where((pl.dot(n, v) < 0)[..., None], -n, n)

    # ambient and emission: the same at every point
    ia = np.zeros(3)
    for light in lights:
        if isinstance(light, pl.AmbientLight):
            ia += light.ambient_rgb
    ambient = np.broadcast_to((np.asarray(material.ka) * ia).astype(dtype), points.shape)
    emission = np.broadcast_to(np.asarray(material.emission, dtype), points.shape)

    diffuse = np.zeros(points.shape, dtype)
    specular = np.zeros(points.shape, dtype)
    for light in lights:
        if isinstance(light, pl.AmbientLight):
            continue
        # direction to the light and its distance
        if isinstance(light, pl.DirectionalLight):
            l = np.broadcast_to(pl.normalize(np.asarray(light.direction, dtype)), points.shape)
            distance = None
        else:
            l, distance = pl.normalize(np.asarray(light.position, dtype) - points, return_length=True)
        f = np.asarray(_light_factor(light, distance, l), dtype)[..., None]
        nl = pl.dot(n, l)

        # diffuse: k_d I_d times the diffuse weight
        kd_id = np.asarray(material.kd) * np.asarray(light.diffuse_rgb)
        diffuse += (f * kd_id * diffuse_step(nl)[..., None]).astype(dtype)

        # specular: k_s I_s times the specular weight of r·v or n·h
        if model == "phong":
            c = pl.dot(pl.reflect(l, n), v)
        else:
            c = pl.dot(n, pl.normalize(l + v))
        ks_is = np.asarray(material.ks) * np.asarray(light.specular_rgb)
        specular += (f * ks_is * specular_step(nl, c, material.shininess)[..., None]).astype(dtype)

    color = ambient + emission + diffuse + specular
    return pl.Shading(ambient=ambient, diffuse=diffuse, specular=specular, emission=emission, color=color)


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
    return textbook(points, normals, diffuse_step=lambert_unclamped, **shade_args)


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
    return textbook(points, normals, specular_step=specular_lobe_ungated, **shade_args)


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
    return textbook(points, normals, normal_step=raw_normal, **shade_args)


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
    return textbook(points, normals, specular_step=specular_lobe_zero_exponent, **shade_args)


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


def shade_scene(scene, points, normals, mistake: str | None = None):
    """Shade ``points`` under a scene, correctly or with a named mistake.

    Parameters
    ----------
    scene : phonglab.scene.Scene
    points, normals : array_like, shape (..., 3)
    mistake : str or None
        None shades correctly (:func:`phonglab.scene.shade`); a name from
        :data:`MISTAKES` uses that wrong variant with the scene's material,
        lights, viewer, model and two-sidedness.

    Returns
    -------
    phonglab.core.Shading
    """
    from phonglab import scene as scene_module  # scenes are optional here: imported on use
    from phonglab.scene import viewer

    if mistake is None:
        return scene_module.shade(scene, points, normals)
    return get_mistake(mistake).shade(
        points,
        normals,
        material=scene.material,
        lights=scene.lights,
        model=scene.model,
        two_sided=scene.two_sided,
        **viewer(scene),
    )
