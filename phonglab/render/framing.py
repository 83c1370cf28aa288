"""Framing the arrows: the view angle that holds their tips, and where their letters go.

VTK-free: plain geometry on points, directions and pixel sizes, so it can be
tested without a render window. :class:`~phonglab.render.SceneView` feeds it
the camera it shows and the arrows at the probe.

The view angle spans the *shorter* side of the window (the height of a wide
window, the width of a tall one). Directions point *away from the surface
point*: an arrow's tip is ``probe + direction * arrow_length``.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from phonglab.render.annotate import font
from phonglab.render.camera import stands_at

#: the widest view angle (degrees) the framing of the arrows may choose
MAX_VIEW_ANGLE = 120.0
#: free border around the arrows and their letters, as a fraction of the window's shorter side
FRAME_PAD = 0.02
#: Arrows closer than this angle (degrees) have their letters stacked.
LABEL_STACK_DEGREES = 10.0


def _ball_reach(c: float, depth: float, radius: float) -> float | None:
    """Largest |tan| of a ball's span along one screen axis; None when the ball is not in front of the eye."""
    distance = math.hypot(c, depth)
    if depth <= 0 or distance <= radius:
        return None
    centre, half = math.atan2(c, depth), math.asin(radius / distance)
    if abs(centre) + half >= math.pi / 2:
        return None
    return max(abs(math.tan(centre - half)), abs(math.tan(centre + half)))


def view_angle_for_tips(eye, focal_point, view_up, tips, *, tip_radius: float, width: int, height: int,
                        reach: float) -> float:
    """The smallest view angle (degrees) that shows every tip with its letter.

    Parameters
    ----------
    eye, focal_point, view_up : 3 floats
        The camera.
    tips : sequence of 3 floats
        The arrows' tips in world coordinates.
    tip_radius : float
        Each tip is taken as a ball of this radius (the arrow head's).
    width, height : int
        The window in pixels.
    reach : float
        Pixels a letter reaches past its tip (0 without letters); a border of
        :data:`FRAME_PAD` of the shorter side is kept on top of it.

    Returns
    -------
    float
        At most :data:`MAX_VIEW_ANGLE`, which is also the answer when a tip
        is not in front of the eye.

    Notes
    -----
    Seen from the eye, a ball at screen-axis offset ``c`` and depth ``z``
    with radius ``ρ`` spans the angles
    :math:`\\arctan(c / z) \\pm \\arcsin(\\rho / \\sqrt{c^2 + z^2})` along that
    axis; the window must hold those spans plus, in pixels, the letters drawn
    beyond the tips and the free border.
    """
    eye = np.asarray(eye, dtype=float)
    forward = np.asarray(focal_point, dtype=float) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, view_up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_x = tan_y = 0.0
    for tip in tips:
        offset = np.asarray(tip, dtype=float) - eye
        depth = float(offset @ forward)
        rx, ry = _ball_reach(float(offset @ right), depth, tip_radius), _ball_reach(float(offset @ up), depth, tip_radius)
        if rx is None or ry is None:
            return MAX_VIEW_ANGLE
        tan_x, tan_y = max(tan_x, rx), max(tan_y, ry)
    # the letters beyond the tips and a free border, as fractions of the half window
    border = reach + FRAME_PAD * min(width, height)
    keep_x = max(0.5, 1.0 - border / (width / 2))
    keep_y = max(0.5, 1.0 - border / (height / 2))
    aspect = width / height
    if width < height:
        # the view angle spans the width
        half_tan = max(tan_x / keep_x, tan_y * aspect / keep_y)
    else:
        half_tan = max(tan_y / keep_y, tan_x / (aspect * keep_x))
    return min(MAX_VIEW_ANGLE, math.degrees(2.0 * math.atan(half_tan)))


#: a light marker is framed whole if that widens the scene's view angle by at most this factor;
#: one farther out (a lamp beside the eye) is left out of the picture rather than shrink the scene
MARKER_WIDENING = 1.5


def fitted_view_angle(scene_camera, position, focal_point, view_up, tips, *, tip_radius: float, width: int,
                      height: int, reach: float) -> float | None:
    """The view angle (degrees) for a camera: the scene's, widened if the tips would leave the window.

    Returns None while the camera (``position``, ``focal_point``) is not the
    scene's (:func:`~phonglab.render.camera.stands_at`): a camera turned by
    someone else, a browser's say, keeps the view angle it was given.
    Without tips, the scene's view angle. Arguments as for
    :func:`view_angle_for_tips`.
    """
    if not stands_at(position, focal_point, scene_camera):
        return None
    angle = float(scene_camera.view_angle)
    if tips:
        angle = max(angle, view_angle_for_tips(position, focal_point, view_up, tips, tip_radius=tip_radius,
                                               width=width, height=height, reach=reach))
    return angle


# ---------------------------------------------------------------------------
# letters at the arrow tips


def letter_font_size(height: int) -> int:
    """Font size (pixels) of the VTK text letters at the arrow tips in a window this tall."""
    return max(12, height // 24)


@functools.lru_cache(maxsize=64)
def _letter_metrics(height: int, letters: str) -> tuple[int, float, float]:
    size = max(12, round(height / 24))
    fnt = font(size, bold=True)
    # draw_labels: half-extent of the letter from its anchor, and the centre's distance from the tip
    extent = max(max(fnt.getbbox(letter, anchor="mm")[2:]) for letter in letters)
    return size, 0.45 * size + 0.6 * extent, float(extent)


def label_metrics(height: int, letters) -> tuple[int, float, float]:
    """For letters drawn on an image ``height`` pixels tall: (font size, centre beyond the tip, half extent).

    As :func:`~phonglab.render.annotate.draw_labels` draws them; ``letters``
    are the letters shown (their widest one counts).
    """
    return _letter_metrics(int(height), "".join(sorted(letters)))


def label_reach(height: int, letters) -> float:
    """How far (pixels) a letter drawn by :func:`~phonglab.render.annotate.draw_labels` reaches past its tip."""
    size, offset, half = label_metrics(height, letters)
    return offset + half + max(1, size // 10) + 2.0


def label_offsets(letters, directions) -> dict[str, int]:
    """How many lines down to shift each letter so nearly coinciding arrows stay readable.

    Each letter moves one line below every earlier letter whose arrow lies
    within :data:`LABEL_STACK_DEGREES` of its own (e.g. N, L, R, V and H all
    coincide when the light and the eye are straight above the point).
    """
    cos_limit = np.cos(np.radians(LABEL_STACK_DEGREES))
    offsets: dict[str, int] = {}
    for i, letter in enumerate(letters):
        d = np.asarray(directions[letter], float)
        taken = {offsets[other] for other in letters[:i]
                 if float(np.dot(d, np.asarray(directions[other], float))) >= cos_limit}
        offsets[letter] = next(k for k in range(len(letters) + 1) if k not in taken)
    return offsets
