"""Opacity: a finished colour blended over what lies behind it ("over" compositing).

Opacity (alpha) is not part of the Phong sum: the model computes the light
a surface sends towards the eye, ``I``, and alpha only says how much of what
lies behind the surface that colour *covers* when the picture is put
together. Blending mixes amounts of light, so it is done on **linear** light
(after exposure and the clip to [0, 1], *before* the display encoding of
:mod:`phonglab.core.display`): a 50 % mix of black and white is half the
light of white, which the sRGB curve then shows as 188/255, not 128.

Two functions: :func:`over` puts one layer over what is behind it;
:func:`composite_closed` spells out the case of a closed convex mesh,
whose near side lies over its own far side, which lies over the
background.
"""

from __future__ import annotations

import numpy as np

__all__ = ["over", "composite_closed"]


def _float(values):
    a = np.asarray(values)
    return a if np.issubdtype(a.dtype, np.floating) else a.astype(np.float64)


def over(color, alpha, behind):
    """A layer of opacity ``alpha`` over what lies behind it, in linear light.

    Parameters
    ----------
    color : array_like, shape (..., 3)
        The layer's linear colour (already exposed and clipped for display).
    alpha : float or array_like broadcasting with ``color[..., :1]``
        Its opacity in [0, 1]: 1 covers what is behind, 0 is invisible.
    behind : array_like, shape (..., 3)
        The linear colour of everything behind the layer, already composited.

    Returns
    -------
    ndarray, shape (..., 3)
        The blended linear colour; float32 stays float32.

    Notes
    -----
    The "over" operator of Porter and Duff (1984) for an opaque background:

    .. math:: C = \\alpha\\, C_{\\text{layer}} + (1 - \\alpha)\\, C_{\\text{behind}}

    It is linear in both colours, so it must be applied to linear light: an
    encoded (sRGB) value is not proportional to the light it stands for.
    ``alpha = 1`` returns ``color`` exactly and ``alpha = 0`` returns
    ``behind`` exactly.

    Examples
    --------
    >>> over([1.0, 0.0, 0.0], 0.5, [0.0, 0.0, 1.0]).tolist()
    [0.5, 0.0, 0.5]
    """
    c = _float(color)
    b = np.asarray(behind, dtype=c.dtype)
    a = np.asarray(alpha, dtype=c.dtype)
    # each colour weighted by how much of the pixel it covers
    return a * c + (c.dtype.type(1) - a) * b


def composite_closed(front, back, background, alpha):
    """A closed convex surface of opacity ``alpha``: near side over far side over background.

    Parameters
    ----------
    front : array_like, shape (..., 3)
        Linear colour of the near side (the front faces, seen from outside).
    back : array_like, shape (..., 3)
        Linear colour of the far side (the back faces, seen from inside),
        shaded with the scene's rule for faces turned away from the eye.
    background : array_like, shape (..., 3)
        Linear colour of what lies behind the surface.
    alpha : float in [0, 1]
        The material's opacity, the same on both sides.

    Returns
    -------
    ndarray, shape (..., 3)

    Notes
    -----
    Two layers, each blended with :func:`over`, the far one first:

    .. math:: C = \\alpha C_{\\text{front}} + (1 - \\alpha)
              \\left[\\alpha C_{\\text{back}} + (1 - \\alpha) C_{\\text{bg}}\\right]

    A ray through a closed convex mesh meets it exactly twice, so this is
    the whole picture for a sphere or a cube. A non-convex mesh (a torus)
    can be met four times; the renderer then composites the nearest front
    face and the nearest back face only (see :mod:`phonglab.render.translucency`).

    Examples
    --------
    >>> composite_closed([0.8, 0.8, 0.8], [0.0, 0.0, 0.0], [0.4, 0.4, 0.4], 0.5).tolist()
    [0.5, 0.5, 0.5]
    """
    return over(front, alpha, over(back, alpha, background))
