"""Which effects a scene calls for, and shading that does only those.

:func:`plan` asks the core's :func:`~phonglab.core.plan_effects` which terms
of the Phong sum the scene's material and lights need, and adds what the
scene itself decides: where shading is evaluated (per triangle, per vertex or
per pixel). :func:`shade` runs the core with that plan, so a skipped effect
costs nothing; ``full=True`` runs the full evaluation instead, the reference
the planned result matches to within an ulp.
"""

from __future__ import annotations

from dataclasses import dataclass

from phonglab import core
from phonglab.scene.model import Scene

#: interpolation -> (computed effect, reason)
_WHERE = {
    "flat": ("flat shading", "one shade per triangle, with the triangle's normal"),
    "gouraud": ("per-vertex shading", "one shade per vertex; colours are interpolated across each triangle"),
    "pixel": ("per-pixel shading", "normals are interpolated and every pixel is shaded: one shade per pixel"),
}


@dataclass(frozen=True)
class ScenePlan:
    """The effects a scene computes and skips.

    Attributes
    ----------
    computed, skipped : tuple of (effect, reason)
        Human-readable, in the order of the model's equation, then the
        scene-level lines (interpolation).
    core : phonglab.core.Plan
        The core plan to pass to ``phonglab.core.shade(..., plan=...)``.
    """

    computed: tuple[tuple[str, str], ...]
    skipped: tuple[tuple[str, str], ...]
    core: core.Plan

    def as_dict(self) -> dict:
        """A JSON-ready form: ``{"computed": [{"effect", "reason"}...], "skipped": [...]}``."""
        return {
            "computed": [{"effect": e, "reason": r} for e, r in self.computed],
            "skipped": [{"effect": e, "reason": r} for e, r in self.skipped],
        }


def viewer(scene: Scene) -> dict:
    """The core's viewer keywords: ``{"eye": ...}`` or ``{"view_direction": ...}`` for an infinite viewer."""
    if scene.camera.infinite_viewer:
        return {"view_direction": scene.camera.view_direction}
    return {"eye": scene.camera.eye}


def plan(scene: Scene) -> ScenePlan:
    """Decide which effects ``scene`` needs, with a reason for each one skipped.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    ScenePlan

    Notes
    -----
    The core skips what contributes exactly nothing (a zero ``k_d``, ``k_s``
    or light, attenuation ``(1, 0, 0)``, a 180° spot cone, the two-sided
    flip when it is off) and replaces per-point vectors by constants where
    they are the same everywhere (directional ``L``, infinite-viewer ``V``).
    The scene adds where shading happens: ``interpolation = "pixel"`` costs
    one shade per pixel instead of one per vertex.
    """
    core_plan = core.plan_effects(
        scene.material, scene.lights, two_sided=scene.two_sided, model=scene.model, **viewer(scene)
    )
    computed = list(core_plan.computed)
    skipped = list(core_plan.skipped)
    computed.append(_WHERE[scene.interpolation])
    if scene.interpolation != "pixel":
        skipped.append(("per-pixel shading", f'interpolation is "{scene.interpolation}", not "pixel"'))
    return ScenePlan(tuple(computed), tuple(skipped), core_plan)


def shade(scene: Scene, points, normals, *, full: bool = False, scene_plan: ScenePlan | None = None) -> core.Shading:
    """Shade ``points`` with ``normals`` under the scene's material, lights and viewer.

    Parameters
    ----------
    scene : Scene
    points, normals : array_like, shape (..., 3)
    full : bool
        Evaluate every term of the model instead of the scene's plan.
    scene_plan : ScenePlan, optional
        A plan already made for this scene by :func:`plan` (saves remaking it).

    Returns
    -------
    phonglab.core.Shading
        ``ambient``, ``diffuse``, ``specular``, ``emission`` and ``color``.
    """
    if full:
        chosen = "full"
    else:
        chosen = (scene_plan or plan(scene)).core
    return core.shade(
        points,
        normals,
        material=scene.material,
        lights=scene.lights,
        model=scene.model,
        two_sided=scene.two_sided,
        plan=chosen,
        **viewer(scene),
    )
