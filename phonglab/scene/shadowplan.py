"""Which shadows a scene must trace: the light–object pairs where a shadow can fall on a lit surface.

With ``shadows = true`` every shaded point casts a ray towards every point,
spot and directional light; the light is blocked where the ray meets an
object's triangles (cast by :mod:`phonglab.render.shadows`). A ray costs
time, and most pairs of a light and an object can be shown, from the
objects' boxes alone, never to block anything. :func:`plan_shadows` decides
for every light and every object that could block it (the *occluder*) which
objects' points (the *receivers*) must test their rays against it, and says
why the others need not. A pair is traced when it has a receiver.

A receiver R is left out for the light L and the occluder B when one of these
holds (each is conservative: it never leaves out a ray that could be blocked):

1. L adds nothing to R (its intensity, or R's ``k_d`` and ``k_s``, are 0);
2. R is B itself, and B cannot shadow itself: a convex solid or a flat
   plane (:data:`~phonglab.scene.objects.CONVEX_KINDS`; a torus may, and so
   may a mesh read from a file, whose shape the planner does not read). On the smooth
   surface such a mesh stands for, the only rays its own surface blocks
   leave the point into the solid, where the light is behind the surface
   and ``n·l ≤ 0`` already gives 0; the ray caster never tests an object
   that cannot shadow itself against its own triangles (their facets would
   only add the tessellation's artefacts, a jagged false terminator);
3. L is a spot and B's box lies wholly outside its cone: a lit point is
   inside the cone, and so is the whole segment from it to the spot's tip
   (the cone is convex), so B cannot touch it; or R's box lies wholly
   outside the cone (R is not lit at all);
4. a plane separates B's box from every segment between R's box and L
   (from the convex hull of R's box and the light's position; for a
   directional light, of R's box swept towards the light): B is wholly
   behind the light, beside the light's path, or behind R, seen from L.
   The planes tried are across the three axes and across the lines from B's
   centre to L and to R's centre; a pair no plane separates is traced.

Boxes come from the geometries alone (:func:`~phonglab.scene.objects.object_box`),
widened by a margin for the rounding of placed points, so no mesh is built.
With ``full=True`` every pair is traced except rule 2's, which is not a
shortcut but the model (see above): the test suite holds the planned
shadows to the fully traced ones, exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from phonglab import core
from phonglab.scene.objects import cannot_shadow_itself, object_box

__all__ = ["ShadowPair", "plan_shadows"]

#: slack, in radians, of the spot-cone test (the core's cone test has a few ulps of slack too)
CONE_SLACK = 1e-6
#: margin of every box, relative to its largest coordinate (placed points are rounded to float32)
BOX_MARGIN = 1e-5


@dataclass(frozen=True)
class ShadowPair:
    """One light and one object that could block it: which objects' rays are tested against it, and why.

    Attributes
    ----------
    light : int
        The light's index in ``scene.lights``.
    occluder : int
        The object's index in ``scene.all_objects``.
    receivers : tuple of int
        The objects whose points test their shadow rays towards the light
        against this object's triangles; empty when the pair is skipped.
    reasons : tuple of (int, str)
        For every object left out: its index and why.
    """

    light: int
    occluder: int
    receivers: tuple[int, ...]
    reasons: tuple[tuple[int, str], ...] = ()

    @property
    def traced(self) -> bool:
        """Whether any ray is tested against this pair's occluder."""
        return bool(self.receivers)


