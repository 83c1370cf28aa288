"""Execute a lesson's claims on its own scene.

A lesson's ``[[claims]]`` (read and checked for form by
:mod:`phonglab.scene.claims`) pair a sentence with a check expression. Here
each check is evaluated on the lesson's scene, with the claim's experiment
and settings applied by :meth:`Scene.replace_many` as the page applies an
experiment. The measurement functions see the scene as the page shows it:

- the *picture* is the scene's mesh (:func:`phonglab.render.objects.scene_mesh`:
  every object, each shaded with its own material, and the scene's shadows
  traced for every light–object pair) seen through the pixels of the scene's camera (exact ray casting,
  :mod:`phonglab.accuracy.raycast`), shaded by the core with the scene's
  interpolation: one shade per triangle (flat), per vertex blended with the
  barycentric weights (Gouraud) or per pixel with blended normals;
- the *probe* is the point :func:`phonglab.render.probe.locate_probe` picks,
  with the vectors of :func:`phonglab.render.probe.probe_vectors`.

Colours are the core's unclamped linear values (what the readout shows).
The ``shown_*`` functions measure instead the 8-bit picture the page shows
(:mod:`phonglab.accuracy.shown`): after the opacity blend, the exposure, the
clip and the display encoding, in the scene's interpolation mode.

A claim's ``false_when`` is run by :func:`check_false_when`: the same check,
with the sentence made false, must fail; a check that still passes is too
weak to tell the sentence from its opposite.
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import math
import operator
from dataclasses import dataclass, field

import numpy as np

from phonglab import core
from phonglab.accuracy import interpolation
from phonglab.accuracy.arealight import LIGHT
from phonglab.accuracy.raycast import View, hit_mesh
from phonglab.accuracy.shown import levels, shown
from phonglab.scene.claims import parse_check, replaced_check

__all__ = ["ClaimResult", "check_claim", "check_false_when", "check_lesson", "FUNCTIONS", "PICTURE_SIZE"]

#: width and height, in pixels, of the picture the image measurements use
PICTURE_SIZE = 160


@dataclass(frozen=True)
class ClaimResult:
    """The verdict on one claim.

    ``measured`` lists each function call of the check with the value it
    gave, e.g. ``[("peak('specular')", 0.6)]``; ``value`` is the check's own
    value (True/False); ``error`` names what went wrong when the check could
    not be evaluated.
    """

    lesson: str
    says: str
    check: str
    passed: bool
    value: object = None
    measured: list = field(default_factory=list)
    error: str = ""
    #: the settings the check ran under beyond the claim's own (a ``false_when``), as (path, value)
    changed: tuple = ()

    def describe(self) -> str:
        """One line per fact: the lesson, the sentence, the check and every measured value."""
        lines = [f"{self.lesson}: {'ok' if self.passed else 'FAILS'}: {self.says}", f"  check: {self.check}"]
        if self.changed:
            lines.append("  with " + ", ".join(f"{path} = {value}" for path, value in self.changed))
        lines += [f"  {call} = {_shown_number(value)}" for call, value in self.measured]
        if self.error:
            lines.append(f"  error: {self.error}")
        return "\n".join(lines)

    def measured_text(self) -> str:
        """The measured values on one line: ``peak('specular') = 0.6, shown_peak('color') = 255``."""
        return ", ".join(f"{call} = {_shown_number(value)}" for call, value in self.measured) or "nothing measured"


def _shown_number(value) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


# ---------------------------------------------------------------------------
# the picture and the probe, as the page computes them


@dataclass
class _Picture:
    shading: core.Shading  # per covered pixel
    lit: np.ndarray  # per covered pixel: a directed light reaches it
    mask: np.ndarray  # (height, width): the pixels the surface covers


def _mesh(scene):
    from phonglab.render.objects import scene_mesh

    return scene_mesh(scene)


def _view(scene, size: int = PICTURE_SIZE) -> View:
    cam = scene.camera
    return View(eye=tuple(cam.eye), focal_point=tuple(cam.focal_point), up=tuple(cam.up),
                view_angle=float(cam.view_angle), width=size, height=size)


def _shade(scene, points, normals, objects=None):
    """The full evaluation at the points (on ``objects``), with the scene's shadows fully traced."""
    from phonglab.render.shadows import visibility
    from phonglab.scene import shade

    seen = visibility(scene, points, objects, full=True) if scene.shadows else None
    return shade(scene, points, normals, full=True, objects=objects, visibility=seen)


