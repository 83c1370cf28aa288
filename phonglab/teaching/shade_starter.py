"""The Phong model at one point: write ``shade`` below, then grade it.

Check your work with::

    phonglab grade shade.py

The grader calls your function on a fixed set of cases and compares it with
phonglab's own shading, group by group (ambient, diffuse, specular, the
reflection vector, shininess, attenuation, directional lights, spotlights,
many lights, hard cases). When a group fails it shows the worst case and,
if your result matches a common mistake, names it.

The contract
------------
``shade(point, normal, eye, material, lights)`` returns the colour of ONE
surface point as 3 floats (R, G, B), not clamped to [0, 1] (above 1 is
over-exposed, not wrong). Use float64 throughout.

- ``point``, ``normal``, ``eye``: NumPy arrays of 3 float64 numbers. The
  normal may have any length: normalise it. The viewer is at ``eye``:
  ``v = normalize(eye - point)``.
- ``material``: read-only; ``material.ka``, ``.kd``, ``.ks`` and
  ``.emission`` are RGB triples, ``material.shininess`` is α ≥ 0.
- ``lights``: a list of read-only lights. ``light.ambient_rgb``,
  ``light.diffuse_rgb`` and ``light.specular_rgb`` are its effective
  intensities ``Ia``, ``Id``, ``Is`` (RGB triples). Tell them apart with
  ``type(light).__name__`` or ``isinstance(light, shade_helpers.PointLight)``
  (a ``SpotLight`` is also a ``PointLight``).

  * ``AmbientLight``: adds ``ka ∘ ambient_rgb``, nothing else. Only
    ambient lights add ambient light.
  * ``PointLight``: at ``light.position``; ``l = normalize(position - point)``,
    ``f = 1 / (a + b·d + c·d²)`` with ``(a, b, c) = light.attenuation`` and
    ``d`` the distance from the point to the light.
  * ``DirectionalLight``: ``l = normalize(light.direction)`` at every point
    (the direction points *towards* the light), ``f = 1``.
  * ``SpotLight``: a point light whose ``f`` is also multiplied by the spot
    factor: with ``s = normalize(light.direction)`` the cone's axis (from
    the light outwards), ``max(0, -l·s) ** light.exponent`` where
    ``-l·s >= cos(light.cutoff degrees)`` (inside the cone, edge included)
    and 0 outside. ``cutoff == 180`` is a plain point light: no cone, no
    exponent.

The model, one-sided Phong, every product per RGB channel (``∘``)::

    I = ke + ka∘Ia + Σ_lights f · [ kd∘Id · max(0, n·l) + ks∘Is · S ]
    r = 2(n·l)n − l
    S = max(0, r·v) ** α   where n·l > 0 and r·v > 0,   else 0 (also for α = 0)

``Ia`` is the sum of the ambient lights' ``ambient_rgb``; ``ke`` is
``material.emission``; every direction is a unit vector pointing *away from
the point* (towards the light, towards the eye). At α = 0, ``S`` is 1 where
``n·l > 0`` and ``r·v > 0`` and 0 elsewhere, although ``max(0, r·v) ** 0``
is 1 also where ``r·v ≤ 0`` (``0 ** 0 == 1``). Guards: a light exactly on the point
(``l`` of length 0) or a normal of length 0 adds no diffuse or specular
light; an eye exactly on the point (``v`` of length 0) sees no specular
light (``r·v`` is 0 there).

You may use NumPy, ``math`` and the grader's helpers::

    from shade_helpers import normalize, dot, reflect

(``normalize`` keeps a zero vector zero). The phonglab package is not
available while grading: this is the model you are writing. Your file runs
in a sandbox with no files to open, no programs, no network and no new
processes; ``print`` output is not shown.
"""

import numpy as np


def shade(point, normal, eye, material, lights):
    """The Phong colour at ``point``: 3 floats (R, G, B), unclamped.

    Parameters
    ----------
    point, normal, eye : numpy.ndarray, shape (3,), float64
        The surface point, its normal (any length) and the viewer's position.
    material : read-only material
        ``ka``, ``kd``, ``ks``, ``emission`` (RGB triples) and ``shininess``.
    lights : list of read-only lights
        ``AmbientLight``, ``PointLight``, ``DirectionalLight``, ``SpotLight``.

    Returns
    -------
    numpy.ndarray or sequence of 3 floats
        ``ke + ka∘Ia + Σ f [kd∘Id max(0, n·l) + ks∘Is S]``, with
        ``S = max(0, r·v)^α`` where ``n·l > 0`` and ``r·v > 0``, else 0
        (also at α = 0 and for an eye on the point).
    """
    raise NotImplementedError("write the Phong model here")
