"""The arrows at the probe as a view draws them: which vectors, where their tips and letters land.

The vectors themselves come from the core (:func:`phonglab.render.probe.probe_vectors`);
this keeps them with the probe point and the arrows' length, and turns them
into the letters an image carries. Directions point *away from the surface
point*: an arrow's tip is ``point + direction * length``.
"""

from __future__ import annotations

import numpy as np

from phonglab.render import annotate, glyphs
from phonglab.render.probe import locate_probe, probe_vectors


class ProbeArrows:
    """N, L, R, V, H at a view's probe.

    Parameters
    ----------
    letters : str
        The letters asked for (checked, as :func:`phonglab.render.glyphs.parse_vectors` returns them).

    Attributes
    ----------
    letters : str
        The letters asked for.
    point, normal : ndarray of shape (3,)
        The probe on the mesh and the unit normal there.
    vectors : ProbeVectors or None
        The core's vectors at the probe; None without a directed light.
    directions : dict
        letter -> unit direction of each vector that exists (N and V only without a directed light).
    length : float
        The arrows' length in world units.
    """

    def __init__(self, letters: str):
        self.letters = letters
        self.point = self.normal = None
        self.vectors = None
        self.directions: dict[str, np.ndarray] = {}
        self.length = 0.0

    def locate(self, mesh, scene) -> None:
        """Put the probe where the scene says on ``mesh`` (see :func:`phonglab.render.probe.locate_probe`)."""
        self.point, self.normal = locate_probe(mesh, scene)

    def compute(self, scene, light_index: int | None) -> None:
        """The vectors at the probe for ``scene`` and its light ``light_index``, from the core."""
        self.vectors, self.directions = probe_vectors(scene, self.point, self.normal, light_index)

    def shown(self) -> list[str]:
        """The letters drawn: asked for, and with a vector."""
        return [letter for letter in self.letters if letter in self.directions]

    def tip(self, letter: str) -> np.ndarray:
        """The tip of an arrow in world coordinates."""
        return self.point + self.directions[letter] * self.length

    def image_labels(self, project):
        """The letters and legend entries for :func:`~phonglab.render.annotate.draw_labels` and ``draw_legend``.

        ``project(world) -> (x, y)`` gives image pixels. Returns ``(labels,
        entries)``: ``(letter, tip, direction on the image, colour)`` and
        ``(letter, meaning, colour)`` per letter shown.
        """
        labels, entries = [], []
        for letter in self.shown():
            x, y = project(self.tip(letter))
            bx, by = project(self.point)
            colour, meaning = glyphs.VECTORS[letter]
            labels.append((letter, (x, y), (x - bx, y - by), colour))
            entries.append((letter, meaning, colour))
        return labels, entries

    def marks(self, project, size) -> dict[str, tuple[tuple[float, float], tuple[float, float, float, float]]]:
        """letter -> ``((x, y), (left, top, right, bottom))``: each shown tip and its letter's box on an image.

        ``project(world) -> (x, y)`` gives pixels of an image of ``size``
        (width, height). The boxes are where
        :func:`~phonglab.render.annotate.draw_labels` draws the letters
        (:func:`~phonglab.render.annotate.label_layout`): a letter's own
        glyph, in a label shared with the arrows whose tips meet its own or alone.
        """
        labels, _ = self.image_labels(project)
        tips = {letter: (float(xy[0]), float(xy[1])) for letter, xy, _, _ in labels}
        return {letter: (tips[letter], tuple(float(c) for c in box))
                for label in annotate.label_layout(labels, size) for letter, box in label.boxes.items()}

    def legend(self) -> list[tuple[str, str, str]]:
        """(letter, meaning, ``"#rrggbb"``) per letter shown."""
        return [(letter, glyphs.VECTORS[letter][1], "#%02x%02x%02x" % glyphs.VECTORS[letter][0])
                for letter in self.shown()]