@functools.lru_cache(maxsize=64)
def _picture(scene) -> _Picture:
    from phonglab.render.mesh import face_centroids_normals, triangles
    from phonglab.render.objects import cell_objects, point_objects

    mesh = _mesh(scene)
    on_vertex, on_face = point_objects(mesh), cell_objects(mesh)
    tri = triangles(mesh)
    points = np.asarray(mesh.points, dtype=np.float64)
    normals = np.asarray(mesh.point_data["Normals"], dtype=np.float64)
    hits = hit_mesh(_view(scene), points, tri)
    corners = tri[hits.triangle]
    w = hits.weights

    def blend(values):
        return sum(w[:, k:k + 1] * values[corners[:, k]] for k in range(3))

    if scene.interpolation == "flat":
        centroids, face_normals = face_centroids_normals(mesh)
        per_face = _shade(scene, np.asarray(centroids, float), np.asarray(face_normals, float), on_face)
        shading = core.Shading(**{t: getattr(per_face, t)[hits.triangle] for t in _TERMS})
    elif scene.interpolation == "gouraud":
        per_vertex = _shade(scene, points, normals, on_vertex)
        shading = core.Shading(**{t: blend(getattr(per_vertex, t)) for t in _TERMS})
    else:  # per pixel: normals blended, renormalised by the core
        shading = _shade(scene, blend(points), blend(normals), None if on_face is None else on_face[hits.triangle])
    lit = shading.diffuse.max(axis=-1) > 0
    return _Picture(shading=shading, lit=lit, mask=hits.mask)


_TERMS = ("ambient", "diffuse", "specular", "emission", "color")


def _channel(values, channel: str):
    values = np.asarray(values, dtype=np.float64)
    if channel == "max":
        return values.max(axis=-1)
    return values[..., "rgb".index(channel)]


@functools.lru_cache(maxsize=64)
def _probe(scene):
    """The record of the model at the probe (:func:`phonglab.scene.trace`), its shading, and the light drawn.

    What the readout shows: ``probe('nl')`` is the drawn light's ``n·l`` as
    the model used it, ``probe('specular')`` the specular term of all lights.
    """
    from phonglab.render.probe import directed_light_index, locate_probe
    from phonglab.render.shadows import at_probe
    from phonglab.scene import trace

    point, normal = locate_probe(_mesh(scene), scene)
    obj, seen, _ = at_probe(scene, point)  # the object the probe is on, and the lights that reach it
    shading, record = trace(scene, np.asarray([point], float), np.asarray([normal], float), obj=obj,
                            visibility=seen)
    return record.at(0), shading, directed_light_index(scene.lights)


#: a claim's name for a quantity at the probe -> the record's name
_PROBE_NAMES = {"nl": "n·l", "rv": "r·v", "nh": "n·h", "distance": "d", "nv": "n·v", "vh": "v·h"}


def _probe_value(scene, quantity: str, channel: str = "max") -> float:
    record, shading, index = _probe(scene)
    if quantity in _TERMS:
        return float(_channel(getattr(shading, quantity)[0], channel))
    if index is None:
        raise ValueError(f"probe({quantity!r}): the scene has no directed light")
    light = record.light(index)
    name = _PROBE_NAMES.get(quantity, quantity)
    if name in light.values and np.ndim(light[name]) == 0:
        return float(light[name])
    if name in light.values and np.ndim(light[name]) == 1:  # a colour (Cook–Torrance's F)
        return float(_channel(light[name], channel))
    if name in ("attenuation", "spot"):
        return 1.0  # a directional light (or a point light, for the spot factor) has none
    if name == "d":
        return math.nan  # a directional light has no distance
    raise ValueError(f"probe({quantity!r}): not a number the model records at the probe")


def _peak(scene, term: str, channel: str = "max") -> float:
    return float(_channel(getattr(_picture(scene).shading, term), channel).max())


