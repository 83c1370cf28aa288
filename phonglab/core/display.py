"""From linear light to the numbers a display shows.

The model computes *linear* radiance: 0.5 is half as much light as 1.0. A
display does not respond linearly to the numbers it is sent; an sRGB screen
shows the value ``V`` with a luminance of about ``V^2.2``. Writing linear
values straight into an 8-bit image (×255, as 1990s fixed-function hardware
did) therefore shows a 50 % grey at about 21 % of white's luminance. The
display encoding undoes the screen's curve so that what the eye receives is
proportional to what the model computed:

    linear radiance → × exposure → clip to [0, 1] → transfer curve → × 255

with the transfer curve of IEC 61966-2-1 (sRGB) by default, or none
(``"linear"``) to show what the raw numbers look like.
"""

from __future__ import annotations

import numpy as np

from .model import InvalidValue

__all__ = ["DISPLAY_ENCODINGS", "srgb_encode", "srgb_decode", "display_values", "display_bytes"]

#: the encodings a scene, the page and an export can use
DISPLAY_ENCODINGS = ("srgb", "linear")

# IEC 61966-2-1: the linear segment near black and the power segment above it
_SRGB_THRESHOLD = 0.0031308
_SRGB_SLOPE = 12.92
_SRGB_GAMMA = 2.4
_SRGB_OFFSET = 0.055
_SRGB_DECODE_THRESHOLD = _SRGB_THRESHOLD * _SRGB_SLOPE  # 0.04045 (to rounding)


def srgb_encode(linear):
    """The sRGB transfer curve: linear values in [0, 1] to encoded values in [0, 1].

    Parameters
    ----------
    linear : array_like
        Linear values, already clipped to [0, 1].

    Returns
    -------
    ndarray
        Encoded values, same shape; float32 stays float32.

    Notes
    -----
    .. math::

        V = \\begin{cases} 12.92\\,c & c \\le 0.0031308 \\\\
                           1.055\\,c^{1/2.4} - 0.055 & c > 0.0031308 \\end{cases}

    (IEC 61966-2-1). The two pieces meet at the threshold to within 1e-7.

    Examples
    --------
    >>> round(float(srgb_encode(0.5)), 4)
    0.7354
    """
    c = np.asarray(linear)
    if not np.issubdtype(c.dtype, np.floating):
        c = c.astype(np.float64)
    # the power segment, on values clipped up to the threshold so the power never sees 0
    power = np.power(np.maximum(c, c.dtype.type(_SRGB_THRESHOLD)), c.dtype.type(1 / _SRGB_GAMMA))
    encoded = c.dtype.type(1 + _SRGB_OFFSET) * power - c.dtype.type(_SRGB_OFFSET)
    # the linear segment near black
    return np.where(c <= _SRGB_THRESHOLD, c * c.dtype.type(_SRGB_SLOPE), encoded)


def srgb_decode(encoded):
    """The inverse of :func:`srgb_encode`: an sRGB value in [0, 1] to linear light.

    Used where a person picks a colour on screen (a colour picker shows and
    returns sRGB) and the model needs the linear value.

    Examples
    --------
    >>> round(float(srgb_decode(188 / 255)), 3)
    0.503
    """
    v = np.asarray(encoded)
    if not np.issubdtype(v.dtype, np.floating):
        v = v.astype(np.float64)
    power = np.power((np.maximum(v, v.dtype.type(_SRGB_DECODE_THRESHOLD)) + v.dtype.type(_SRGB_OFFSET))
                     / v.dtype.type(1 + _SRGB_OFFSET), v.dtype.type(_SRGB_GAMMA))
    return np.where(v <= _SRGB_DECODE_THRESHOLD, v / v.dtype.type(_SRGB_SLOPE), power)


def _check(encoding, exposure):
    if encoding not in DISPLAY_ENCODINGS:
        raise InvalidValue("display", encoding, f"must be one of {', '.join(DISPLAY_ENCODINGS)}")
    if not (isinstance(exposure, (int, float, np.floating)) and np.isfinite(exposure) and exposure > 0):
        raise InvalidValue("exposure", exposure, "must be a finite number > 0")


def display_values(color, *, encoding: str = "srgb", exposure: float = 1.0):
    """Linear radiance to display values in [0, 1]: exposure, clip, transfer curve.

    Parameters
    ----------
    color : array_like
        Linear radiance, any shape (unclamped: values above 1 are over-exposed).
    encoding : {"srgb", "linear"}
        ``"srgb"`` applies the sRGB curve; ``"linear"`` sends the clipped
        values as they are (the fixed-function look).
    exposure : float > 0
        Radiance is multiplied by this before clipping: below 1 brings an
        over-exposed highlight back into range.

    Returns
    -------
    ndarray
        Values in [0, 1], same shape; float32 stays float32.

    Notes
    -----
    .. math:: V = \\mathrm{curve}(\\min(1, \\max(0, e \\cdot c)))

    NaN is shown as 0 (black) rather than propagated into an image.

    Examples
    --------
    >>> display_values([0.5, 1.0, 2.0], encoding="linear").tolist()
    [0.5, 1.0, 1.0]
    """
    _check(encoding, exposure)
    c = np.asarray(color)
    if not np.issubdtype(c.dtype, np.floating):
        c = c.astype(np.float64)
    # exposure, then clip to what the display can show (NaN to black)
    c = np.nan_to_num(c * c.dtype.type(exposure), nan=0.0, posinf=1.0, neginf=0.0)
    c = np.clip(c, 0, 1)
    return srgb_encode(c) if encoding == "srgb" else c


def display_bytes(color, *, encoding: str = "srgb", exposure: float = 1.0) -> np.ndarray:
    """Linear radiance to 8-bit display values (uint8), rounded to nearest.

    A 50 % grey (0.5) is 188 with the sRGB encoding and 128 with ``"linear"``.

    Examples
    --------
    >>> display_bytes([0.5, 1.0]).tolist(), display_bytes([0.5, 1.0], encoding="linear").tolist()
    ([188, 255], [128, 255])
    """
    values = display_values(color, encoding=encoding, exposure=exposure)
    return np.rint(values * values.dtype.type(255)).astype(np.uint8)
