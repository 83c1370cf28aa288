"""Comparing rendered images with a stated tolerance.

Two renders of the same scene on different drivers differ by a level here
and there along edges; a real change (a moved highlight, a wrong colour)
moves many pixels by a lot. :func:`image_difference` measures both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: default tolerance: mean absolute difference per channel, in 0..1 units
MEAN_TOLERANCE = 2 / 255
#: default tolerance: a pixel is "off" when a channel differs by more than this (0..1 units)
PIXEL_TOLERANCE = 16 / 255
#: default tolerance: fraction of pixels allowed to be off
OFF_FRACTION_TOLERANCE = 0.005


@dataclass(frozen=True)
class ImageDifference:
    """How far two RGB images are apart.

    Attributes
    ----------
    mean_abs : float
        Mean absolute difference over all pixels and channels, in 0..1 units.
    off_fraction : float
        Fraction of pixels with some channel differing by more than ``pixel_tolerance``.
    pixel_tolerance : float
        The per-channel threshold used for ``off_fraction`` (0..1 units).
    """

    mean_abs: float
    off_fraction: float
    pixel_tolerance: float

    def within(self, mean_tolerance: float = MEAN_TOLERANCE,
               off_fraction_tolerance: float = OFF_FRACTION_TOLERANCE) -> bool:
        """True when both measures are inside their tolerances."""
        return self.mean_abs <= mean_tolerance and self.off_fraction <= off_fraction_tolerance

    def __str__(self) -> str:
        return (f"mean |diff| = {self.mean_abs * 255:.2f}/255 per channel, "
                f"{self.off_fraction:.3%} of pixels off by > {self.pixel_tolerance * 255:.0f}/255")


def image_difference(a: np.ndarray, b: np.ndarray, pixel_tolerance: float = PIXEL_TOLERANCE) -> ImageDifference:
    """Compare two uint8 RGB images of the same shape.

    Raises
    ------
    ValueError
        If the shapes differ.
    """
    a = np.asarray(a)
    b = np.asarray(b)
    if a.shape != b.shape:
        raise ValueError(f"images differ in shape: {a.shape} and {b.shape}")
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16)) / 255.0
    off = (diff > pixel_tolerance).any(axis=-1)
    return ImageDifference(float(diff.mean()), float(off.mean()), pixel_tolerance)