def plan_shadows(scene, core_plans, *, full: bool = False) -> tuple[ShadowPair, ...]:
    """The light–object pairs of ``scene`` and which of them are traced (empty without ``shadows``).

    Parameters
    ----------
    scene : Scene
    core_plans : sequence of phonglab.core.Plan
        Each object's plan (its material and the lights): a light the plan
        does not evaluate adds nothing to the object.
    full : bool
        Trace every pair (but an object that cannot shadow itself is still
        not tested against itself: that is the model's rule, not a shortcut).

    Returns
    -------
    tuple of ShadowPair
        One per directed light and object, in the lights' then the objects' order.
    """
    if not scene.shadows:
        return ()
    objects = scene.all_objects
    names = [o.label for o in objects]
    boxes = [_widened(object_box(o.geometry)) for o in objects]
    flat = [cannot_shadow_itself(o.geometry) for o in objects]
    pairs = []
    for index, light in enumerate(scene.lights):
        if isinstance(light, core.AmbientLight):
            continue
        for b in range(len(objects)):
            receivers, reasons = [], []
            for r in range(len(objects)):
                why = _left_out(light, index, b, r, boxes, flat, core_plans, names, full)
                if why is None:
                    receivers.append(r)
                else:
                    reasons.append((r, why))
            pairs.append(ShadowPair(index, b, tuple(receivers), tuple(reasons)))
    return tuple(pairs)


def _left_out(light, index, b, r, boxes, flat, core_plans, names, full) -> str | None:
    """Why receiver ``r`` need not test its rays towards ``light`` against occluder ``b``; None when it must."""
    if b == r and flat[b]:
        return (f"the {names[b]} cannot shadow itself: its shape is convex or flat, so where its own surface "
                "would block the light, n·l ≤ 0 already gives 0")
    if not any(lp.index == index for lp in core_plans[r].lights):
        return f"light {index} adds nothing to the {names[r]}"
    if full:
        return None
    if isinstance(light, core.SpotLight) and light.is_cone:
        if not _box_meets_cone(boxes[b], light):
            return f"the {names[b]} lies wholly outside the spot's cone"
        if not _box_meets_cone(boxes[r], light):
            return f"the {names[r]} lies wholly outside the spot's cone: it is not lit"
    if b != r and _separated(boxes[b], boxes[r], light):
        return (f"seen from light {index}, the {names[b]} is not between it and the {names[r]} "
                "(a plane separates them)")
    return None


def _widened(box):
    lo, hi = (np.asarray(x, dtype=np.float64) for x in box)
    margin = BOX_MARGIN * (1.0 + max(np.abs(lo).max(), np.abs(hi).max()))
    return lo - margin, hi + margin


def _corners(box) -> np.ndarray:
    lo, hi = box
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def _separated(occluder, receiver, light) -> bool:
    """Whether a plane separates the occluder's box from every segment between the receiver's box and the light."""
    b_corners, r_corners = _corners(occluder), _corners(receiver)
    b_centre, r_centre = b_corners.mean(axis=0), r_corners.mean(axis=0)
    directional = isinstance(light, core.DirectionalLight)
    towards = np.asarray(light.direction if directional else light.position, dtype=np.float64)
    axes = [np.eye(3)[k] for k in range(3)]
    axes.append(towards if directional else towards - b_centre)
    axes.append(r_centre - b_centre)
    for axis in axes:
        norm = float(np.linalg.norm(axis))
        if norm == 0:
            continue
        axis = axis / norm
        b = b_corners @ axis
        r = r_corners @ axis
        lo, hi = float(r.min()), float(r.max())
        if directional:
            # the receiver swept towards the light, without end
            along = float(towards @ axis)
            lo, hi = (lo, math.inf) if along > 0 else (-math.inf, hi) if along < 0 else (lo, hi)
        else:
            reach = float(towards @ axis)
            lo, hi = min(lo, reach), max(hi, reach)
        if float(b.max()) < lo or float(b.min()) > hi:
            return True
    return False


def _box_meets_cone(box, spot) -> bool:
    """Whether the box's bounding sphere meets the spot's cone (apex at the light, half-angle the cutoff)."""
    lo, hi = box
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2
    offset = centre - np.asarray(spot.position, dtype=np.float64)
    dist = float(np.linalg.norm(offset))
    if dist <= radius:
        return True
    axis = np.asarray(spot.direction, dtype=np.float64)
    axis = axis / np.linalg.norm(axis)
    angle = math.acos(max(-1.0, min(1.0, float(offset @ axis) / dist)))
    return angle - math.radians(spot.cutoff) <= math.asin(min(1.0, radius / dist)) + CONE_SLACK
