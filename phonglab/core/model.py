"""Materials and lights: frozen, validated descriptions of what is shaded.

Validation happens once, here, when an object is made: every coefficient is a
finite number (or an RGB triple of them), never negative and never above its
upper limit (:data:`MAX_COEFFICIENT`, :data:`MAX_INTENSITY`,
:data:`MAX_EXPONENT`, :data:`MAX_ATTENUATION`); a bad value raises
:class:`InvalidValue` (a ``ValueError``) naming the field, the value and what is
allowed. The shading code trusts these objects and does not check again.

Why the upper limits
--------------------
The fast kernel works in float32, whose largest finite value is about
3.4·10³⁸. With every factor at its limit, the brightest colour a scene can
make, per channel, is

.. math:: k_e + k_a I_a + \\sum_{l=1}^{16} f_{max} (k_d I_{d,l} + k_s I_{s,l})
          \\le 10^3 + 10^3 \\cdot 16 \\cdot 10^9 + 16 \\cdot 10^{12} \\cdot 2 \\cdot 10^3 \\cdot 10^9
          \\approx 3.2 \\cdot 10^{25}

(``I = intensity × colour`` ≤ 10⁶ · 10³; at most 16 lights, the scene's limit;
the attenuation factor ``f`` is capped at :data:`ATTENUATION_MAX` = 10¹²; the
spot factor, ``max(0, n·l)`` and ``max(0, r·v)^α`` are at most 1). The display's
exposure (at most :data:`MAX_EXPOSURE`) makes that 3.2·10²⁸, and a sum over
every pixel of the largest figure (2²³ of them) 2.7·10³⁵: still finite, so no
product or sum the shading and display steps form overflows.
The exponents (shininess, a spot's fall-off) raise a number in [0, 1], which
cannot overflow; their limit is the float32 resolution of ``r·v`` next to 1
(steps of 2⁻²⁴): at α = 10⁶ the highlight's half-width, √(2 ln 2 / α) ≈ 1.2
mrad, is already only a few such steps (≈ 0.35 mrad) wide, so a larger α
draws nothing different. The attenuation coefficients multiply distances
(at most 3.5·10⁶ between two points within the scene's ±10⁶ coordinates):
``c d²`` ≤ 10⁶ · 1.2·10¹³ stays finite.

Directions follow the package convention: they point *away from the surface*,
so a :class:`DirectionalLight`'s ``direction`` points towards the light.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "MODELS",
    "PHONG_MODELS",
    "InvalidValue",
    "vec3",
    "Material",
    "Light",
    "AmbientLight",
    "PointLight",
    "DirectionalLight",
    "SpotLight",
    "light_from_homogeneous",
    "DISTANCE_FLOOR",
    "ATTENUATION_MAX",
    "MAX_COEFFICIENT",
    "MAX_INTENSITY",
    "MAX_EXPONENT",
    "MAX_ATTENUATION",
    "MAX_EXPOSURE",
    "limit_text",
]

#: The illumination models :func:`~phonglab.core.shade` evaluates; every layer takes the list from here.
MODELS = ("phong", "blinn-phong", "cook-torrance")
#: The models with a shininess exponent α: Phong's mirror-vector lobe and Blinn-Phong's half-vector lobe.
PHONG_MODELS = ("phong", "blinn-phong")

#: Attenuation uses ``max(d, DISTANCE_FLOOR)`` for the light's distance ``d``.
DISTANCE_FLOOR = 1e-6
#: The attenuation factor never exceeds this (its denominator is floored at the inverse).
ATTENUATION_MAX = 1e12

#: Largest ka, kd, ks, emission and light colour channel (color, diffuse, specular); see the module's Notes.
MAX_COEFFICIENT = 1e3
#: Largest light intensity.
MAX_INTENSITY = 1e6
#: Largest shininess α and spot fall-off exponent.
MAX_EXPONENT = 1e6
#: Largest size of an attenuation coefficient a, b or c.
MAX_ATTENUATION = 1e6
#: Largest display exposure (checked with the scene, which carries it).
MAX_EXPOSURE = 1e3

RGB = tuple[float, float, float]
Vec3 = tuple[float, float, float]


class InvalidValue(ValueError):
    """A value refused at the boundary.

    Attributes
    ----------
    field : str
        Where the value was given, e.g. ``"Material.kd"`` or ``"SpotLight.cutoff"``.
    value : object
        The value as given.
    allowed : str
        What would have been accepted.
    limit : float or None
        The upper limit the value passed, when that is what was wrong (None otherwise).
    """

    def __init__(self, field: str, value, allowed: str, *, limit: float | None = None):
        self.field, self.value, self.allowed, self.limit = field, value, allowed, limit
        super().__init__(f"{field}: {allowed}, got {_show(value)}")


def _show(value) -> str:
    try:
        return repr(tuple(value)) if not isinstance(value, (str, bytes)) else repr(value)
    except TypeError:
        return repr(value)


def limit_text(x: float) -> str:
    """A limit as a rule states it: ``1000``, ``1e6``.

    >>> limit_text(1e3), limit_text(1e6), limit_text(0.5)
    ('1000', '1e6', '0.5')
    """
    if x >= 1e4 and math.log10(x).is_integer():
        return f"1e{int(math.log10(x))}"
    return f"{x:g}"


def _number(where: str, value, *, minimum: float | None = 0.0, maximum: float | None = None,
            allowed: str | None = None) -> float:
    """A finite float, optionally >= minimum and <= maximum (past it, a refusal naming the range)."""
    text = allowed or ("a finite number" + (f" >= {minimum:g}" if minimum is not None else ""))
    if isinstance(value, bool):
        raise InvalidValue(where, value, f"must be {text}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidValue(where, value, f"must be {text}") from None
    if not math.isfinite(x) or (minimum is not None and x < minimum):
        raise InvalidValue(where, value, f"must be {text}")
    if maximum is not None and x > maximum:
        raise InvalidValue(where, value, f"must be a finite number in [{minimum:g}, {limit_text(maximum)}]",
                           limit=maximum)
    return x


def _rgb(where: str, value) -> RGB:
    """A scalar or an RGB triple of finite numbers in [0, MAX_COEFFICIENT], as a triple."""
    allowed = "must be a finite number >= 0 or an RGB triple of them"
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        x = _number(where, value, allowed=allowed[8:])
        items = [x]
    else:
        try:
            if isinstance(value, (str, bytes)):
                raise TypeError
            items = list(value)
            if len(items) != 3:
                raise TypeError
            items = [_number(where, x) for x in items]
        except (TypeError, InvalidValue):
            raise InvalidValue(where, value, allowed) from None
    if max(items) > MAX_COEFFICIENT:
        raise InvalidValue(where, value, f"must be a finite number in [0, {limit_text(MAX_COEFFICIENT)}] or an RGB "
                                         "triple of them", limit=MAX_COEFFICIENT)
    return (items[0],) * 3 if len(items) == 1 else tuple(items)  # type: ignore[return-value]


def vec3(where: str, value, *, nonzero: bool = False) -> Vec3:
    """Three finite numbers (any sign) as a tuple of floats: the one "3-vector" check.

    Parameters
    ----------
    where : str
        The field the value was given for, named in the error (``"PointLight.position"``).
    value : sequence of 3 numbers
    nonzero : bool, keyword-only
        Also refuse ``(0, 0, 0)`` (a direction must have one).

    Returns
    -------
    tuple of 3 floats

    Raises
    ------
    InvalidValue
        Naming ``where``, the value and what is allowed, for anything but three
        finite real numbers (booleans, strings, NaN and inf included).

    Examples
    --------
    >>> vec3("eye", [0, 0, 5])
    (0.0, 0.0, 5.0)
    >>> vec3("direction", (0, 0, 0), nonzero=True)
    Traceback (most recent call last):
    ...
    phonglab.core.model.InvalidValue: direction: must be 3 finite numbers, not all zero, got (0, 0, 0)
    """
    allowed = "must be 3 finite numbers" + (", not all zero" if nonzero else "")
    try:
        items = list(value)
    except TypeError:
        raise InvalidValue(where, value, allowed) from None
    if len(items) != 3:
        raise InvalidValue(where, value, allowed)
    out = []
    for x in items:
        if isinstance(x, bool):
            raise InvalidValue(where, value, allowed)
        try:
            f = float(x)
        except (TypeError, ValueError):
            raise InvalidValue(where, value, allowed) from None
        if not math.isfinite(f):
            raise InvalidValue(where, value, allowed)
        out.append(f)
    if nonzero and not any(out):
        raise InvalidValue(where, value, allowed)
    return tuple(out)  # type: ignore[return-value]


#: the former private name, kept for callers that import it
_vec3 = vec3


def _attenuation(where: str, value) -> Vec3:
    """Coefficients (a, b, c) with a + b d + c d² > 0 for every d >= DISTANCE_FLOOR."""
    allowed = (
        "must be (a, b, c) with a + b·d + c·d² > 0 at every distance d >= "
        f"{DISTANCE_FLOOR:g} (e.g. (1, 0, 0) none, (0, 0, 1) inverse square)"
    )
    try:
        a, b, c = vec3(where, value)
    except InvalidValue:
        raise InvalidValue(where, value, allowed) from None
    if max(abs(a), abs(b), abs(c)) > MAX_ATTENUATION:
        raise InvalidValue(where, value, f"must be (a, b, c) with every coefficient within "
                                         f"±{limit_text(MAX_ATTENUATION)}", limit=MAX_ATTENUATION)
    if c < 0 or (c == 0 and b < 0):
        raise InvalidValue(where, value, allowed)  # negative at large d
    # smallest value on [DISTANCE_FLOOR, inf): at the floor, or at the vertex -b / 2c
    d = DISTANCE_FLOOR if c == 0 else max(DISTANCE_FLOOR, -b / (2 * c))
    if not a + b * d + c * d * d > 0:
        raise InvalidValue(where, value, allowed)
    return (a, b, c)


@dataclass(frozen=True)
class Material:
    """Surface reflectance of the Phong model.

    Parameters
    ----------
    ka, kd, ks : float or RGB triple
        Ambient, diffuse and specular reflection coefficients, each in
        [0, :data:`MAX_COEFFICIENT`]; a scalar means the same value in every channel.
    shininess : float
        The specular exponent α in [0, :data:`MAX_EXPONENT`].
    emission : float or RGB triple, default 0
        Light the surface emits, ``k_e``.
    opacity : float in [0, 1], default 1
        Carried for rendering; the lighting does not use it.
    roughness : float in [0, 1], default 0.5
        Cook–Torrance only: the perceptual roughness, ``α_GGX = roughness²``
        (below :data:`~phonglab.core.microfacet.MIN_ROUGHNESS` it is raised to it).
    metallic : float in [0, 1], default 0
        Cook–Torrance only: 0 a dielectric (``F₀ = 0.04``), 1 a metal
        (``F₀ = k_d``, no diffuse term); values between mix the two.

    Notes
    -----
    .. math:: I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[k_d \\circ I_{d,l}
              \\max(0, n\\cdot l) + k_s \\circ I_{s,l} \\max(0, r\\cdot v)^{\\alpha}\\right]

    ``∘`` multiplies per RGB channel. Under ``model="cook-torrance"``
    (:mod:`phonglab.core.microfacet`) ``k_d`` is the base colour, ``k_s``
    scales the specular lobe (1 is physical) and ``shininess`` is not used;
    the Phong models do not use ``roughness`` or ``metallic``.
    """

    ka: RGB
    kd: RGB
    ks: RGB
    shininess: float
    emission: RGB = (0.0, 0.0, 0.0)
    opacity: float = 1.0
    roughness: float = 0.5
    metallic: float = 0.0

    def __post_init__(self):
        for name in ("ka", "kd", "ks", "emission"):
            object.__setattr__(self, name, _rgb(f"Material.{name}", getattr(self, name)))
        object.__setattr__(self, "shininess", _number("Material.shininess", self.shininess, maximum=MAX_EXPONENT))
        for name in ("opacity", "roughness", "metallic"):
            where = f"Material.{name}"
            x = _number(where, getattr(self, name), allowed="a number in [0, 1]")
            if x > 1:
                raise InvalidValue(where, getattr(self, name), "must be a number in [0, 1]")
            object.__setattr__(self, name, x)


@dataclass(frozen=True)
class Light:
    """Base of all lights: a colour scaled by an intensity.

    ``diffuse`` and ``specular``, when given, replace ``color`` for that term,
    so a light can have separate diffuse and specular intensities. The
    effective intensities are ``I_d = intensity · (diffuse or color)`` and
    ``I_s = intensity · (specular or color)``.
    """

    color: RGB = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    diffuse: RGB | None = None
    specular: RGB | None = None

    def _validate_common(self):
        kind = type(self).__name__
        object.__setattr__(self, "color", _rgb(f"{kind}.color", self.color))
        object.__setattr__(self, "intensity", _number(f"{kind}.intensity", self.intensity, maximum=MAX_INTENSITY))
        for name in ("diffuse", "specular"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _rgb(f"{kind}.{name}", getattr(self, name)))

    def __post_init__(self):
        self._validate_common()

    @property
    def diffuse_rgb(self) -> RGB:
        """``I_d``: the intensity times the diffuse colour."""
        base = self.color if self.diffuse is None else self.diffuse
        return tuple(self.intensity * c for c in base)  # type: ignore[return-value]

    @property
    def specular_rgb(self) -> RGB:
        """``I_s``: the intensity times the specular colour."""
        base = self.color if self.specular is None else self.specular
        return tuple(self.intensity * c for c in base)  # type: ignore[return-value]

    @property
    def ambient_rgb(self) -> RGB:
        return tuple(self.intensity * c for c in self.color)  # type: ignore[return-value]

    @property
    def shines(self) -> bool:
        """Whether the light adds anything to the diffuse or specular term (``I_d`` or ``I_s`` not 0)."""
        return any(self.diffuse_rgb) or any(self.specular_rgb)


@dataclass(frozen=True)
class AmbientLight(Light):
    """Light arriving equally from everywhere, standing in for indirect light.

    Notes
    -----
    .. math:: I_{ambient} = k_a \\circ I_a, \\qquad I_a = \\sum \\mathrm{intensity} \\cdot \\mathrm{color}

    summed over the scene's ambient lights; the same at every point, with no
    direction (so it has no ``L`` and no specular part).
    """


@dataclass(frozen=True, kw_only=True)
class PointLight(Light):
    """A light at ``position`` shining in every direction.

    Notes
    -----
    .. math:: f = \\frac{1}{a + b\\,d + c\\,d^2}, \\quad d = \\max(|p_{light} - p|, 10^{-6})

    The coefficients must keep the denominator positive at every distance;
    the factor is capped at ``ATTENUATION_MAX`` = 1e12, so a light sitting on
    the surface stays finite.
    """

    position: Vec3
    attenuation: Vec3 = (1.0, 0.0, 0.0)

    def __post_init__(self):
        self._validate_common()
        kind = type(self).__name__
        object.__setattr__(self, "position", vec3(f"{kind}.position", self.position))
        object.__setattr__(self, "attenuation", _attenuation(f"{kind}.attenuation", self.attenuation))


@dataclass(frozen=True, kw_only=True)
class DirectionalLight(Light):
    """A light infinitely far away; ``direction`` points *towards* the light.

    Notes
    -----
    .. math:: l = \\frac{d}{|d|} \\text{ at every point}, \\qquad f = 1

    No attenuation: there is no distance. The homogeneous position
    ``(x, y, z, 0)`` describes the same light.
    """

    direction: Vec3

    def __post_init__(self):
        self._validate_common()
        object.__setattr__(
            self, "direction", vec3("DirectionalLight.direction", self.direction, nonzero=True)
        )


@dataclass(frozen=True, kw_only=True)
class SpotLight(PointLight):
    """A point light restricted to a cone around ``direction``.

    Parameters
    ----------
    direction : 3 floats
        The cone's axis, from the light outwards.
    cutoff : float
        Half-angle of the cone in degrees, in (0, 90], or exactly 180 for a
        plain point light.
    exponent : float
        Fall-off towards the rim, >= 0.

    Notes
    -----
    With ``s`` the unit axis and ``-l`` the direction from the light to the point,

    .. math:: f_{spot} = \\begin{cases} \\max(0, -l\\cdot s)^{e} & -l\\cdot s \\ge \\cos(\\mathrm{cutoff}) \\\\
              0 & \\text{otherwise} \\end{cases}

    A point exactly on the cone counts as inside (the ``>=`` test has a few
    ulps of slack). ``cutoff = 180`` makes the factor 1 everywhere, even
    straight behind the light.
    """

    direction: Vec3
    cutoff: float = 30.0
    exponent: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "direction", vec3("SpotLight.direction", self.direction, nonzero=True))
        allowed = "must be a half-angle in degrees in (0, 90], or 180 for a plain point light"
        cutoff = _number("SpotLight.cutoff", self.cutoff, minimum=None, allowed=allowed[8:])
        if not (0 < cutoff <= 90 or cutoff == 180):
            raise InvalidValue("SpotLight.cutoff", self.cutoff, allowed)
        object.__setattr__(self, "cutoff", cutoff)
        object.__setattr__(self, "exponent", _number("SpotLight.exponent", self.exponent, maximum=MAX_EXPONENT))

    @property
    def is_cone(self) -> bool:
        """False for cutoff 180, which is a plain point light."""
        return self.cutoff != 180


def light_from_homogeneous(position, **kwargs) -> PointLight | DirectionalLight:
    """A light from a homogeneous position ``(x, y, z, w)``.

    ``w = 1`` gives a :class:`PointLight` at ``(x, y, z)``; ``w = 0`` a
    :class:`DirectionalLight` towards ``(x, y, z)``. Any other ``w > 0`` is a
    point light at ``(x, y, z) / w``. Further keyword arguments go to the light.

    Notes
    -----
    .. math:: (x, y, z, w) \\mapsto \\begin{cases} p = (x, y, z) / w & w > 0 \\\\
              l = (x, y, z) / |(x, y, z)| & w = 0 \\end{cases}

    the point at infinity in direction ``(x, y, z)`` is the limit of point
    lights moved ever further that way.

    Examples
    --------
    >>> light_from_homogeneous((0, 0, 1, 0)).direction
    (0.0, 0.0, 1.0)
    """
    allowed = "must be (x, y, z, w) with finite numbers and w >= 0 (w = 0 directional)"
    try:
        items = [float(x) for x in position]
    except (TypeError, ValueError):
        raise InvalidValue("light.homogeneous", position, allowed) from None
    if len(items) != 4 or not all(math.isfinite(x) for x in items) or items[3] < 0:
        raise InvalidValue("light.homogeneous", position, allowed)
    x, y, z, w = items
    if w == 0:
        return DirectionalLight(direction=(x, y, z), **kwargs)
    return PointLight(position=(x / w, y / w, z / w), **kwargs)

