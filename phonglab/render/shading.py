"""Colours for the three interpolation modes, computed by the core.

* **flat** — one colour per triangle: the core shades the triangle's
  centroid with its geometric normal; VTK paints the whole face with it.
* **gouraud** — the core shades every vertex with its normal; VTK
  interpolates the *colours* across each triangle.
* **pixel** — VTK interpolates *positions and normals* per pixel (the
  G-buffer of :mod:`phonglab.render.gbuffer`); the core shades every pixel.

Colours leave the core unclamped; they are clipped to [0, 1] and scaled to
8-bit RGB only here, at the last step before VTK.
"""

from __future__ import annotations

import numpy as np

from phonglab.render.gbuffer import GBuffer
from phonglab.render.mesh import face_centroids_normals

#: what a view can show: one term of the sum, or the whole colour
TERMS = ("color", "ambient", "diffuse", "specular")


def shade(scene, points, normals):
    """The core's shading of ``points`` with ``normals`` under ``scene``.

    A thin wrapper over :func:`phonglab.scene.shade` (which passes the
    scene's material, lights, eye, model, two-sidedness and plan to the core).
    """
    from phonglab import scene as scene_module

    return scene_module.shade(scene, points, normals)


def term_of(shading, term: str) -> np.ndarray:
    """One term of a core ``Shading``: ``"color"`` (the sum), ``"ambient"``, ``"diffuse"``, ``"specular"``."""
    if term not in TERMS:
        raise ValueError(f"term must be one of {', '.join(TERMS)}, got {term!r}")
    return getattr(shading, term)


def to_rgb8(values) -> np.ndarray:
    """Clip colours to [0, 1] and scale them to uint8 RGB (rounded)."""
    values = np.asarray(values)
    if values.dtype not in (np.float32, np.float64):
        values = values.astype(np.float64)
    scaled = np.clip(values, 0.0, 1.0) * 255.0
    # NaN would survive the clip; it becomes black
    scaled = np.where(np.isnan(scaled), 0.0, scaled) if np.isnan(scaled).any() else scaled
    return np.rint(scaled).astype(np.uint8)


def vertex_colors(scene, mesh, terms=("color",)) -> dict[str, np.ndarray]:
    """Gouraud: uint8 RGB per mesh point, for each requested term."""
    shading = shade(scene, np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"]))
    return {t: to_rgb8(term_of(shading, t)) for t in terms}


def face_colors(scene, mesh, terms=("color",)) -> dict[str, np.ndarray]:
    """Flat: uint8 RGB per triangle, shaded at its centroid with its face normal."""
    centroids, normals = face_centroids_normals(mesh)
    shading = shade(scene, centroids, normals)
    return {t: to_rgb8(term_of(shading, t)) for t in terms}


def pixel_colors(scene, gbuffer: GBuffer, background, terms=("color",)) -> dict[str, np.ndarray]:
    """Per pixel: a (height, width, 3) uint8 image per term, background where uncovered.

    Parameters
    ----------
    scene : phonglab.scene.Scene
    gbuffer : GBuffer
    background : sequence of 3 floats in [0, 1]
        Colour of the pixels the mesh does not cover.
    terms : sequence of str
    """
    mask = gbuffer.mask
    shading = shade(scene, gbuffer.positions[mask], gbuffer.normals[mask])
    back = to_rgb8(background)
    out = {}
    for t in terms:
        image = np.empty(mask.shape + (3,), dtype=np.uint8)
        image[...] = back
        image[mask] = to_rgb8(term_of(shading, t))
        out[t] = image
    return out
