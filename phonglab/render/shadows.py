"""Shadow rays cast on the scene's triangles with Embree: which lights reach which shaded points.

The core says what a shadow ray is (:func:`phonglab.core.shadow_rays`: from
the point, offset by the scene's ``shadow_bias`` towards the light, up to
the light) and applies the answer (``visibility=`` of the kernels); the
scene's planner says which light–object pairs can block anything
(:mod:`phonglab.scene.shadowplan`). Here the rays are cast: each object's
triangles, placed as the view shows them (:func:`~phonglab.render.objects.scene_mesh`),
get their own Embree scene (a bounding volume hierarchy, built once per
mesh and kept), and a traced pair asks Embree's *occluded* query whether
each of its receivers' rays meets that object's triangles before the light.

Embree (through ``embreex``) answers about a million shadow rays a second on
one core here, against 35 thousand for VTK's cell locator called from Python
and about a thousand for a NumPy loop over the triangles; its scenes are
built "robust" (watertight: a ray through a shared edge cannot slip between
the two triangles).

An object that cannot shadow itself (convex or flat) is never tested
against its own triangles: see :mod:`phonglab.scene.shadowplan`.
"""

from __future__ import annotations

import threading

import numpy as np

from phonglab import core
from phonglab.render.objects import mesh_key, object_at, object_count, object_triangles, scene_mesh

__all__ = ["Caster", "caster", "visibility", "blockers", "at_probe", "forget"]


class Caster:
    """Shadow rays against one scene mesh: an Embree scene per object, built on first use.

    Parameters
    ----------
    mesh : pyvista.PolyData
        A :func:`~phonglab.render.objects.scene_mesh` (kept for its triangles).
    """

    def __init__(self, mesh):
        self._mesh = mesh
        self._scenes = {}
        self._lock = threading.Lock()  # a per-pixel picture is finished in another thread
        self.objects = object_count(mesh)

    def _scene(self, index: int):
        with self._lock:
            found = self._scenes.get(index)
            if found is None:
                from embreex import rtcore_scene
                from embreex.mesh_construction import TriangleMesh

                found = rtcore_scene.EmbreeScene(robust=True)
                TriangleMesh(found, np.ascontiguousarray(object_triangles(self._mesh, index)))
                self._scenes[index] = found
            return found

    def occluded(self, index: int, origins, directions, lengths) -> np.ndarray:
        """Which rays meet object ``index``'s triangles within their length (bool, one per ray).

        ``origins`` and ``directions`` are (n, 3) float32, ``lengths`` (n,) float32;
        a ray of length 0 meets nothing.
        """
        hit = np.zeros(len(origins), bool)
        run = lengths > 0
        if run.any():
            answer = self._scene(index).run(np.ascontiguousarray(origins[run]), np.ascontiguousarray(directions[run]),
                                            dists=np.ascontiguousarray(lengths[run]), query="OCCLUDED")
            hit[run] = answer >= 0  # Embree's occluded query: 0 blocked, -1 free
        return hit


_CASTERS: dict = {}
_CASTERS_LOCK = threading.Lock()
#: casters kept (one per scene mesh); the oldest goes first
MAX_CASTERS = 4


def caster(scene) -> Caster:
    """The :class:`Caster` of ``scene``'s objects as placed, made once per set of objects and kept."""
    key = mesh_key(scene)
    with _CASTERS_LOCK:
        found = _CASTERS.get(key)
        if found is None:
            found = Caster(scene_mesh(scene))
            if len(_CASTERS) >= MAX_CASTERS:
                _CASTERS.pop(next(iter(_CASTERS)))
            _CASTERS[key] = found
        return found


_SEEN: dict = {}
#: visibilities kept (a turn of the view shades the same vertices under the same lights again)
MAX_SEEN = 8


def forget() -> None:
    """Drop every kept visibility (a benchmark times the casting itself, as after a lamp moved)."""
    with _CASTERS_LOCK:
        _SEEN.clear()