def _low(scene, term: str, channel: str = "max") -> float:
    return float(_channel(getattr(_picture(scene).shading, term), channel).min())


def _mean(scene, term: str, channel: str = "max") -> float:
    return float(_channel(getattr(_picture(scene).shading, term), channel).mean())


def _stretch(scene) -> float:
    picture = _picture(scene)
    specular = picture.shading.specular.max(axis=-1)
    rows, cols = np.nonzero(picture.mask)
    bright = specular >= 0.5 * specular.max()
    if specular.max() <= 0:
        raise ValueError("stretch(): the picture has no highlight")
    height = rows[bright].max() - rows[bright].min() + 1
    width = cols[bright].max() - cols[bright].min() + 1
    return float(height / width)


def _rim(scene) -> float:
    picture = _picture(scene)
    diffuse = picture.shading.diffuse.max(axis=-1)[picture.lit]
    if diffuse.size == 0:
        raise ValueError("rim(): no directed light reaches the picture")
    return float(diffuse.min() / diffuse.max())


def _lit_fraction(scene) -> float:
    return float(_picture(scene).lit.mean())


def _vertices(scene, resolution=None) -> float:
    if resolution is not None:
        scene = scene.replace("geometry.resolution", int(resolution))
    return float(_mesh(scene).n_points)


def _lit_cap(scene) -> float:
    from phonglab.render.objects import point_objects
    from phonglab.render.probe import directed_light_index

    mesh = _mesh(scene)
    points = np.asarray(mesh.points, dtype=np.float64)
    normals = np.asarray(mesh.point_data["Normals"], dtype=np.float64)
    index = directed_light_index(scene.lights)
    if index is None:
        raise ValueError("lit_cap(): the scene has no directed light")
    light = scene.lights[index]
    centre = points.mean(axis=0)
    # l seen from the centre (the core's l at a point, whatever the kind of light)
    axis = core.vectors(centre, (0.0, 0.0, 1.0), light=light, eye=scene.camera.eye).l
    one = scene.replace_many([(f"lights[{i}].intensity", 0) for i in range(len(scene.lights)) if i != index])
    lit = _shade(one, points, normals, point_objects(mesh)).diffuse.max(axis=-1) > 0
    offsets = points[lit] - centre
    cosines = offsets @ axis / np.linalg.norm(offsets, axis=-1)
    return float(np.degrees(np.arccos(np.clip(cosines.min(), -1.0, 1.0))))


@functools.lru_cache(maxsize=32)
def _error(scene, method: str, resolution: float, measure: str) -> float:
    # on the grid of the page's error images, so the figures a lesson states are the panel's
    view = _view(scene, interpolation.ERROR_IMAGE_SIZE)
    setup = interpolation.Setup(material=scene.material, lights=tuple(scene.lights), view=view)
    ref = interpolation.reference(setup, seconds=0.0)  # errors and counts only: nothing timed
    prep = interpolation.prepare(setup, int(resolution))
    row, _ = interpolation.measure(setup, ref, prep, method, repeats=1, seconds=0.0)
    return float(row[measure])


def _area_ratio(scene) -> float:
    below = np.array([[0.0, 0.0, 0.0]])  # the floor point under the panel's centre
    normal = np.array([[0.0, 0.0, 1.0]])
    point = core.area_irradiance(LIGHT, below, normal, method="point")
    exact = core.area_irradiance(LIGHT, below, normal, method="exact")
    return float(point[0] / exact[0])


@functools.lru_cache(maxsize=32)
def _area_error(scene, method: str, samples: float) -> float:
    from phonglab.accuracy.arealight import floor_points, relative_error

    points, normals = floor_points(24)
    exact = core.area_irradiance(LIGHT, points, normals, method="exact")
    errors = [relative_error(core.area_irradiance(LIGHT, points, normals, method=method, samples=int(samples),
                                                  seed=seed), exact) for seed in range(4)]
    return float(np.sqrt(np.mean(np.square(errors))))


