"""phonglab.teaching: material for the lessons that is not part of the model.

:mod:`phonglab.teaching.mistakes` holds deliberately wrong versions of the
shading (no ``max(0, ·)`` on ``n·l``, specular without the ``n·l`` gate,
interpolated normals not renormalised, shininess 0) that a lesson's
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
)

__all__ = [
    "MISTAKES",
    "Mistake",
    "get_mistake",
    "no_clamp_diffuse",
    "ungated_specular",
    "unnormalised_normals",
    "zero_shininess",
]
