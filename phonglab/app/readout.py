"""The numbers at the probe point, and the equation with them substituted.

Everything here comes from the core: the vectors and cosines from
:func:`phonglab.core.vectors`, the terms from :func:`phonglab.scene.shade`
at the single probe point. This module only formats them (as MathML through
:func:`phonglab.app.text.mathml`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from phonglab import core
from phonglab.app.text import mathml
from phonglab.scene import shade


def _num(x: float, digits: int = 2) -> str:
    text = f"{x:.{digits}f}"
    return "0" + text[2:] if text.startswith("-0") and float(text) == 0 else text


def _alpha(alpha: float) -> str:
    """The shininess as an exponent: whole numbers without decimals."""
    return f"{alpha:.0f}" if abs(alpha - round(alpha)) < 5e-3 or alpha >= 100 else f"{alpha:.2f}"


def _rgb_tex(rgb, digits: int = 2) -> str:
    """A colour as one number when grey, else as a triple."""
    rgb = [float(c) for c in rgb]
    if max(rgb) - min(rgb) < 0.5 * 10**-digits:
        return _num(rgb[0], digits)
    return r"\left(" + ", ".join(_num(c, digits) for c in rgb) + r"\right)"


def _vec_text(v, digits: int = 3) -> str:
    return "(" + ", ".join(f"{float(c):+.{digits}f}" for c in v) + ")"


def probe_readout(scene, point, normal, vectors, light_index, *, scene_plan=None) -> dict:
    """The readout beside the view, as plain data.

    Parameters
    ----------
    scene : Scene
    point, normal : (3,) arrays
        The probe and the unit normal there.
    vectors : core ProbeVectors or None
        From the view (None when the scene has no directed light).
    light_index : int or None
        The light the vectors refer to.
    scene_plan : phonglab.scene.ScenePlan, optional
        The scene's plan when it is already made (:func:`phonglab.scene.plan`).

    Returns
    -------
    dict
        ``point``, ``dots`` (list of {name, html, value}), ``terms`` (list of
        {name, value, hex}), ``equation`` (MathML), ``notes`` (list of str),
        ``vectors`` (letter -> "(x, y, z)").
    """
    p = np.asarray(point, dtype=np.float64).reshape(1, 3)
    n = np.asarray(normal, dtype=np.float64).reshape(1, 3)
    total = shade(scene, p, n, scene_plan=scene_plan)
    material = scene.material
    ambients = [light for light in scene.lights if isinstance(light, core.AmbientLight)]
    out = {
        "point": _vec_text(p[0]),
        "dots": [],
        "terms": [],
        "equation": "",
        "notes": [],
        "vectors": {},
        "light": light_index,
    }
    for name, values in (("ambient", total.ambient), ("diffuse", total.diffuse), ("specular", total.specular),
                         ("emission", total.emission), ("total", total.color)):
        rgb = [float(c) for c in values[0]]
        if name == "emission" and not any(rgb):
            continue
        out["terms"].append({"name": name, "value": "(" + ", ".join(f"{c:.3f}" for c in rgb) + ")",
                             "hex": "#" + "".join(f"{int(round(min(max(c, 0), 1) * 255)):02x}" for c in rgb)})
    if vectors is None:
        out["notes"].append("No point, directional or spot light: only the ambient term is lit.")
        ia = [sum(light.ambient_rgb[i] for light in ambients) for i in range(3)]
        out["equation"] = mathml(
            rf"I = k_a I_a = {_rgb_tex(material.ka)} \cdot {_rgb_tex(ia)} = {_rgb_tex(total.color[0])}",
            display=True,
        )
        return out
    blinn = scene.model == "blinn-phong"
    out["vectors"] = {k: _vec_text(getattr(vectors, k)) for k in "nlrvh"}
    out["dots"] = [
        {"name": "n·l", "tex": mathml(r"n\cdot l"), "value": f"{vectors.nl:+.3f}"},
        {"name": "r·v", "tex": mathml(r"r\cdot v"), "value": f"{vectors.rv:+.3f}"},
        {"name": "n·h", "tex": mathml(r"n\cdot h"), "value": f"{vectors.nh:+.3f}"},
    ]
    light = scene.lights[light_index]
    # the shown light's own terms, from the core, with the ambient lights
    one = dataclasses.replace(scene, lights=tuple(ambients) + (light,))
    part = shade(one, p, n)
    f = vectors.attenuation * vectors.spot
    ia = [sum(a.ambient_rgb[i] for a in ambients) for i in range(3)]
    cosine, cos_tex = (vectors.nh, r"n\cdot h") if blinn else (vectors.rv, r"r\cdot v")
    alpha = material.shininess
    ka, kd, ks = (_rgb_tex(c) for c in (material.ka, material.kd, material.ks))
    f_tex, nl_tex = _num(f, 3), _num(max(0.0, vectors.nl), 3)
    # one row per term: the symbols, the numbers, the core's value
    rows = [
        ("model", rf"I = k_a I_a + f\left[k_d I_d \max(0, n\cdot l) + k_s I_s \max(0, {cos_tex})^{{\alpha}}\right]"),
        ("ambient", rf"k_a I_a = {ka} \cdot {_rgb_tex(ia)} = {_rgb_tex(part.ambient[0], 3)}"),
        ("diffuse", rf"f\, k_d I_d \max(0, n\cdot l) = {f_tex} \cdot {kd} \cdot {_rgb_tex(light.diffuse_rgb)} "
                    rf"\cdot {nl_tex} = {_rgb_tex(part.diffuse[0], 3)}"),
        ("specular", rf"f\, k_s I_s \max(0, {cos_tex})^{{\alpha}} = {f_tex} \cdot {ks} \cdot "
                     rf"{_rgb_tex(light.specular_rgb)} \cdot {_num(max(0.0, cosine), 3)}^{{{_alpha(alpha)}}} "
                     rf"= {_rgb_tex(part.specular[0], 3)}"),
    ]
    if any(part.emission[0]):
        rows.append(("emission", rf"k_e = {_rgb_tex(part.emission[0], 3)}"))
    rows.append(("sum", rf"I = {_rgb_tex(part.color[0], 3)}"))
    out["equation"] = "".join(
        f'<div class="eq-row"><span class="eq-label">{label}</span>{mathml(tex)}</div>' for label, tex in rows
    )
    if vectors.nl <= 0:
        out["notes"].append("n·l ≤ 0: the light is behind the surface here, so diffuse and specular are 0.")
    if f != 1.0:
        parts = []
        if vectors.distance is not None:
            parts.append(f"distance {vectors.distance:.2f}, attenuation {vectors.attenuation:.3f}")
        if isinstance(light, core.SpotLight):
            parts.append(f"spot factor {vectors.spot:.3f}")
        out["notes"].append("f = " + ", ".join(parts) + ".")
    if vectors.flipped:
        out["notes"].append("Two-sided lighting flipped the normal: it faced away from the eye.")
    others = len(scene.lights) - len(ambients) - 1
    if others > 0:
        rest = total.color[0] - part.color[0]
        out["notes"].append(
            (f"{others} other lights add " if others > 1 else "1 other light adds ")
            + "(" + ", ".join(f"{c:.3f}" for c in rest) + f"), for a total of "
            + "(" + ", ".join(f"{c:.3f}" for c in total.color[0]) + ")."
        )
    return out
