"""phonglab.teaching: material for the lessons that is not part of the model.

:mod:`phonglab.teaching.mistakes` holds deliberately wrong versions of the
shading (no ``max(0, ·)`` on ``n·l``, specular without the ``n·l`` gate,
interpolated normals not renormalised, shininess 0, the mirror vector
turned round, light or view vector not normalised, the view vector from the
eye, attenuated ambient light, the spot cone in degrees, the power before
the max) that a lesson's
"common mistake" view shows next to the correct picture: each is the core's
reference kernel with one step replaced. This package imports the core only;
the core never imports it. To shade a scene with a mistake, use
``phonglab.scene.shade(scene, points, normals, mistake=name)``.
"""

from phonglab.teaching.mistakes import (
    MISTAKES,
    Mistake,
    get_mistake,
    no_clamp_diffuse,
    ungated_specular,
    unnormalised_normals,
    zero_shininess,
    reflect_wrong_way,
    unnormalised_light,
    unnormalised_view,
    view_from_eye,
    attenuated_ambient,
    spot_cutoff_in_degrees,
    power_before_max,
)

__all__ = [
    "MISTAKES",
    "Mistake",
    "get_mistake",
    "no_clamp_diffuse",
    "ungated_specular",
    "unnormalised_normals",
    "zero_shininess",
    "reflect_wrong_way",
    "unnormalised_light",
    "unnormalised_view",
    "view_from_eye",
    "attenuated_ambient",
    "spot_cutoff_in_degrees",
    "power_before_max",
]
