"""What a kernel used: the record of the sum, and the sums the kernels share.

Directions point *away from the surface point*: ``n`` the normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``.

:func:`~phonglab.core.shade_reference` with ``trace=True`` returns a
:class:`Record` beside its :class:`~phonglab.core.Shading`: every vector,
factor, cosine, weight and term it computed, under the names of the lesson's
equation. A common mistake is that kernel with one step swapped, so its
record holds its own (wrong) intermediate values. Readers (the page's
readout, the arrows at the probe, the lessons' claims, the grader) format
the record; they compute no physics of their own.

The record is generic over the model. Each light's quantities are an ordered
mapping of named values (:attr:`LightRecord.values`), and each term is a
*formula* over those names (:attr:`LightRecord.terms`), so a model with other
quantities (a microfacet model's ``D``, ``G``, ``F``) records them under its
own names and its terms are shown by the same code.

Formulas
--------
A formula is a name (a key of the light's or the record's values), a number,
or a tuple ``(operator, *operands)``:

- ``("mul", a, b, ...)``: the product ``a b ...`` (per RGB channel);
- ``("add", a, b, ...)``: the sum;
- ``("sub", a, b)``: ``a − b``;
- ``("div", a, b)``: ``a / b``;
- ``("pow", a, b)``: ``a^b``;
- ``("max0", a)``: ``max(0, a)`` (0 for NaN, as ``np.fmax``);
- ``("if", (c1, c2, ...), a)``: ``a`` where every ``c > 0``, else 0 (a gate).

:func:`evaluate` computes a formula from the values, :func:`resolve` replaces
each gate by the branch it takes at one point. A replaceable step of the
reference kernel (:class:`~phonglab.core.Steps`) says which formula it
computes in its ``formula`` attribute; the record's terms are built from
them, so a wrong step shows its own formula.

Also here, because both kernels and the scene need them once:
:func:`ambient_intensity` (``I_a``, the sum over the ambient lights) and
:func:`add_area_light` (an area light's diffuse light added to a shading and
its record).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import numpy as np

from .area import area_diffuse, area_irradiance
from .model import AmbientLight
from .physics import face_forward
from .vectors import normalize

__all__ = ["LightRecord", "Record", "ambient_intensity", "add_area_light", "evaluate", "resolve", "names_in"]

#: operator -> how many operands it takes (None: any number)
OPERATORS = {"mul": None, "add": None, "sub": 2, "div": 2, "pow": 2, "max0": 1, "if": 2}


def ambient_intensity(lights) -> np.ndarray:
    """``I_a``: the ambient lights' intensities added up, shape (3,), float64.

    Only :class:`~phonglab.core.AmbientLight` adds ambient light; the sum is
    made in the lights' order, so every caller gets the same rounding.

    Examples
    --------
    >>> import phonglab as pl
    >>> ambient_intensity([pl.AmbientLight(intensity=0.25), pl.PointLight(position=(0, 0, 1)),
    ...                    pl.AmbientLight(color=(1, 0, 0), intensity=0.5)]).tolist()
    [0.75, 0.25, 0.25]
    """
    ia = np.zeros(3)
    for light in lights:
        if isinstance(light, AmbientLight):
            ia += light.ambient_rgb
    return ia


def _frozen(values: Mapping) -> Mapping:
    return MappingProxyType(dict(values))


@dataclass(frozen=True)
class LightRecord:
    """What the kernel used for one light, at every point.

    Attributes
    ----------
    index : int or None
        The light's position in the lights given; None for a scene's area
        light (:func:`add_area_light`).
    kind : str
        ``"point"``, ``"directional"``, ``"spot"`` or ``"area"``.
    values : mapping str -> ndarray
        The quantities in the order the kernel computed them, each of shape
        ``(...)`` (a scalar per point) or ``(..., 3)`` (a vector or an RGB
        triple per point). For Phong and Blinn-Phong: ``l``, ``d`` (distance),
        ``attenuation``, ``spot`` (the last three for point and spot lights),
        ``f``, ``n·l``, ``r``, ``r·v``, ``h``, ``n·h``, ``I_d``, ``I_s``,
        ``diffuse weight``, ``specular weight``, ``diffuse``, ``specular``
        and ``adds`` (diffuse + specular); with shadows, ``lit`` (True where
        the light reaches the point, False in its shadow).
    terms : mapping str -> formula
        ``"diffuse"`` and ``"specular"``: the formula each term was computed
        by, over the names of ``values`` and of the record's values.
    factors : mapping str -> formula
        Named factors of the terms that have a formula of their own, in the
        order they are shown before the terms (Cook–Torrance's ``D``, ``V``,
        ``F`` and ``k_D = (1 − F)(1 − m)``); empty for Phong. Each factor's
        value is in ``values`` under the same name.
    """

    index: int | None
    kind: str
    values: Mapping[str, np.ndarray]
    terms: Mapping[str, object]
    factors: Mapping[str, object] = dataclasses.field(default_factory=lambda: MappingProxyType({}))

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]


@dataclass(frozen=True)
class Record:
    """What :func:`~phonglab.core.shade_reference` used, term by term and light by light.

    Attributes
    ----------
    model : str
        The model whose sum this is.
    values : mapping str -> ndarray
        What every light shares, each of shape ``(...)`` or ``(..., 3)``:
        ``n`` (the normal used, turned towards the eye when two-sided),
        ``v``, ``n·v``, ``flipped`` (two-sided lighting turned ``n``),
        ``α``, ``k_a``, ``k_d``, ``k_s``, ``k_e``, ``I_a``, ``f_lamp`` (the
        first point or spot light's ``f``, when there is one), ``ambient`` and
        ``emission``.
    terms : mapping str -> formula
        ``"ambient"`` and ``"emission"``: how each was computed.
    lights : tuple of LightRecord
        One per light that is not ambient, in the lights' order (and the area
        light last, when one was added).
    """

    model: str
    values: Mapping[str, np.ndarray]
    terms: Mapping[str, object]
    lights: tuple[LightRecord, ...]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]

    def light(self, index: int | None) -> LightRecord:
        """The record of ``lights[index]`` (None: the area light)."""
        for lr in self.lights:
            if lr.index == index:
                return lr
        raise KeyError(f"no record of light {index!r}: recorded {[lr.index for lr in self.lights]}")

    def lookup(self, name: str, light: LightRecord | None = None) -> np.ndarray:
        """The value called ``name``: the light's own first, then the record's."""
        if light is not None and name in light.values:
            return light.values[name]
        return self.values[name]

    def at(self, index) -> Record:
        """The record at one point: every value indexed by ``index`` over the points' axes."""
        def pick(values):
            return _frozen({k: np.asarray(a)[index] for k, a in values.items()})

        return Record(self.model, pick(self.values), self.terms,
                      tuple(dataclasses.replace(lr, values=pick(lr.values)) for lr in self.lights))


