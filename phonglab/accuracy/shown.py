"""The picture the page shows for a scene, as 8-bit levels, for a lesson's picture claims.

A sentence about what the student *sees* ("the dark side never catches up",
"a red light gives black") is a sentence about the screen, not about the
model's linear numbers: between the two lie the opacity blend, the exposure,
the clip to [0, 1] and the display encoding (sRGB by default), and in the
flat and Gouraud modes VTK's blend of the encoded vertex colours. So a
picture claim is measured on the picture itself, made by the same code that
makes the page's per-pixel picture and its exports:
:meth:`SceneView.screenshot <phonglab.render.view.SceneView.screenshot>`,
for the scene's camera and interpolation mode.

The picture is :data:`SHOWN_SIZE`, the page's 960 × 720 at a third, with
neither arrows nor light markers (they would cover parts of the surface).
Only the pixels the surface covers are measured (the G-buffer's mask).
Pictures are kept per (scene, term) for the run; one offscreen view is
reused for every scene, updated as the page updates its own.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

__all__ = ["SHOWN_SIZE", "Shown", "shown", "levels"]

#: width and height, in pixels, of the picture the picture claims measure (the page's 960 × 720 at a third)
SHOWN_SIZE = (320, 240)


@dataclass(frozen=True)
class Shown:
    """One displayed picture.

    Attributes
    ----------
    image : ndarray, shape (height, width, 3), uint8
        The picture as the page shows it (background included).
    mask : ndarray, shape (height, width), bool
        The pixels the surface covers.
    probe : (row, column) or None
        The pixel the probe point (where the arrows start) is seen through;
        None when the surface hides it or it falls outside the picture.
    """

    image: np.ndarray
    mask: np.ndarray
    probe: tuple[int, int] | None


_view = []  # the one offscreen SceneView, made on first use


def _the_view(scene, term: str):
    from phonglab.render.view import SceneView

    if not _view:
        _view.append(SceneView(scene, size=SHOWN_SIZE, vectors="", labels=False, vtk_text=False, markers=False,
                               term=term))
    view = _view[0]
    view.update(scene)
    view.set_term(term)
    return view


@functools.lru_cache(maxsize=128)
def shown(scene, term: str = "color") -> Shown:
    """The picture the page shows for ``scene`` (one term, or ``"color"``, their sum).

    Parameters
    ----------
    scene : phonglab.scene.Scene
    term : str
        ``"color"``, ``"ambient"``, ``"diffuse"``, ``"specular"`` (the page's term buttons).
    """
    view = _the_view(scene, term)
    image = view.screenshot(annotate=False)
    mask = view.gbuffer().mask
    point, _ = view.probe
    x, y = view.to_image(point, image.shape[0])
    row, col = int(np.rint(y)), int(np.rint(x))
    inside = 0 <= row < mask.shape[0] and 0 <= col < mask.shape[1]
    probe = (row, col) if inside and mask[row, col] and _probe_visible(view, point) else None
    return Shown(image=image, mask=mask, probe=probe)


def _probe_visible(view, point) -> bool:
    """Whether the first surface on the ray from the eye through the probe is the probe itself."""
    eye = np.asarray(view.scene.camera.eye, dtype=np.float64)
    hit = view.ray_hit(eye, np.asarray(point, dtype=np.float64))
    return hit is None or float(np.linalg.norm(hit[0] - point)) < 1e-3 * view.arrow_length


def levels(picture: Shown, channel: str = "max") -> np.ndarray:
    """The 8-bit levels (0 to 255) of the covered pixels, one channel or the largest of the three, as floats."""
    pixels = picture.image[picture.mask].astype(np.float64)
    return pixels.max(axis=-1) if channel == "max" else pixels[:, "rgb".index(channel)]

