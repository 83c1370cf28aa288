"""What a graded ``shade`` may use besides NumPy and ``math``: three vector helpers and the scene's data.

The grader's sandbox holds this one file, not the phonglab package (whose
shading is the answer): in a student's file ::

    from shade_helpers import normalize, dot, reflect

The material and the lights reach ``shade`` as the plain, read-only objects
below, rebuilt in the sandbox from the grader's numbers. Their fields are
what the model needs and nothing else; ``ambient_rgb``, ``diffuse_rgb`` and
``specular_rgb`` are a light's effective intensities ``Ia``, ``Id``, ``Is``
(its colour already multiplied by its intensity).

Convention: every direction is a unit vector pointing *away from the surface
point* (``l`` towards the light, ``v`` towards the eye). The helpers work on
one vector of 3 numbers and return float64 NumPy arrays; they equal
phonglab's own ``normalize``, ``dot`` and ``reflect`` (a test checks it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["normalize", "dot", "reflect", "Material", "Light", "AmbientLight", "PointLight",
           "DirectionalLight", "SpotLight", "material_from", "light_from"]


def normalize(v) -> np.ndarray:
    """``v / |v|`` as a float64 array of 3; a zero vector stays zero (no NaN).

    Examples
    --------
    >>> normalize([3.0, 0.0, 4.0])
    array([0.6, 0. , 0.8])
    """
    v = np.asarray(v, dtype=np.float64).reshape(3)
    squares = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    if 1e-290 < squares < 1e290:  # the direct formula: the squares neither overflow nor lose bits
        return v / np.sqrt(squares)
    scale = np.max(np.abs(v))  # else divide by the largest component first
    if scale == 0:
        return np.zeros(3)  # the zero-length guard
    w = v / scale
    return w / np.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])


def dot(a, b) -> float:
    """``a·b = ax bx + ay by + az bz``: for unit vectors, the cosine of the angle between them."""
    a = np.asarray(a, dtype=np.float64).reshape(3)
    b = np.asarray(b, dtype=np.float64).reshape(3)
    return float(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])


def reflect(l, n) -> np.ndarray:
    """The mirror image of ``l`` about the unit normal ``n``: ``r = 2(n·l)n − l``.

    Examples
    --------
    >>> reflect([1.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    array([-1.,  0.,  1.])
    """
    l = np.asarray(l, dtype=np.float64).reshape(3)
    n = np.asarray(n, dtype=np.float64).reshape(3)
    return 2.0 * dot(n, l) * n - l


@dataclass(frozen=True, kw_only=True)
class Material:
    """``ka``, ``kd``, ``ks``, ``emission``: RGB triples; ``shininess``: the exponent α ≥ 0."""

    ka: tuple
    kd: tuple
    ks: tuple
    shininess: float
    emission: tuple


@dataclass(frozen=True, kw_only=True)
class Light:
    """A light's effective intensities ``Ia``, ``Id``, ``Is`` (RGB triples)."""

    ambient_rgb: tuple
    diffuse_rgb: tuple
    specular_rgb: tuple


@dataclass(frozen=True, kw_only=True)
class AmbientLight(Light):
    """Adds ``ka ∘ ambient_rgb`` and nothing else."""


@dataclass(frozen=True, kw_only=True)
class PointLight(Light):
    """At ``position``; ``f = 1 / (a + b·d + c·d²)`` with ``(a, b, c) = attenuation``."""

    position: tuple
    attenuation: tuple


@dataclass(frozen=True, kw_only=True)
class DirectionalLight(Light):
    """``l = normalize(direction)`` everywhere: the direction points towards the light; ``f = 1``."""

    direction: tuple


@dataclass(frozen=True, kw_only=True)
class SpotLight(PointLight):
    """A point light in a cone around ``direction`` (from the light outwards), half-angle ``cutoff`` degrees."""

    direction: tuple
    cutoff: float
    exponent: float


KINDS = {cls.__name__: cls for cls in (AmbientLight, PointLight, DirectionalLight, SpotLight)}


def _triple(value) -> tuple:
    return tuple(float(x) for x in value)


def material_from(data: dict) -> Material:
    """A :class:`Material` from the grader's numbers."""
    return Material(ka=_triple(data["ka"]), kd=_triple(data["kd"]), ks=_triple(data["ks"]),
                    shininess=float(data["shininess"]), emission=_triple(data["emission"]))


def light_from(data: dict) -> Light:
    """A light from the grader's numbers: ``{"type": "PointLight", "position": [...], ...}``."""
    cls = KINDS[data["type"]]
    fields = {name: value for name, value in data.items() if name != "type"}
    return cls(**{name: (float(value) if name in ("cutoff", "exponent") else _triple(value))
                  for name, value in fields.items()})
