"""A shade() that returns NaN in the red channel."""

import numpy as np


def shade(point, normal, eye, material, lights):
    return np.array([np.nan, 0.0, 0.0])
