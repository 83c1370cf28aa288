"""Which effects a scene calls for, and shading that does only those.

:func:`plan` asks the core's :func:`~phonglab.core.plan_effects` which terms
of the Phong sum the scene's material and lights need, and adds what the
scene itself decides: where shading is evaluated (per triangle, per vertex or
per pixel). :func:`shade` runs the core with that plan, so a skipped effect
costs nothing; ``full=True`` runs the full evaluation instead, the reference
the planned result matches to within an ulp, and ``mistake=`` shades with
one of the teaching layer's deliberately wrong variants instead.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from phonglab import core
from phonglab.scene.model import Scene
from phonglab.scene.shadowplan import ShadowPair, plan_shadows

#: interpolation -> (computed effect, reason)
_WHERE = {
    "flat": ("flat shading", "one shade per triangle, with the triangle's normal"),
    "gouraud": ("per-vertex shading", "one shade per vertex; colours are interpolated across each triangle"),
    "pixel": ("per-pixel shading", "normals are interpolated and every pixel is shaded: one shade per pixel"),
}


_AREA_HOW = {
    "exact": "diffuse light from the rectangle, exactly (Lambert's closed form for a polygon)",
    "point": "diffuse light approximated by a point light at the rectangle's centre",
    "uniform": "diffuse light by Monte Carlo, {samples} uniform samples of the rectangle per point",
    "stratified": "diffuse light by Monte Carlo, {samples} stratified samples of the rectangle per point",
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
    area_light: bool = False  # the scene's area light adds light
    #: every object's core plan (its own material), the first one's being ``core``
    objects: tuple = ()
    #: the light–object pairs of a scene with shadows, traced or skipped
    #: (:func:`~phonglab.scene.shadowplan.plan_shadows`)
    shadows: tuple[ShadowPair, ...] = ()

    def as_dict(self) -> dict:
        """A JSON-ready form: ``{"computed": [{"effect", "reason"}...], "skipped": [...]}``."""
        return {
            "computed": [{"effect": e, "reason": r} for e, r in self.computed],
            "skipped": [{"effect": e, "reason": r} for e, r in self.skipped],
        }

    @property
    def traced(self) -> tuple[ShadowPair, ...]:
        """The light–object pairs whose shadow rays are cast."""
        return tuple(pair for pair in self.shadows if pair.traced)


def viewer(scene: Scene) -> dict:
    """The core's viewer keywords: ``{"eye": ...}`` or ``{"view_direction": ...}`` for an infinite viewer."""
    if scene.camera.infinite_viewer:
        return {"view_direction": scene.camera.view_direction}
    return {"eye": scene.camera.eye}


def plan(scene: Scene, *, full_shadows: bool = False) -> ScenePlan:
    """Decide which effects ``scene`` needs, with a reason for each one skipped.

    Parameters
    ----------
    scene : Scene
    full_shadows : bool
        Trace the shadow rays of every light–object pair (the reference the
        planned shadows match), not only those that can be blocked.

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
    one shade per pixel instead of one per vertex. A scene of several objects
    plans each object's material (the lines shown are the first object's),
    and a scene with shadows lists its light–object pairs, the ones traced
    and why the others are skipped (:mod:`phonglab.scene.shadowplan`).
    """
    objects = scene.all_objects
    plans = tuple(core.plan_effects(o.material, scene.lights, two_sided=scene.two_sided, model=scene.model,
                                    **viewer(scene)) for o in objects)
    core_plan = plans[0]
    computed = list(core_plan.computed)
    skipped = list(core_plan.skipped)
    if len(objects) > 1:
        computed.append(("objects", f"{len(objects)} objects, each shaded with its own material: "
                                    + ", ".join(o.label for o in objects)))
    computed.append(_WHERE[scene.interpolation])
    if scene.interpolation != "pixel":
        skipped.append(("per-pixel shading", f'interpolation is "{scene.interpolation}", not "pixel"'))
    area = scene.area_light
    if area is None:
        skipped.append(("area light", "the scene has none"))
    elif not any(any(o.material.kd) for o in objects) or not area.light.intensity or not any(area.light.color):
        skipped.append(("area light", "k_d or its intensity is 0: it adds nothing"))
        area = None
    else:
        computed.append(("area light", _AREA_HOW[area.method].format(samples=area.samples)))
    pairs = plan_shadows(scene, plans, full=full_shadows)
    if not scene.shadows:
        skipped.append(("shadows", "shadows are off: every light reaches every point its n·l gate lets it"))
    for pair in pairs:
        effect = f"shadow of the {objects[pair.occluder].label} from light {pair.light}"
        if pair.traced:
            computed.append((effect, "rays from " + ", ".join(f"the {objects[r].label}" for r in pair.receivers)
                             + " are tested against it" + "".join(f"; {why}" for _, why in pair.reasons)))
        else:
            skipped.append((effect, "; ".join(why for _, why in pair.reasons)))
    return ScenePlan(tuple(computed), tuple(skipped), core_plan, area is not None, plans, pairs)