def make_record(model, values, terms, lights) -> Record:
    """A :class:`Record` with read-only mappings (the kernels build it with this)."""
    return Record(model, _frozen(values), _frozen(terms), tuple(lights))


def make_light_record(index, kind, values, terms, factors=None) -> LightRecord:
    """A :class:`LightRecord` with read-only mappings."""
    return LightRecord(index, kind, _frozen(values), _frozen(terms), _frozen(factors or {}))


# ---------------------------------------------------------------------------
# formulas


def names_in(formula) -> list[str]:
    """The value names a formula reads, in order of appearance (each once)."""
    found = []

    def walk(node):
        if isinstance(node, str):
            if node not in found:
                found.append(node)
        elif isinstance(node, tuple):
            operator, *operands = node
            if operator == "if":
                conditions, inner = operands
                for c in conditions:
                    walk(c)
                walk(inner)
            else:
                for x in operands:
                    walk(x)

    walk(formula)
    return found


def _check(node) -> None:
    if isinstance(node, tuple):
        operator, *operands = node
        arity = OPERATORS.get(operator, -1)
        if arity == -1 or (arity is not None and len(operands) != arity):
            raise ValueError(f"formula: unknown operator or wrong operand count in {node!r}")


def evaluate(formula, lookup):
    """The value of ``formula``, reading names through ``lookup(name) -> array``.

    Scalars per point (shape ``(...)``) are applied to every RGB channel of an
    ``(..., 3)`` operand. A gate ``("if", conditions, a)`` is ``a`` where
    every condition is > 0 and 0 elsewhere.
    """
    def value(node):
        if isinstance(node, str):
            return np.asarray(lookup(node))
        if not isinstance(node, tuple):
            return np.asarray(node, dtype=np.float64)
        _check(node)
        operator, *operands = node
        if operator == "if":
            conditions, inner = operands
            open_ = np.logical_and.reduce([value(c) > 0 for c in conditions])
            x = value(inner)
            return np.where(_widen(open_, x), x, 0)
        xs = [value(x) for x in operands]
        xs = _aligned(xs)
        if operator == "mul":
            out = xs[0]
            for x in xs[1:]:
                out = out * x
            return out
        if operator == "add":
            out = xs[0]
            for x in xs[1:]:
                out = out + x
            return out
        if operator == "sub":
            return xs[0] - xs[1]
        if operator == "div":
            return xs[0] / xs[1]
        if operator == "pow":
            return xs[0] ** xs[1]
        return np.fmax(xs[0], 0)  # max0 (a NaN power, as np.fmax gives it, is 0)

    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return value(formula)


