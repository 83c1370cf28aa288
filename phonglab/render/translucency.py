"""A mesh of opacity < 1: its near side over its far side over what lies behind, in linear light.

Opacity is not lighting: the core shades the surface as it does at
opacity 1, and the finished colours are blended afterwards with
:func:`phonglab.core.blend.over`. Blending mixes amounts of light, so it is
done on linear light (exposed and clipped, before the display encoding)
and the result is encoded once, at the end, with the scene's ``display``
curve. The same steps serve the three interpolation modes; only where the
two layers come from differs:

* **flat** and **gouraud**: VTK draws the mesh alone, opaque, with the
  core's colours (per face or interpolated per vertex, as at opacity 1),
  twice: once without the faces turned away from the camera (the **near
  layer**) and once without the faces turned towards it (the **far
  layer**, the inside of the far side). Each render's colour and depth
  buffers are read; the 8-bit colours are decoded to linear light.
* **pixel**: two G-buffers, one per layer (:meth:`GBufferRenderer.render`
  with ``cull``), each shaded per pixel by the core
  (:func:`~phonglab.render.shading.pixel_linear`). The far layer's normals
  point away from the eye; the scene's own rule for such faces applies
  (one-sided: only light from behind reaches them; ``two_sided``: the
  normal is flipped towards the eye), exactly as VTK's colours per vertex
  or face have it in the other modes.

Then, per pixel, from far to near: what lies behind (the background and
the glyphs, rendered without the mesh, decoded to linear), the far layer
over it, the near layer over that; a layer counts only where it is nearer
than the glyph drawn at that pixel (glyphs are opaque). For a closed convex
mesh (sphere, cube) this is exactly
:func:`phonglab.core.blend.composite_closed`,
``C = a C_front + (1 - a)(a C_back + (1 - a) C_behind)``.

Assumption: **depth complexity ≤ 2**. A ray through a closed convex mesh
meets it twice, and the lesson meshes are drawn right. A non-convex mesh
(the torus) can be met four times; only its nearest front face and nearest
back face are blended, and what lies beyond that back face (the other side
of the ring) is not seen through it. An open surface (the plane) is one
layer: near when its front faces the eye, far otherwise.

The 8-bit round trip of the VTK modes costs at most about one level of
255 against the per-pixel path (measured in ``tests/test_render_opacity.py``).
At opacity 1 none of this runs: the pictures are those of an opaque mesh.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import vtk

from phonglab.core.blend import over
from phonglab.core.display import display_bytes, srgb_decode
from phonglab.render._vtk import eye_distance, hidden, read_depth, read_rgb
from phonglab.render.shading import pixel_linear

#: a layer is in front of a glyph where it is nearer by more than this fraction of the distance
DEPTH_SLACK = 1e-4
#: the layers, far first, by the faces each leaves out
CULL_FAR, CULL_NEAR = "front", "back"


class Layer(NamedTuple):
    """One side of the mesh as the camera sees it."""

    #: linear light shown at each pixel, shape (height, width, 3), float64 (meaningless where ``mask`` is False)
    linear: np.ndarray
    #: True where this layer covers the pixel
    mask: np.ndarray
    #: distance from the eye along the view axis, shape (height, width)
    distance: np.ndarray


def translucent(scene) -> bool:
    """True when the scene's material lets what is behind it show (opacity < 1)."""
    return float(scene.material.opacity) < 1.0


#: the linear light each 8-bit value encodes, per display curve (a table: decoding is per pixel and channel)
_DECODED = {"srgb": srgb_decode(np.arange(256) / 255.0), "linear": np.arange(256) / 255.0}


def decode(rgb8: np.ndarray, encoding: str) -> np.ndarray:
    """8-bit display values back to the linear light they encode (``"srgb"`` or ``"linear"``), float64."""
    return _DECODED[encoding][np.asarray(rgb8, dtype=np.uint8)]


def _decoded_where(rgb8: np.ndarray, mask: np.ndarray, encoding: str) -> np.ndarray:
    """:func:`decode` of the masked pixels; zero elsewhere."""
    linear = np.zeros(rgb8.shape, dtype=np.float64)
    linear[mask] = decode(rgb8[mask], encoding)
    return linear


