"""phonglab.core: the Phong illumination model in pure NumPy.

Every direction is a unit vector pointing *away from the surface point*:
``n`` the normal, ``l`` towards the light, ``v`` towards the eye,
``r = 2(n·l)n − l`` and ``h = normalize(l + v)``. Functions take ``(..., 3)``
arrays that broadcast over the leading axes and keep float32 as float32.
This package imports NumPy only: no PyVista, no trame, no file I/O.
"""

from .area import AREA_METHODS, AreaLight, area_diffuse, area_irradiance, polygon_irradiance
from .model import (
    ATTENUATION_MAX,
    DISTANCE_FLOOR,
    AmbientLight,
    DirectionalLight,
    InvalidValue,
    Light,
    Material,
    PointLight,
    SpotLight,
    light_from_homogeneous,
)
from .shading import MODELS, LightPlan, Plan, ProbeVectors, Shading, plan_effects, shade, vectors
from .vectors import SQUARING_MAX, dot, normalize, one_minus_cos, reflect

__all__ = [
    "ATTENUATION_MAX", "DISTANCE_FLOOR", "MODELS", "SQUARING_MAX",
    "AmbientLight", "DirectionalLight", "InvalidValue", "Light", "Material", "PointLight", "SpotLight",
    "light_from_homogeneous",
    "LightPlan", "Plan", "ProbeVectors", "Shading", "plan_effects", "shade", "vectors",
    "dot", "normalize", "one_minus_cos", "reflect",
    "AREA_METHODS", "AreaLight", "area_diffuse", "area_irradiance", "polygon_irradiance",
]
