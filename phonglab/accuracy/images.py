"""Linear radiance images as the display shows them: the accuracy panel's and the grader's pictures.

The core computes linear light. Like every picture the app shows or writes,
these go through the core's display encoding (:func:`phonglab.core.display.display_bytes`):
exposure, clip, then the sRGB curve by default or the raw values with
``encoding="linear"``. Pixels outside the surface get a background colour,
which is already a display value (not encoded again).
"""

from __future__ import annotations

import numpy as np

from phonglab.core.display import display_bytes

__all__ = ["display_image"]


def display_image(color, mask, *, background, encoding: str = "srgb", exposure: float = 1.0) -> np.ndarray:
    """A (height, width, 3) linear-radiance image as 8-bit display values, ``background`` outside ``mask``.

    Parameters
    ----------
    color : array_like, shape (height, width, 3)
        Linear radiance; NaN (no colour) is shown black.
    mask : array_like of bool, shape (height, width)
        The pixels the surface covers.
    background : 3 ints
        The RGB (0..255) of the pixels outside ``mask``, a display value.
    encoding : {"srgb", "linear"}
        The display's transfer curve (:func:`phonglab.core.display.display_values`).
    exposure : float > 0
        Radiance is multiplied by this before clipping.

    Returns
    -------
    ndarray, shape (height, width, 3), uint8

    Notes
    -----
    .. math:: V = \\mathrm{round}(255\\,\\mathrm{curve}(\\min(1, \\max(0, e \\cdot c))))

    A 50 % grey (0.5) is 188 with the sRGB curve and 128 raw.

    Examples
    --------
    >>> grey = np.full((1, 2, 3), 0.5)
    >>> display_image(grey, np.array([[True, False]]), background=(26, 26, 30)).tolist()
    [[[188, 188, 188], [26, 26, 30]]]
    >>> display_image(grey, np.ones((1, 2), bool), background=(0, 0, 0), encoding="linear")[0, 0].tolist()
    [128, 128, 128]
    """
    # exposure, clip and the display's curve, once, by the core
    out = display_bytes(np.asarray(color, dtype=np.float64), encoding=encoding, exposure=exposure)
    out[~np.asarray(mask, dtype=bool)] = background
    return out