def shade(scene: Scene, points, normals, *, full: bool = False, scene_plan: ScenePlan | None = None,
          mistake: str | None = None, objects=None, visibility=None) -> core.Shading:
    """Shade ``points`` with ``normals`` under the scene's materials, lights and viewer.

    Parameters
    ----------
    scene : Scene
    points, normals : array_like, shape (..., 3)
    full : bool
        Evaluate every term of the model instead of the scene's plan.
    scene_plan : ScenePlan, optional
        A plan already made for this scene by :func:`plan` (saves remaking it).
    mistake : str, optional
        A name from :data:`phonglab.teaching.MISTAKES`: shade with that
        deliberately wrong variant of the model (the core's reference kernel
        with one step changed) instead, with the scene's material, lights,
        model, two-sidedness and viewer. The scene's area light is not added
        to a mistake's shading.
    objects : array_like of int, shape (...), optional
        The object each point lies on (its index in ``scene.all_objects``):
        it is shaded with that object's material. None: the first object's.
    visibility : mapping int -> array_like, optional
        Shadows, one 0 or 1 per point for a light's index
        (:func:`phonglab.core.shade`'s ``visibility``, found by a ray caster
        above this layer). None: no light is blocked.

    Returns
    -------
    phonglab.core.Shading
        ``ambient``, ``diffuse``, ``specular``, ``emission`` and ``color``.

    Raises
    ------
    ValueError
        For an unknown mistake name (the message lists the names allowed).
    """
    scene_plan = None if full or mistake is not None else (scene_plan or plan(scene))
    if objects is None or len(scene.all_objects) == 1:
        return _shade_object(scene, 0, points, normals, full, scene_plan, mistake, visibility)
    points, normals = np.asarray(points), np.asarray(normals)
    shape = np.broadcast_shapes(points.shape, normals.shape)
    ids = np.broadcast_to(np.asarray(objects), shape[:-1]).reshape(-1)
    present = np.unique(ids)
    if len(present) == 1:  # every point on one object
        return _shade_object(scene, int(present[0]), points, normals, full, scene_plan, mistake, visibility)
    P = np.broadcast_to(points, shape).reshape(-1, 3)
    N = np.broadcast_to(normals, shape).reshape(-1, 3)
    seen = {i: np.broadcast_to(np.asarray(v), shape[:-1]).reshape(-1) for i, v in (visibility or {}).items()}
    out = None
    for k in present:
        where = np.flatnonzero(ids == k)
        part = _shade_object(scene, int(k), P[where], N[where], full, scene_plan, mistake,
                             {i: v[where] for i, v in seen.items()} or None)
        if out is None:
            out = {t: np.zeros((len(ids), 3), getattr(part, t).dtype) for t in _TERMS}
        for t in _TERMS:
            out[t][where] = getattr(part, t)
    return core.Shading(**{t: out[t].reshape(shape) for t in _TERMS})


_TERMS = ("ambient", "diffuse", "specular", "emission", "color")


def _shade_object(scene: Scene, k: int, points, normals, full, scene_plan, mistake, visibility) -> core.Shading:
    """The points of object ``k``, shaded with its material (see :func:`shade`)."""
    material = scene.all_objects[k].material
    if mistake is not None:
        # the wrong variants live in the teaching layer, imported only when one is asked for
        from phonglab.teaching import get_mistake

        return get_mistake(mistake).shade(points, normals, material=material, lights=scene.lights,
                                          model=scene.model, two_sided=scene.two_sided, visibility=visibility,
                                          **viewer(scene))
    core_plan = "full" if full else (scene_plan.objects[k] if scene_plan.objects else scene_plan.core)
    shading = core.shade(points, normals, material=material, lights=scene.lights, model=scene.model,
                         two_sided=scene.two_sided, plan=core_plan, visibility=visibility, **viewer(scene))
    if scene.area_light is None or not (full or scene_plan.area_light):
        return shading
    return _add_area_light(scene, points, normals, shading, material=material)


def _add_area_light(scene: Scene, points, normals, shading: core.Shading, record=None, *, material=None):
    """The shading (and its record) with the scene's area light added to its diffuse term and colour."""
    area = scene.area_light
    # a fixed seed: Monte Carlo noise stays put while sliders move
    return core.add_area_light(shading, points, normals, material=material or scene.material, light=area.light,
                               method=area.method, samples=area.samples, seed=0, two_sided=scene.two_sided,
                               record=record, **viewer(scene))


def trace(scene: Scene, points, normals, *, mistake: str | None = None, obj: int = 0,
          visibility=None) -> tuple[core.Shading, core.Record]:
    """The scene's shading and the :class:`~phonglab.core.Record` of what the model used, at ``points``.

    The reference kernel (:func:`~phonglab.core.shade_reference` with
    ``trace=True``), with the scene's area light added (as the last light of
    the record) when it adds light. With ``mistake`` (a name from
    :data:`phonglab.teaching.MISTAKES`) the mistaken kernel's own shading
    and record, without the area light, as :func:`shade` gives it.

    ``obj`` is the object the points lie on (its material is used) and
    ``visibility`` the shadows there, as for :func:`shade`: the record's
    lights then carry ``lit``.

    The colours equal :func:`shade`'s to within the reference kernel's
    rounding (a few ulps; about α ulps of a sharp highlight).
    """
    material = scene.all_objects[obj].material
    args = dict(material=material, lights=scene.lights, model=scene.model, two_sided=scene.two_sided,
                visibility=visibility, **viewer(scene))
    if mistake is not None:
        from phonglab.teaching import get_mistake

        return get_mistake(mistake).shade(points, normals, trace=True, **args)
    shading, record = core.shade_reference(points, normals, trace=True, **args)
    if scene.area_light is None or not plan(scene).area_light:
        return shading, record
    return _add_area_light(scene, points, normals, shading, record, material=material)