def _blocked(scene) -> float:
    from phonglab.render.mesh import ray_hit
    from phonglab.render.probe import directed_light_index, locate_probe

    index = directed_light_index(scene.lights)
    if index is None:
        raise ValueError("blocked(): the scene has no directed light")
    mesh = _mesh(scene)
    point, normal = locate_probe(mesh, scene)
    light = scene.lights[index]
    l = core.vectors(point, normal, light=light, eye=scene.camera.eye).l
    far = getattr(light, "position", None)
    distance = float(np.linalg.norm(np.asarray(far, np.float64) - point)) if far is not None else math.inf
    # leave the surface first: start a hair along l, so the probe's own triangle is not the hit
    size = float(np.linalg.norm(np.ptp(np.asarray(mesh.points), axis=0)))
    start = np.asarray(point, np.float64) + 1e-6 * size * np.asarray(l, np.float64)
    hit = ray_hit(mesh, start, start + np.asarray(l, np.float64) * min(distance, 4.0 * size))
    return float(hit is not None and np.linalg.norm(hit[0] - start) < distance)


def _sum_gap(scene, channel: str = "max") -> float:
    terms = _picture(scene).shading
    total = terms.emission + terms.ambient + terms.diffuse + terms.specular
    return float(_channel(np.abs(np.asarray(terms.color, np.float64) - total), channel).max())


# ---------------------------------------------------------------------------
# the picture the page shows: 8-bit levels of the covered pixels


def _shown_mean(scene, term: str, channel: str = "max") -> float:
    return float(levels(shown(scene, term), channel).mean())


def _shown_median(scene, term: str, channel: str = "max") -> float:
    return float(np.median(levels(shown(scene, term), channel)))


def _shown_peak(scene, term: str, channel: str = "max") -> float:
    return float(levels(shown(scene, term), channel).max())


def _shown_low(scene, term: str, channel: str = "max") -> float:
    return float(levels(shown(scene, term), channel).min())


def _shown_fraction(scene, term: str, lo: float, hi: float, channel: str = "max") -> float:
    values = levels(shown(scene, term), channel)
    return float(np.mean((values >= lo) & (values <= hi)))


def _shown_levels(scene, term: str, channel: str = "max") -> float:
    return float(np.unique(levels(shown(scene, term), channel)).size)


def _shown_probe(scene, term: str, channel: str = "max") -> float:
    picture = shown(scene, term)
    if picture.probe is None:
        raise ValueError("shown_probe(): the probe is not seen in the picture")
    pixel = picture.image[picture.probe].astype(np.float64)
    return float(pixel.max() if channel == "max" else pixel["rgb".index(channel)])


def _shown_sum_gap(scene, channel: str = "max") -> float:
    whole = shown(scene, "color")
    parts = sum(shown(scene, t).image.astype(np.int64) for t in ("ambient", "diffuse", "specular"))
    gap = np.abs(whole.image.astype(np.int64) - np.minimum(parts, 255))[whole.mask].astype(np.float64)
    return float((gap.max(axis=-1) if channel == "max" else gap[:, "rgb".index(channel)]).mean())


def _albedo(model: str, view_angle: float, width: float) -> float:
    from phonglab.core.furnace import directional_albedo

    key = "roughness" if model == "cook-torrance" else "shininess"
    return directional_albedo(model, float(view_angle), **{key: float(width)})


def _degrees(f):
    return lambda x: f(math.radians(x))


#: function name -> implementation; the scene comes first for the measurements
FUNCTIONS = {
    "pow": (False, lambda x, y: math.pow(x, y)),
    "abs": (False, abs),
    "sqrt": (False, math.sqrt),
    "min": (False, min),
    "max": (False, max),
    "cosd": (False, _degrees(math.cos)),
    "acosd": (False, lambda x: math.degrees(math.acos(x))),
    "probe": (True, _probe_value),
    "peak": (True, _peak),
    "low": (True, _low),
    "mean": (True, _mean),
    "stretch": (True, _stretch),
    "rim": (True, _rim),
    "lit_fraction": (True, _lit_fraction),
    "vertices": (True, _vertices),
    "lit_cap": (True, _lit_cap),
    "error": (True, _error),
    "area_error": (True, _area_error),
    "area_ratio": (True, _area_ratio),
    "sum_gap": (True, _sum_gap),
    "blocked": (True, _blocked),
    "albedo": (False, _albedo),
    "shown_mean": (True, _shown_mean),
    "shown_median": (True, _shown_median),
    "shown_peak": (True, _shown_peak),
    "shown_low": (True, _shown_low),
    "shown_fraction": (True, _shown_fraction),
    "shown_levels": (True, _shown_levels),
    "shown_probe": (True, _shown_probe),
    "shown_sum_gap": (True, _shown_sum_gap),
}

