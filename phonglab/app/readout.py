"""The numbers at the probe point, and the equation with them substituted.

Everything here comes from the core: the vectors and cosines from
:func:`phonglab.core.vectors`, the terms from :func:`phonglab.scene.shade`
at the single probe point. This module only formats them (as MathML through
:func:`phonglab.app.text.mathml`).

With a common mistake shown in the picture, the numbers are the ones the
mistaken code computes (:func:`phonglab.scene.shade` with ``mistake=``, the
same call that coloured the mesh), and each term that differs carries the
correct value and the wrong line of code beside the right one.

The numbers are linear light, as the model computes them; the colour
swatches are encoded for the display as the picture is (the scene's
``display`` and ``exposure``, :func:`phonglab.core.display.display_bytes`).

With more than one directed light, the dot products and the worked equation
belong to one light, the one whose vectors are drawn: the readout names it
("light 1"), shows that light's own diffuse and specular beside its n·l and
r·v (or n·h), and ends the equation with the parts that add up to the total
(the ambient with light 1, what each other light adds, the total).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from phonglab import core
from phonglab.app.text import mathml
from phonglab.core.display import display_bytes
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


#: said once beside the numbers: they are the model's, the picture is encoded for the screen
DISPLAY_NOTES = {
    "srgb": "Numbers are linear light; the picture and the swatches are sRGB-encoded.",
    "linear": "Numbers are linear light; the picture and the swatches show them raw (display = linear, no sRGB curve).",
}


#: said once when the picture does not shade each pixel: the numbers are exact at the probe, the picture is not
INTERPOLATION_NOTES = {
    "flat": "Numbers: the model evaluated exactly at the probe; the picture shows one colour per face (flat).",
    "gouraud": "Numbers: the model evaluated exactly at the probe; the picture interpolates vertex colours (Gouraud).",
}


def _rgb_text(rgb) -> str:
    return "(" + ", ".join(f"{float(c):.3f}" for c in rgb) + ")"


def swatch_hex(scene, rgb) -> str:
    """A linear colour as the ``#rrggbb`` the display shows (the scene's display encoding and exposure)."""
    values = display_bytes(np.asarray(rgb, dtype=np.float64), encoding=scene.display, exposure=scene.exposure)
    return "#" + "".join(f"{int(c):02x}" for c in values)


def _differs(a, b) -> bool:
    return bool(np.any(np.abs(np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)) > 5e-4))


def _parts(scene, p, n, light_index, part, total, mistake) -> list[tuple[str, np.ndarray]]:
    """``(name, rgb)``: the shown light with the ambient, what each other directed light adds, and the total.

    Each other light adds what the core computes with it and the ambient lights,
    less the ambient lights alone. Where a mistake makes the lights' sum differ
    from the total (the attenuated ambient, say), the other lights are given as
    one part, the total less the shown light's, so that the parts always add up.
    """
    ambients = tuple(light for light in scene.lights if isinstance(light, core.AmbientLight))
    others = [i for i, light in enumerate(scene.lights)
              if i != light_index and not isinstance(light, core.AmbientLight)]
    alone = shade(dataclasses.replace(scene, lights=ambients), p, n, mistake=mistake).color[0]
    adds = [(f"light {i} adds",
             shade(dataclasses.replace(scene, lights=ambients + (scene.lights[i],)), p, n, mistake=mistake).color[0]
             - alone) for i in others]
    if _differs(part.color[0] + sum(rgb for _, rgb in adds), total.color[0]):
        adds = [("the other lights add" if len(others) > 1 else f"light {others[0]} adds",
                 total.color[0] - part.color[0])]
    glow = "emission + " if any(part.emission[0]) else ""
    return [(f"{glow}ambient + light {light_index}", part.color[0]), *adds, ("total", total.color[0])]


