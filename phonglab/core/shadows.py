"""Shadow rays: the segment from a surface point towards a light that must be free for the light to reach it.

Directions point *away from the surface point*: ``l`` towards the light.
The rendering equation's visibility term ``S_l(p)`` is 1 when nothing lies
on the segment from ``p`` to the light and 0 otherwise; the kernels
(:func:`~phonglab.core.shade`, :func:`~phonglab.core.shade_reference`) take it
per light as ``visibility=`` and multiply the light's ``f_l`` by it. Finding
what lies on the segment needs the scene's triangles and a ray caster, which
the core has not: :func:`shadow_rays` gives the segments, the render layer
casts them.
"""

from __future__ import annotations

import numpy as np

from .model import DirectionalLight, InvalidValue
from .vectors import normalize, unit_direction

__all__ = ["shadow_rays", "UNBOUNDED"]

#: the length of a shadow ray to a directional light: longer than any scene (coordinates are at most 1e6)
UNBOUNDED = 1e30


def shadow_rays(points, light, *, bias: float):
    """The shadow ray of each point towards ``light``: where it starts, its direction and its length.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        Surface points.
    light : PointLight, SpotLight or DirectionalLight
    bias : float, keyword-only
        How far from the point the ray starts, towards the light (scene
        units, >= 0): the shadow ray's offset.

    Returns
    -------
    origins, directions : ndarray, shape (n, 3), float32
        ``p + bias·l`` and ``l``.
    lengths : ndarray, shape (n,), float32
        How far the ray runs before it reaches the light: ``d − bias``, or
        :data:`UNBOUNDED` for a directional light; 0 where the light is
        within ``bias`` of the point (nothing can block it there).

    Notes
    -----
    .. math::

        \\mathbf{o} = \\mathbf{p} + b\\,\\mathbf{l}, \\qquad
        t \\in [0, \\max(0, d - b)] \\qquad (t \\in [0, \\infty) \\text{ for a directional light})

    A surface point is also a point of its own triangles: a ray started on
    the surface (``b = 0``) meets them at ``t ≈ 0`` on one side or the other
    of rounding, so the surface shadows itself in speckles ("acne"). The
    offset ``b`` skips that, but also skips anything closer than ``b`` to
    the point, so light leaks under an object that nearly touches it.
    A light on the point (``d = 0``) gives ``l = 0``: a ray of length 0.
    """
    if not bias >= 0:
        raise InvalidValue("bias", bias, "must be a finite number >= 0")
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if isinstance(light, DirectionalLight):
        l = np.broadcast_to(unit_direction(light.direction, np.float64), p.shape)
        lengths = np.full(len(p), UNBOUNDED)
    else:
        # l = normalize(position − p), d = |position − p|
        l, d = normalize(np.asarray(light.position, np.float64) - p, return_length=True)
        lengths = np.maximum(d - bias, 0.0)
    origins = p + bias * l
    return origins.astype(np.float32), np.ascontiguousarray(l, dtype=np.float32), lengths.astype(np.float32)