# ---------------------------------------------------------------------------
# evaluation of a checked expression

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: math.pow}
_COMPARE = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge,
            ast.Eq: operator.eq, ast.NotEq: operator.ne}


def _evaluate(node, scene, measured: list):
    """The value of a node parse_check accepted; numbers are floats (no huge integers)."""
    if isinstance(node, ast.Constant):
        return float(node.value) if isinstance(node.value, (int, float)) else node.value
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](_evaluate(node.left, scene, measured), _evaluate(node.right, scene, measured))
    if isinstance(node, ast.UnaryOp):
        x = _evaluate(node.operand, scene, measured)
        return (not x) if isinstance(node.op, ast.Not) else (-x if isinstance(node.op, ast.USub) else +x)
    if isinstance(node, ast.BoolOp):
        values = (_evaluate(v, scene, measured) for v in node.values)
        return all(values) if isinstance(node.op, ast.And) else any(values)
    if isinstance(node, ast.Compare):
        left = _evaluate(node.left, scene, measured)
        for op, right_node in zip(node.ops, node.comparators):
            right = _evaluate(right_node, scene, measured)
            if not _COMPARE[type(op)](left, right):
                return False
            left = right
        return True
    if isinstance(node, ast.Call):
        needs_scene, fn = FUNCTIONS[node.func.id]
        args = [_evaluate(a, scene, measured) for a in node.args]
        value = fn(scene, *args) if needs_scene else fn(*args)
        if needs_scene or node.func.id == "pow":
            measured.append((ast.unparse(node), value))
        return value
    raise ValueError(f"unexpected construct {ast.unparse(node)!r}")  # parse_check refuses it first


def claim_scene(lesson, claim):
    """The scene a claim is checked on: the lesson's, then its experiment's settings, then its own."""
    scene = lesson.scene
    if claim.experiment is not None:
        scene = scene.replace_many(lesson.experiments[claim.experiment - 1].settings)
    if claim.settings:
        scene = scene.replace_many(claim.settings)
    return scene


def _run(lesson, claim, check: str, scene, changed=()) -> ClaimResult:
    measured: list = []
    name = f"lesson {lesson.number} ({lesson.path})"
    try:
        value = _evaluate(parse_check(check).body, scene, measured)
    except (ArithmeticError, ValueError) as exc:
        return ClaimResult(name, claim.says, check, False, None, measured, f"{type(exc).__name__}: {exc}", changed)
    return ClaimResult(name, claim.says, check, value is True, value, measured, changed=changed)


def check_claim(lesson, claim) -> ClaimResult:
    """Evaluate one claim of ``lesson`` on its scene."""
    return _run(lesson, claim, claim.check, claim_scene(lesson, claim))


def check_false_when(lesson, claim) -> ClaimResult:
    """Evaluate a claim's check with its sentence made false (its ``false_when``).

    Returns
    -------
    ClaimResult
        ``passed`` is True when the check, as it should, *fails* cleanly
        (gives False) under the change: the check can tell the sentence from
        its opposite. A check that still holds, or cannot be evaluated,
        gives ``passed`` False.
    """
    change = claim.false_when
    check = replaced_check(claim.check, change.replace) if change.replace else claim.check
    scene = claim_scene(lesson, claim)
    if change.settings:
        scene = scene.replace_many(change.settings)
    changed = tuple(change.settings) + ((("check", check),) if change.replace else ())
    result = _run(lesson, claim, check, scene, changed)
    return dataclasses.replace(result, passed=result.value is False and not result.error)


def check_lesson(lesson) -> list[ClaimResult]:
    """Evaluate every claim of ``lesson``, in order."""
    return [check_claim(lesson, claim) for claim in lesson.claims]