def _widen(mask, x):
    """A per-point mask against an RGB operand: one more axis."""
    return mask[..., None] if np.ndim(x) == np.ndim(mask) + 1 else mask


def _aligned(xs):
    """Per-point scalars given a channel axis when another operand is an RGB triple per point."""
    if len({np.ndim(x) for x in xs}) <= 1:
        return xs
    top = max(np.ndim(x) for x in xs)
    return [x[..., None] if 0 < np.ndim(x) == top - 1 else x for x in xs]


def resolve(formula, lookup):
    """``formula`` at one point with every gate replaced by the branch it takes (``a`` or 0).

    ``lookup(name)`` gives the value at that point. What a page shows as the
    worked formula: a closed gate makes its term 0.
    """
    if isinstance(formula, tuple):
        _check(formula)
        operator, *operands = formula
        if operator == "if":
            conditions, inner = operands
            if all(bool(np.all(np.asarray(lookup(c)) > 0)) for c in conditions):
                return resolve(inner, lookup)
            return 0
        return (operator, *(resolve(x, lookup) for x in operands))
    return formula


def bind(formula, names: Mapping[str, str]):
    """``formula`` with names renamed (a step's ``c`` becomes the model's ``r·v`` or ``n·h``)."""
    if isinstance(formula, str):
        return names.get(formula, formula)
    if isinstance(formula, tuple):
        operator, *operands = formula
        if operator == "if":
            conditions, inner = operands
            return ("if", tuple(bind(c, names) for c in conditions), bind(inner, names))
        return (operator, *(bind(x, names) for x in operands))
    return formula


# ---------------------------------------------------------------------------
# a scene's area light, added to a shading (and its record)


def add_area_light(shading, points, normals, *, material, light, method: str, samples: int, seed=0,
                   two_sided: bool = False, eye=None, view_direction=None, record: Record | None = None):
    """``shading`` with an area light's diffuse light added to its diffuse term and colour.

    Parameters
    ----------
    shading : Shading
        The point and spot lights' shading of ``points``.
    points, normals : array_like, shape (..., 3)
    material : Material
    light : AreaLight
    method, samples, seed
        How the light's integral is evaluated (:func:`~phonglab.core.area_diffuse`);
        a fixed seed keeps Monte Carlo noise in place from call to call.
    two_sided : bool
        Turn normals facing away from the eye towards it first, as the kernels do.
    eye, view_direction : 3 floats
        The viewer (only read when two-sided).
    record : Record, optional
        The record of ``shading``: the area light is added to it too, as a
        light of kind ``"area"`` with ``k_d``, ``I_d`` (its colour), ``E``
        (the irradiance) and ``diffuse``.

    Returns
    -------
    Shading, or (Shading, Record) when ``record`` is given.

    Notes
    -----
    .. math:: I_{diffuse} \\mathrel{+}= k_d \\circ c_{light}\\, E(x)

    Two-sided lighting turns the normal as :func:`~phonglab.core.face_forward`
    does, with ``v = eye − p`` (or the infinite viewer's direction).
    """
    normals = np.asarray(normals)
    if two_sided:  # the kernels' flip: normals facing away from the eye are turned towards it
        to_eye = (normalize(np.broadcast_to(view_direction, np.shape(points)))
                  if eye is None else np.subtract(eye, points))
        normals = face_forward(normals, to_eye)
    extra = area_diffuse(points, normals, material=material, light=light, method=method, samples=samples,
                         seed=seed)
    extra = extra.astype(shading.color.dtype, copy=False)
    shaded = dataclasses.replace(shading, diffuse=shading.diffuse + extra, color=shading.color + extra)
    if record is None:
        return shaded
    shape = np.shape(extra)
    kd = np.broadcast_to(np.asarray(material.kd, extra.dtype), shape)
    colour = np.broadcast_to(np.asarray(light.color, extra.dtype), shape)
    # E again, for the record (the same seed gives the same samples)
    e = area_irradiance(light, points, normals, method=method, samples=samples, seed=seed).astype(extra.dtype)
    values = {"k_d": kd, "I_d": colour, "E": np.broadcast_to(e, shape[:-1]), "diffuse": extra, "adds": extra}
    area = make_light_record(None, "area", values, {"diffuse": ("mul", "k_d", "I_d", "E")})
    return shaded, dataclasses.replace(record, lights=record.lights + (area,))

