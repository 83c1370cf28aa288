"""What a :class:`~phonglab.render.view.SceneView` gives out: picks, projections, the letters' places and images.

A mixin of :class:`~phonglab.render.view.SceneView`, kept apart from the
window's upkeep (:mod:`phonglab.render.view`): picking the mesh under a
pointer, projecting world points onto an image, the arrows' tips and which
of them the mesh hides, the legend, and the images themselves (the G-buffer,
the mesh shaded per pixel by the core, letters and the legend drawn on a
render, the screenshot). It reads the view's renderer, window, mesh, arrows
and options; it changes none of them.
"""

from __future__ import annotations

import numpy as np

from phonglab.render import picking, pixel_job, shading
from phonglab.render.annotate import draw_labels, draw_legend
from phonglab.render.saving import save_png


class ViewPictures:
    """Picks, projections, letters and images of a :class:`~phonglab.render.view.SceneView`."""

    def vector_marks(self) -> dict[str, tuple[tuple[float, float], tuple[float, float, float, float]]]:
        """Where each shown arrow's tip and letter land on an image of the current window.

        Returns
        -------
        dict
            letter -> ``((x, y), (left, top, right, bottom))``: the projected
            tip and the box of its letter where
            :func:`~phonglab.render.annotate.draw_labels` draws it (moved
            aside from another letter, or set beside the letters of arrows
            whose tips meet its own), in image pixels with row 0 at the top.
        """
        self._fit_view_angle()
        self.renderer.ResetCameraClippingRange()
        height = self.size[1]
        return self._arrows.marks(lambda world: self.to_image(world, height), tuple(self.size))

    def pick(self, display_x: float, display_y: float):
        """The mesh point under a display position, or None.

        Parameters
        ----------
        display_x, display_y : float
            VTK display coordinates: pixels from the window's *bottom-left* corner.

        Returns
        -------
        ndarray of shape (3,) or None
            The picked world point on the mesh (glyphs are not pickable).
        """
        return picking.pick(self.renderer, self._mesh_actor, display_x, display_y)

    def to_image(self, world, height: int | None = None) -> tuple[float, float]:
        """Where a world point lands on an image of the window as it is now rendered.

        Parameters
        ----------
        world : 3 floats
        height : int, optional
            The image's height in pixels; the window's by default.

        Returns
        -------
        (x, y)
            Image pixels, row 0 at the top.
        """
        return picking.to_image(self.renderer, world, self.size[1] if height is None else int(height))

    def arrow_tips(self) -> list[tuple[str, tuple[float, float, float], tuple[float, float, float]]]:
        """Every arrow shown as ``(letter, base, tip)`` in world coordinates, for letters a front end draws.

        The base is the probe point; the tip is ``base + direction * arrow_length``.
        """
        base = tuple(float(c) for c in self._arrows.point)
        return [(letter, base, tuple(float(c) for c in self._arrows.tip(letter))) for letter in self._arrows.shown()]

    def hidden_letters(self) -> set[str]:
        """The letters whose arrow tip the mesh hides from the window's camera (say, a probe turned to the far side).

        Kept until the camera, the arrows or the mesh's points move (a slider that changes only colours pays nothing).
        """
        origin = tuple(self.renderer.GetActiveCamera().GetPosition())
        tips = tuple((letter, tuple(self._arrows.tip(letter))) for letter in self._arrows.shown())
        key = (id(self.mesh), self.mesh.GetPoints().GetMTime(), self.mesh.GetPolys().GetMTime(), origin, tips)
        if getattr(self, "_hidden", (None,))[0] != key:
            self._hidden = (key, frozenset(picking.hidden_tips(self.mesh, origin, dict(tips))))
        return set(self._hidden[1])

    def legend(self) -> list[tuple[str, str, str]]:
        """The vectors shown, for a legend drawn elsewhere (HTML): (letter, meaning, "#rrggbb")."""
        return self._arrows.legend()

    def gbuffer(self, *, cull: str | None = None):
        """The mesh's :class:`~phonglab.render.gbuffer.GBuffer` for the current VTK camera and window size.

        Rendered again only when the mesh, the camera or the size has changed.
        ``cull="back"`` or ``"front"`` leaves out one side's faces (the
        layers of a translucent mesh, :mod:`~phonglab.render.translucency`).
        """
        return self._gbuffers.get(self.mesh, self.renderer.GetActiveCamera(), self.render_window.GetSize(),
                                  cull=cull)

    def pixel_image(self, term: str | None = None) -> np.ndarray:
        """The mesh shaded per pixel by the core, on the background (no glyphs).

        With a mistake set (:meth:`set_mistake`) the pixels are shaded with
        it; a mistake with ``needs_raw_normals`` gets the interpolated normals
        as they came, not renormalised, so its bug shows here.

        Parameters
        ----------
        term : str, optional
            ``"color"``, ``"ambient"``, ``"diffuse"`` or ``"specular"``; the view's term by default.

        Returns
        -------
        ndarray, shape (height, width, 3), uint8
            For the current VTK camera and window size, top row first.
        """
        term = term or self.term
        return shading.pixel_colors(self.scene, self.gbuffer(), self.background, (term,), self.mistake)[term]

    def annotate(self, image: np.ndarray, *, legend: bool = True) -> np.ndarray:
        """Draw the letters at the arrow tips (and the legend) on a rendered image.

        Parameters
        ----------
        image : ndarray, shape (height, width, 3), uint8
            A render of this view at its current camera and size.
        legend : bool
            Also draw the legend box.
        """
        found = self.image_labels(image.shape[0])
        if found is None:
            return image
        labels, entries = found
        image = draw_labels(image, labels)
        return draw_legend(image, entries) if legend else image

    def image_labels(self, height: int):
        """What :meth:`annotate` draws on an image ``height`` pixels tall: ``(labels, entries)``, None without labels."""
        return self._arrows.image_labels(lambda world: self.to_image(world, height)) if self.show_labels else None

    def screenshot(self, path=None, *, annotate: bool = True) -> np.ndarray:
        """Render and return the image, optionally saving it as PNG.

        In pixel mode the per-pixel shaded mesh is composited with the glyphs
        by depth. A material with opacity < 1 is blended over what lies
        behind it, in every mode (:mod:`~phonglab.render.translucency`).
        Labels and the legend are drawn on the image (not by VTK).

        Parameters
        ----------
        path : str or path-like, optional
            Where to write a PNG (written to a temporary file, then renamed).
        annotate : bool
            Draw the vector letters and the legend.

        Returns
        -------
        ndarray, shape (height, width, 3), uint8
        """
        # the VTK part here, then the NumPy part (a server runs that one in a thread: pixel_job)
        image = pixel_job.prepare(self, annotate=annotate).finish()
        if path is not None:
            save_png(image, path)
        return image
