"""A view's screenshot in two parts: what needs VTK, then what needs only NumPy.

:meth:`SceneView.screenshot <phonglab.render.view.SceneView.screenshot>` is
:func:`prepare` followed by :meth:`PixelJob.finish`. The split lets a server
run the slow half elsewhere:

* :func:`prepare` — **the VTK part**, in the thread that owns the view
  (VTK's OpenGL contexts belong to one thread): render the window without
  the mesh (pixel mode, translucency) or with it, read its colour and depth
  buffers, render the G-buffers (:meth:`SceneView.gbuffer`) or, for a
  translucent mesh shaded by VTK, its two layers
  (:func:`~phonglab.render.translucency.vtk_layers`), note the camera's
  numbers and where the letters land on the image.
* :meth:`PixelJob.finish` — **the NumPy part**, in any thread: the core
  shades every covered pixel of the G-buffer
  (:func:`~phonglab.render.shading.pixel_colors`,
  :func:`~phonglab.render.translucency.pixel_layer`), the mesh is
  composited with the glyphs by depth (:func:`~phonglab.render.pixels.composite`)
  or its layers blended (:func:`~phonglab.render.translucency.composite`),
  and the letters and legend are drawn (Pillow).

A job holds only arrays, frozen scene data and plain numbers, none of them
shared with the view: the view may change (or be closed) while a job is
finished elsewhere, and the job still makes the picture of the moment it
was prepared. Both parts together are the screenshot, byte for byte.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from phonglab.render import pixels, shading, translucency
from phonglab.render._vtk import eye_distance, hidden, read_depth, read_rgb
from phonglab.render.annotate import draw_labels, draw_legend


class CameraNumbers(NamedTuple):
    """What the NumPy part needs of a ``vtkCamera``, read once in the VTK thread.

    It answers the three getters the compositing functions call
    (:func:`~phonglab.render._vtk.eye_distance`,
    :func:`~phonglab.render.pixels.composite`,
    :func:`~phonglab.render.translucency.pixel_layer`) with the numbers the
    camera had when the window was rendered.
    """

    position: tuple[float, float, float]
    direction_of_projection: tuple[float, float, float]
    clipping_range: tuple[float, float]

    @classmethod
    def of(cls, camera) -> "CameraNumbers":
        """The numbers of a ``vtkCamera`` as they are now."""
        return cls(tuple(camera.GetPosition()), tuple(camera.GetDirectionOfProjection()),
                   tuple(camera.GetClippingRange()))

    def GetPosition(self):  # noqa: N802 - the vtkCamera getter it stands for
        return self.position

    def GetDirectionOfProjection(self):  # noqa: N802
        return self.direction_of_projection

    def GetClippingRange(self):  # noqa: N802
        return self.clipping_range


@dataclass(frozen=True)
class PixelJob:
    """A screenshot whose VTK part is done: :meth:`finish` makes the image, in any thread.

    Attributes
    ----------
    image : ndarray, shape (height, width, 3), uint8
        The window as VTK rendered it (without the mesh in pixel mode or for
        a translucent mesh).
    kind : str
        ``"window"`` (the render is the picture), ``"pixel"`` (the mesh
        shaded per pixel, composited by depth) or ``"translucent"``.
    scene, term, mistake, background
        What the core shades with (the view's, when prepared).
    depth : ndarray or None
        The render's depth buffer, top row first.
    camera : CameraNumbers or None
    gbuffers : tuple of GBuffer
        Pixel mode: the mesh's one G-buffer; a translucent mesh in pixel
        mode: its far and near layers' G-buffers.
    layers : tuple of translucency.Layer
        A translucent mesh shaded by VTK (flat, gouraud): its layers, far first.
    labels : (labels, entries) or None
        The letters and legend entries to draw (None: no text).
    """

    image: np.ndarray
    kind: str = "window"
    scene: Any = None
    term: str = "color"
    mistake: str | None = None
    background: tuple = (0.0, 0.0, 0.0)
    depth: np.ndarray | None = None
    camera: CameraNumbers | None = None
    gbuffers: tuple = ()
    layers: tuple = ()
    labels: tuple | None = None

    def finish(self) -> np.ndarray:
        """The picture: the NumPy part of the screenshot (no VTK; safe in a worker thread).

        Returns
        -------
        ndarray, shape (height, width, 3), uint8
            What :meth:`SceneView.screenshot` returns for the view as it was prepared.
        """
        image = self.image
        if self.kind == "translucent":
            # the mesh's two layers blended over the glyphs and background
            scene = self.scene
            encoding = getattr(scene, "display", "srgb")
            behind_distance = eye_distance(self.camera, self.depth)
            layers = self.layers or tuple(
                translucency.pixel_layer(scene, gbuffer, self.camera, self.term, self.mistake)
                for gbuffer in self.gbuffers)
            image = translucency.composite(image, behind_distance, layers, float(scene.material.opacity), encoding)
        elif self.kind == "pixel":
            # the core's shading of every covered pixel, in front of or behind the glyphs by depth
            gbuffer = self.gbuffers[0]
            shaded = shading.pixel_colors(self.scene, gbuffer, self.background, (self.term,), self.mistake)[self.term]
            image = pixels.composite(image, self.depth, gbuffer, shaded, self.camera)
        if self.labels is not None:
            labels, entries = self.labels
            image = draw_legend(draw_labels(image, labels), entries)
        return image


def prepare(view, *, annotate: bool = True) -> PixelJob:
    """The VTK part of ``view.screenshot(annotate=annotate)``: run it in the view's thread.

    Parameters
    ----------
    view : phonglab.render.view.SceneView
    annotate : bool
        Draw the vector letters and the legend (if the view shows labels).

    Returns
    -------
    PixelJob
        Its :meth:`~PixelJob.finish` makes the screenshot, in any thread.
    """
    scene = view.scene
    pixel_mode = scene.interpolation == "pixel"
    translucent = translucency.translucent(scene)
    kind = "translucent" if translucent else "pixel" if pixel_mode else "window"
    fields = {}
    # VTK's text is not in images (they get their own letters); in pixel mode the core draws the mesh
    with hidden(view.glyph_actors.text_actors() + ([view.mesh_actor] if kind != "window" else [])):
        view.render()
        image = read_rgb(view.render_window)
        if kind != "window":
            depth = read_depth(view.render_window)
            # the camera as rendered: a translucent mesh's own renders below refit its clipping range
            camera = CameraNumbers.of(view.renderer.GetActiveCamera())
            fields.update(depth=depth, camera=camera, scene=scene, term=view.term, mistake=view.mistake,
                          background=view.background)
            if translucent and pixel_mode:
                fields["gbuffers"] = tuple(view.gbuffer(cull=cull)
                                           for cull in (translucency.CULL_FAR, translucency.CULL_NEAR))
            elif translucent:
                fields["layers"] = tuple(translucency.vtk_layers(view.render_window, view.renderer, view.mesh_actor,
                                                                 getattr(scene, "display", "srgb")))
            else:
                fields["gbuffers"] = (view.gbuffer(),)
    if annotate:
        fields["labels"] = view.image_labels(image.shape[0])
    return PixelJob(image=image, kind=kind, **fields)