def visibility(scene, points, objects=None, *, scene_plan=None, full: bool = False, cache=None) -> dict | None:
    """Which directed lights reach each point: ``{light index: bool array}`` for the kernels, or None.

    Parameters
    ----------
    scene : Scene
        With ``shadows`` on (otherwise None is returned: nothing is blocked).
    points : array_like, shape (n, 3)
        Shaded points on the scene's surfaces (vertices, face centroids or
        the G-buffer's pixels).
    objects : array_like of int, shape (n,), optional
        The object each point lies on; None: all on the first.
    scene_plan : ScenePlan, optional
        ``plan(scene)``: its traced pairs are cast (planned here when None).
    full : bool
        Cast every pair's rays (:func:`phonglab.scene.plan` with
        ``full_shadows``): the reference the planned shadows equal.
    cache : tuple, optional
        What the points are, for keeping the answer: ``("vertex",)`` and
        ``("face",)`` (the scene mesh's vertices or face centroids), or
        ``("pixel", gbuffer)``. The answer is kept while the objects, the
        lights and the bias stay (not the camera, the material or the model:
        a shadow does not depend on them).

    Returns
    -------
    dict or None
        For every light with a traced pair: True where nothing blocks it.
    """
    if not scene.shadows:
        return None
    from phonglab.scene import plan

    pairs = (plan(scene, full_shadows=True) if full else (scene_plan or plan(scene))).shadows
    traced = [pair for pair in pairs if pair.traced]
    if not traced:
        return None
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    key = None
    if cache is not None:
        key = (tuple(x if isinstance(x, str) else id(x) for x in cache), mesh_key(scene), scene.lights,
               scene.shadow_bias, tuple(traced), len(points))
        kept = _SEEN.get(key)
        if kept is not None:
            return kept[1]
    ids = np.zeros(len(points), np.int32) if objects is None else np.asarray(objects).reshape(-1)
    cast = caster(scene)
    seen = {}
    for index in sorted({pair.light for pair in traced}):
        origins, directions, lengths = core.shadow_rays(points, scene.lights[index], bias=scene.shadow_bias)
        lit = np.ones(len(points), bool)
        for pair in (p for p in traced if p.light == index):
            # the receivers' points not yet in shadow: their rays against this occluder
            rows = np.flatnonzero(np.isin(ids, pair.receivers) & lit)
            if len(rows):
                lit[rows[cast.occluded(pair.occluder, origins[rows], directions[rows], lengths[rows])]] = False
        seen[index] = lit
    if key is not None:
        with _CASTERS_LOCK:
            if len(_SEEN) >= MAX_SEEN:
                _SEEN.pop(next(iter(_SEEN)))
            _SEEN[key] = (cache, seen)  # the cache's objects are held, so their ids stay theirs
    return seen


def blockers(scene, point, obj: int = 0) -> dict[int, int | None]:
    """At one point: for every directed light, the first object (in the scene's order) that blocks it, else None.

    Every pair is cast (the probe is one point), under the same rule as the
    picture: an object that cannot shadow itself is not tested against itself.
    Empty without ``shadows``.
    """
    if not scene.shadows:
        return {}
    from phonglab.scene import plan

    cast = caster(scene)
    point = np.asarray(point, dtype=np.float64).reshape(1, 3)
    out = {}
    for pair in plan(scene, full_shadows=True).shadows:
        out.setdefault(pair.light, None)
        if out[pair.light] is not None or obj not in pair.receivers:
            continue
        origins, directions, lengths = core.shadow_rays(point, scene.lights[pair.light], bias=scene.shadow_bias)
        if cast.occluded(pair.occluder, origins, directions, lengths)[0]:
            out[pair.light] = pair.occluder
    return out


def at_probe(scene, point) -> tuple[int, dict | None, dict[int, int | None]]:
    """What the readout needs at a probe point: its object, the kernels' visibility there, the blockers.

    Returns
    -------
    (object, visibility, blockers)
        The index of the object the point lies on; ``{light: [lit]}`` for
        the kernels (None without shadows); and for every directed light the
        object that blocks it, or None (:func:`blockers`; empty without shadows).
    """
    obj = object_at(scene_mesh(scene), point) if len(scene.all_objects) > 1 else 0
    found = blockers(scene, point, obj)
    seen = {light: np.array([by is None]) for light, by in found.items()} if scene.shadows else None
    return obj, seen or None, found
