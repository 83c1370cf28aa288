"""Boundary checks shared by the shading functions.

:func:`~phonglab.core.shade`, :func:`~phonglab.core.shade_reference`,
:func:`~phonglab.core.plan_effects` and :func:`~phonglab.core.vectors` check
their arguments here, once per call, and trust them afterwards. A refused
value raises :class:`~phonglab.core.InvalidValue` naming the argument, the
value and what is allowed.
"""

from __future__ import annotations

import numpy as np

from .model import MODELS, AmbientLight, InvalidValue, Light, Material, vec3

__all__ = ["as_points", "check_lights", "check_material", "check_model", "check_visibility", "refuse_nonfinite",
           "viewer"]


def check_material(material) -> Material:
    """``material``, which must be a :class:`~phonglab.core.Material`."""
    if not isinstance(material, Material):
        raise InvalidValue("material", material, "must be a phonglab Material")
    return material


def check_model(model) -> str:
    """``model``, which must be one of :data:`~phonglab.core.MODELS`."""
    if model not in MODELS:
        raise InvalidValue("model", model, f"must be one of {', '.join(MODELS)}")
    return model


def check_lights(lights) -> tuple:
    """``lights`` as a tuple, each a phonglab light."""
    lights = tuple(lights)
    for i, lt in enumerate(lights):
        if not isinstance(lt, Light):
            raise InvalidValue(f"lights[{i}]", lt, "must be a phonglab light (AmbientLight, PointLight, "
                                                    "DirectionalLight, SpotLight)")
    return lights


def viewer(eye, view_direction):
    """``(eye, None)`` for a local viewer or ``(None, view_direction)`` for an infinite one.

    Exactly one must be given; each is three finite numbers (the view
    direction not all zero), returned as a tuple of floats.
    """
    if (eye is None) == (view_direction is None):
        raise InvalidValue("eye", eye, "give exactly one of eye= (a local viewer) or "
                           "view_direction= (an infinite viewer)")
    if eye is not None:
        return vec3("eye", eye), None
    return None, vec3("view_direction", view_direction, nonzero=True)


def as_points(name, a):
    """``a`` as an array of shape (..., 3) of real numbers; finiteness is checked as it is read."""
    a = np.asarray(a)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InvalidValue(name, f"array of shape {a.shape}", "must be an array of shape (..., 3)")
    if not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)):
        raise InvalidValue(name, f"array of dtype {a.dtype}", "must hold real numbers")
    return a


def refuse_nonfinite(name, a):
    """Raise InvalidValue naming the first NaN or inf in ``a``, if there is one."""
    if a.size and not np.isfinite(a).all():
        bad = np.argwhere(~np.isfinite(a))[0]
        raise InvalidValue(name, f"{a[tuple(bad)]} at index {tuple(int(i) for i in bad)}",
                           "must be finite (no NaN or inf)")


def check_visibility(visibility, lights, shape) -> dict | None:
    """``visibility`` as ``{light index: bool array of shape shape}``, or None when no light is blocked anywhere.

    ``visibility`` maps the index of a point, spot or directional light in
    ``lights`` to an array of 0 and 1 (or False and True), one per point,
    broadcasting to ``shape`` (the points' shape without its last axis):
    0 where the light is blocked. Lights it leaves out are not blocked.
    """
    if visibility is None:
        return None
    if not hasattr(visibility, "items"):
        raise InvalidValue("visibility", visibility, "must map light indices to arrays of 0 and 1, one per point")
    out = {}
    for index, seen in visibility.items():
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)) or not 0 <= index < len(lights):
            raise InvalidValue("visibility", f"key {index!r}", f"must be the index of a light, 0 to {len(lights) - 1}")
        if isinstance(lights[index], AmbientLight):
            raise InvalidValue("visibility", f"key {index}", "must be a point, spot or directional light: "
                                                             "ambient light is not blocked")
        seen = np.asarray(seen)
        if seen.dtype != bool:
            if not (np.issubdtype(seen.dtype, np.number) and ((seen == 0) | (seen == 1)).all()):
                raise InvalidValue(f"visibility[{index}]", f"array of dtype {seen.dtype}",
                                   "must hold only 0 and 1 (or False and True)")
            seen = seen == 1
        try:
            seen = np.broadcast_to(seen, tuple(shape))
        except ValueError:
            raise InvalidValue(f"visibility[{index}]", f"array of shape {seen.shape}",
                               f"must broadcast to the points' shape {tuple(shape)}") from None
        out[int(index)] = seen
    return out or None