def _props(renderer: vtk.vtkRenderer) -> list:
    collection = renderer.GetViewProps()
    collection.InitTraversal()
    return [collection.GetNextProp() for _ in range(collection.GetNumberOfItems())]


def vtk_layers(window: vtk.vtkRenderWindow, renderer: vtk.vtkRenderer, actor: vtk.vtkActor,
               encoding: str) -> list[Layer]:
    """The far and near layers of the mesh ``actor`` as VTK draws them (flat, gouraud), far first.

    The mesh is drawn alone and opaque, once per layer; every other prop's
    visibility and the actor's own opacity, culling and visibility are put
    back afterwards.
    """
    camera = renderer.GetActiveCamera()
    prop = actor.GetProperty()
    saved = (actor.GetVisibility(), prop.GetOpacity(), prop.GetBackfaceCulling(), prop.GetFrontfaceCulling())
    layers = []
    with hidden([p for p in _props(renderer) if p is not actor]):
        try:
            actor.VisibilityOn()
            prop.SetOpacity(1.0)
            for cull in (CULL_FAR, CULL_NEAR):
                prop.SetBackfaceCulling(cull == "back")
                prop.SetFrontfaceCulling(cull == "front")
                renderer.ResetCameraClippingRange()
                window.Render()
                depth = read_depth(window)
                # distances now: the next render fits its own clipping range
                mask = depth < 1.0
                distance = np.full(depth.shape, np.inf)
                distance[mask] = eye_distance(camera, depth[mask])
                layers.append(Layer(_decoded_where(read_rgb(window), mask, encoding), mask, distance))
        finally:
            actor.SetVisibility(saved[0])
            prop.SetOpacity(saved[1])
            prop.SetBackfaceCulling(saved[2])
            prop.SetFrontfaceCulling(saved[3])
    return layers


def pixel_layer(scene, gbuffer, camera: vtk.vtkCamera, term: str = "color", mistake: str | None = None) -> Layer:
    """One layer shaded per pixel by the core, from its G-buffer (pixel mode)."""
    eye = np.asarray(camera.GetPosition())
    axis = np.asarray(camera.GetDirectionOfProjection())
    distance = np.full(gbuffer.mask.shape, np.inf)
    distance[gbuffer.mask] = (gbuffer.positions[gbuffer.mask] - eye) @ axis
    return Layer(pixel_linear(scene, gbuffer, term, mistake), gbuffer.mask, distance)


def composite(behind: np.ndarray, behind_distance: np.ndarray, layers, alpha: float, encoding: str) -> np.ndarray:
    """The layers blended, far first, over the picture of what lies behind them.

    Parameters
    ----------
    behind : ndarray, shape (height, width, 3), uint8
        The window rendered without the mesh (background and glyphs), as displayed.
    behind_distance : ndarray, shape (height, width)
        Eye distance of the glyph at each pixel (``inf`` where none).
    layers : sequence of Layer
        Far first.
    alpha : float in [0, 1]
        The material's opacity.
    encoding : {"srgb", "linear"}
        The scene's display curve: ``behind`` is decoded with it and the
        result encoded with it.

    Returns
    -------
    ndarray, shape (height, width, 3), uint8
        ``behind`` where no layer counts (unchanged, not round-tripped).
    """
    out = np.array(behind, dtype=np.uint8, copy=True)
    covered = np.zeros(behind.shape[:2], dtype=bool)
    for layer in layers:
        covered |= layer.mask
    # only the pixels some layer covers, as flat lists
    linear = decode(out[covered], encoding)
    limit = behind_distance[covered] * (1 + DEPTH_SLACK)
    touched = np.zeros(len(linear), dtype=bool)
    for layer in layers:
        # a layer counts where it lies in front of the glyph there (or no glyph was drawn)
        use = layer.mask[covered] & (layer.distance[covered] <= limit)
        linear[use] = over(layer.linear[covered][use], alpha, linear[use])
        touched |= use
    # encode once, after blending
    pixels = out[covered]
    pixels[touched] = display_bytes(linear[touched], encoding=encoding)
    out[covered] = pixels
    return out