def probe_readout(scene, point, normal, vectors, light_index, *, scene_plan=None, mistake=None) -> dict:
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
    mistake : str, optional
        The common mistake the picture shows (a name from
        :data:`phonglab.teaching.MISTAKES`): the terms and the equation's
        results are then the mistaken code's.

    Returns
    -------
    dict
        ``point``, ``dots`` (list of {name, html, value}), ``terms`` (list of
        {name, value, hex}, with ``correct`` and ``correct_hex`` where a
        mistake changes the term), ``equation`` (MathML), ``notes`` (list of
        str; in flat and Gouraud mode the last one says the numbers are exact
        at the probe while the picture is not, :data:`INTERPOLATION_NOTES`), ``vectors`` (letter -> "(x, y, z)"), ``display_note``, and
        ``mistake`` (None or {name, title, wrong, right}), ``light_name``
        (``"light 1"`` when the scene has more than one directed light, else
        None) and ``parts`` (with more than one directed light: {name, value,
        hex} for the ambient with the shown light, what each other light adds,
        and the total; else empty). With more than one directed light, the dot
        n·l carries the shown light's diffuse and r·v (n·h for Blinn-Phong)
        its specular as ``term`` ({name, value, hex}).
    """
    p = np.asarray(point, dtype=np.float64).reshape(1, 3)
    n = np.asarray(normal, dtype=np.float64).reshape(1, 3)
    correct = shade(scene, p, n, scene_plan=scene_plan)
    # with a mistake on, the numbers that made the picture: the same call as the mesh's colours
    total = correct if mistake is None else shade(scene, p, n, mistake=mistake)
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
        "light_name": None,
        "parts": [],
        "display_note": DISPLAY_NOTES[scene.display],
        "mistake": None,
    }
    if mistake is not None:
        from phonglab.teaching import get_mistake

        m = get_mistake(mistake)
        out["mistake"] = {"name": m.name, "title": m.title, "wrong": m.wrong, "right": m.right}
    for name in ("ambient", "diffuse", "specular", "emission", "color"):
        rgb = getattr(total, name)[0]
        if name == "emission" and not any(rgb):
            continue
        term = {"name": "total" if name == "color" else name, "value": _rgb_text(rgb), "hex": swatch_hex(scene, rgb)}
        right = getattr(correct, name)[0]
        if mistake is not None and _differs(rgb, right):
            # the correct value next to the mistaken one, with the line of code that differs
            term.update(correct=_rgb_text(right), correct_hex=swatch_hex(scene, right),
                        wrong=out["mistake"]["wrong"], right=out["mistake"]["right"])
        out["terms"].append(term)
    if vectors is None:
        out["notes"].append("No point, directional or spot light: only the ambient term is lit.")
        ia = [sum(light.ambient_rgb[i] for light in ambients) for i in range(3)]
        out["equation"] = mathml(
            rf"I = k_a I_a = {_rgb_tex(material.ka)} \cdot {_rgb_tex(ia)} = {_rgb_tex(total.color[0])}",
            display=True,
        )
        if scene.interpolation in INTERPOLATION_NOTES:
            out["notes"].append(INTERPOLATION_NOTES[scene.interpolation])
        return out
    blinn = scene.model == "blinn-phong"
    out["vectors"] = {k: _vec_text(getattr(vectors, k)) for k in "nlrvh"}
    out["dots"] = [
        {"name": "n·l", "tex": mathml(r"n\cdot l"), "value": f"{vectors.nl:+.3f}"},
        {"name": "r·v", "tex": mathml(r"r\cdot v"), "value": f"{vectors.rv:+.3f}"},
        {"name": "n·h", "tex": mathml(r"n\cdot h"), "value": f"{vectors.nh:+.3f}"},
    ]
    light = scene.lights[light_index]
    # the shown light's own terms, from the core (the mistaken code with a mistake on), with the ambient lights
    one = dataclasses.replace(scene, lights=tuple(ambients) + (light,))
    part = shade(one, p, n, mistake=mistake)
    several = len(scene.lights) - len(ambients) > 1
    if several:
        # which light the dots and the equation belong to, and its own terms beside its dots
        out["light_name"] = f"light {light_index}"
        parts = _parts(scene, p, n, light_index, part, total, mistake)
        out["parts"] = [{"name": name, "value": _rgb_text(rgb), "hex": swatch_hex(scene, rgb)} for name, rgb in parts]
        specular_dot = "n·h" if blinn else "r·v"
        for dot in out["dots"]:
            term = {"n·l": "diffuse", specular_dot: "specular"}.get(dot["name"])
            if term is not None:
                rgb = getattr(part, term)[0]
                dot["term"] = {"name": term, "value": _rgb_text(rgb), "hex": swatch_hex(scene, rgb)}
    f = vectors.attenuation * vectors.spot
    ia = [sum(a.ambient_rgb[i] for a in ambients) for i in range(3)]
    cosine, cos_tex = (vectors.nh, r"n\cdot h") if blinn else (vectors.rv, r"r\cdot v")
    alpha = material.shininess
    ka, kd, ks = (_rgb_tex(c) for c in (material.ka, material.kd, material.ks))
    f_tex, nl_tex = _num(f, 3), _num(max(0.0, vectors.nl), 3)
    # the substituted numbers the mistaken code uses where its line differs
    if mistake == "no-clamp-diffuse":
        nl_tex = _num(vectors.nl, 3)
    elif mistake == "zero-shininess":
        alpha = 0.0
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
    if not several:
        rows.append(("sum", rf"I = {_rgb_tex(part.color[0], 3)}"))
    else:
        # the parts that add up to the total: the ambient with this light, each other light, the sum
        *shown, (_, whole) = parts
        glow = "k_e + " if any(part.emission[0]) else ""
        rows.append((out["light_name"], rf"{glow}k_a I_a + \text{{{out['light_name']}}} = {_rgb_tex(part.color[0], 3)}"))
        rows += [(name.removesuffix(" adds") if name.startswith("light") else "others",
                  rf"\text{{{name}}}\ {_rgb_tex(rgb, 3)}") for name, rgb in shown[1:]]
        rows.append(("total", "I = " + " + ".join(_rgb_tex(rgb, 3) for _, rgb in shown)
                     + rf" = {_rgb_tex(whole, 3)}"))
    out["equation"] = "".join(
        f'<div class="eq-row"><span class="eq-label">{label}</span>{mathml(tex)}</div>' for label, tex in rows
    )
    if several:
        out["equation"] = (f'<div class="phonglab-eq-head">Worked for {out["light_name"]} (its vectors are drawn) '
                           "with the ambient light; the last rows add the other lights.</div>" + out["equation"])
    if vectors.nl <= 0:
        who, its = (f"{out['light_name']} is", "its ") if several else ("the light is", "")
        out["notes"].append(f"n·l ≤ 0: {who} behind the surface here, so "
                            + (f"{its}diffuse and specular are 0." if mistake is None else
                               f"correct code gives {its}diffuse and specular 0; the mistaken code gives diffuse "
                               f"{_rgb_text(part.diffuse[0])} and specular {_rgb_text(part.specular[0])}."))
    if mistake is not None:
        changed = [t["name"] for t in out["terms"] if "correct" in t]
        out["notes"].insert(0, f"Deliberately wrong ({out['mistake']['title']}): these are the mistaken code's "
                               "numbers, the ones that made the picture"
                            + (f"; {', '.join(changed)} differ from the correct values." if changed
                               else "; here they equal the correct ones."))
    if f != 1.0:
        parts = []
        if vectors.distance is not None:
            parts.append(f"distance {vectors.distance:.2f}, attenuation {vectors.attenuation:.3f}")
        if isinstance(light, core.SpotLight):
            parts.append(f"spot factor {vectors.spot:.3f}")
        out["notes"].append((f"For {out['light_name']}, f = " if several else "f = ") + ", ".join(parts) + ".")
    if vectors.flipped:
        out["notes"].append("Two-sided lighting flipped the normal: it faced away from the eye.")
    if scene.interpolation in INTERPOLATION_NOTES:
        out["notes"].append(INTERPOLATION_NOTES[scene.interpolation])
    return out
