"""phonglab.core: the Phong illumination model in pure NumPy.

Every direction is a unit vector pointing *away from the surface point*:
``n`` the normal, ``l`` towards the light, ``v`` towards the eye,
``r = 2(n·l)n − l`` and ``h = normalize(l + v)``. Functions take ``(..., 3)``
arrays that broadcast over the leading axes and keep float32 as float32.
This package imports NumPy only: no PyVista, no trame, no file I/O.

Modules, by job: :mod:`~phonglab.core.vectors` (unit vectors, dot, reflect,
the specular power), :mod:`~phonglab.core.model` (materials and lights),
:mod:`~phonglab.core.physics` (face-forward, attenuation, spot factor),
:mod:`~phonglab.core.reference` (the model, one light at a time, and the
:mod:`~phonglab.core.record` of what it used),
:mod:`~phonglab.core.plan` and :mod:`~phonglab.core.shading` (the fast
kernel), :mod:`~phonglab.core.probe` (the vectors at one point),
:mod:`~phonglab.core.area` (area lights), :mod:`~phonglab.core.microfacet`
(Cook–Torrance's terms), :mod:`~phonglab.core.furnace` (the white furnace)
and :mod:`~phonglab.core.shadows` (the shadow rays a ray caster above the
core tests).
"""

from .area import AREA_METHODS, AreaLight, area_diffuse, area_irradiance, polygon_irradiance
from .model import (
    ATTENUATION_MAX,
    DISTANCE_FLOOR,
    MODELS,
    PHONG_MODELS,
    AmbientLight,
    DirectionalLight,
    InvalidValue,
    Light,
    Material,
    PointLight,
    SpotLight,
    light_from_homogeneous,
    vec3,
)
from .physics import SPOT_SLACK_ULPS, attenuation, face_forward, facing_away, spot_cos_limit, spot_factor
from .plan import LightPlan, Plan, plan_effects
from .probe import ProbeVectors, vectors
from .record import LightRecord, Record, add_area_light, ambient_intensity
from .reference import Steps, lambert, shade_reference, specular_lobe
from .shading import Shading, shade
from .shadows import shadow_rays
from .vectors import SQUARING_MAX, dot, normalize, one_minus_cos, reflect

__all__ = [
    "ATTENUATION_MAX", "DISTANCE_FLOOR", "MODELS", "PHONG_MODELS", "SQUARING_MAX",
    "AmbientLight", "DirectionalLight", "InvalidValue", "Light", "Material", "PointLight", "SpotLight",
    "light_from_homogeneous", "vec3",
    "SPOT_SLACK_ULPS", "attenuation", "face_forward", "facing_away", "spot_cos_limit", "spot_factor",
    "LightPlan", "Plan", "ProbeVectors", "Shading", "plan_effects", "shade", "vectors",
    "Steps", "shade_reference", "lambert", "specular_lobe",
    "LightRecord", "Record", "add_area_light", "ambient_intensity",
    "dot", "normalize", "one_minus_cos", "reflect", "shadow_rays",
    "AREA_METHODS", "AreaLight", "area_diffuse", "area_irradiance", "polygon_irradiance",
]
