"""The words on a figure: sweep labels, the terms' formulas, and the band that names a common mistake.

A figure that shows a lesson's common mistake (a name from
:data:`phonglab.teaching.MISTAKES`) carries a band at the top: a red
heading, the wrong line of code next to the right one, and a note when the
mistake cannot show in the scene's interpolation mode.
"""

from __future__ import annotations

import re

import numpy as np

from phonglab.render import shading
from phonglab.render.layout import unit
from phonglab.render.text import fit_width, wrap
from phonglab.scene.model import show_value

#: how sweep labels name the common fields
FIELD_SYMBOLS = {
    "material.ka": "$k_a$",
    "material.kd": "$k_d$",
    "material.ks": "$k_s$",
    "material.emission": "$k_e$",
    "material.shininess": r"$\alpha$",
    "material.opacity": "opacity",
    "geometry.resolution": "resolution",
}
#: fields whose values are names: the label shows the value alone
NAMED_FIELDS = ("interpolation", "model", "geometry.kind", "geometry.name")
#: colours of the mistake labels: wrong (red), right (green), notes (grey)
WRONG_COLOR = "#b71c1c"
RIGHT_COLOR = "#1b5e20"
NOTE_COLOR = "#424242"
#: the label box of a correct panel, and of a panel the mistake changes
LABEL_BOX = (0, 0, 0, 0.45)
WRONG_LABEL_BOX = (0.72, 0.11, 0.11, 0.85)
RIGHT_LABEL_BOX = (0.11, 0.37, 0.13, 0.85)


def plain(value) -> str:
    """A sweep value as text: a name as it is, a number or vector as the scene files write it."""
    return value if isinstance(value, str) else show_value(value)


def sweep_label(path: str, value) -> str:
    """How a sweep value is written on the grid: ``$k_s$ = 0.5``, ``roughness = 0.1``, ``pixel``."""
    if path in NAMED_FIELDS and isinstance(value, str):
        return value
    return f"{field_name(path)} = {plain(value)}"


def field_name(path: str) -> str:
    """A field as a figure names it: its symbol (``$k_s$``), or words (``roughness``, ``light 1 intensity``).

    Paths the figure has no words for are written as they are.
    """
    if path in FIELD_SYMBOLS:
        return FIELD_SYMBOLS[path]
    light = re.fullmatch(r"lights\[(\d+)\]\.([a-z_]+)", path)
    if light:
        return f"light {light.group(1)} {light.group(2).replace('_', ' ')}"
    part = re.fullmatch(r"(?:material|camera)\.([a-z_]+)", path)
    if part:
        return part.group(1).replace("_", " ")
    return path.replace("_", " ") if re.fullmatch(r"[a-z_]+", path) else path


def wrong_term_labels(mistake: str, spec: str = r"\max(0,\,r\cdot v)") -> dict[str, str]:
    """The terms a mistake changes, each with the formula it wrongly computes.

    Parameters
    ----------
    mistake : str
        A name from :data:`phonglab.teaching.MISTAKES`.
    spec : str
        The specular base of the scene's model in LaTeX (``\\max(0, r·v)`` or
        ``\\max(0, n·h)``), without the exponent.

    Returns
    -------
    dict
        term (``"diffuse"``, ``"specular"``, ``"color"``) -> label text; the
        sum is always among them. A mistake not listed here changes the sum only.
    """
    labels = {
        "no-clamp-diffuse": {"diffuse": r"$k_d I_d\,(n\cdot l)$, negative on the dark side"},
        "ungated-specular": {"specular": rf"$k_s I_s {spec}^{{\alpha}}$, no $n\cdot l > 0$ gate"},
        "unnormalised-normals": {"diffuse": r"$k_d I_d \max(0,\,n\cdot l)$, $|n| < 1$",
                                 "specular": rf"$k_s I_s {spec}^{{\alpha}}$, $|n| < 1$"},
        "zero-shininess": {"specular": rf"$k_s I_s {spec}^0$ = $k_s I_s$ where lit"},
    }.get(mistake, {})
    return {**labels, "color": "the sum of the wrong terms" if labels else "the wrong sum"}


def ambient_value(scene) -> str:
    """The scene's constant ambient term :math:`k_a \\circ I_a` as text: ``0.02``, or ``(0.08, 0.03, 0.02)``.

    Taken from the core (one shaded point), so it is the value the ambient
    panel shows; one number when the three channels agree.
    """
    point = np.array([[0.0, 0.0, 1.0]])
    ambient = np.asarray(shading.shade(scene, point, point).ambient, dtype=float).reshape(-1, 3)[0]
    if np.allclose(ambient, ambient[0], rtol=0, atol=5e-4):
        return f"{ambient[0]:.3g}"
    return "(" + ", ".join(f"{c:.3g}" for c in ambient) + ")"


# ---------------------------------------------------------------------------
# Phong beside Cook–Torrance

#: the models the side-by-side view compares, in its order, and their labels
COMPARED_MODELS = (("phong", "Phong"), ("cook-torrance", "Cook–Torrance"))


def model_label(scene, model: str) -> str:
    """A panel's label: the model and the material parameters its lobe uses.

    The exported figure draws it over its panel; the page shows it as text
    under its picture (``app/compare_panel.py``).
    """
    m = scene.material
    if model == "cook-torrance":
        return f"Cook–Torrance: roughness {m.roughness:g}, metallic {m.metallic:g}"
    return f"{dict(COMPARED_MODELS).get(model, 'Blinn-Phong')}: α = {m.shininess:g}"


# ---------------------------------------------------------------------------
# the mistake's band


def mistake_caption(mistake: str, interpolation: str, heading: str,
                    heading_kind: str = "heading") -> list[tuple[str, str]]:
    """The lines of a mistake's band: ``(kind, text)``.

    Kinds: ``heading`` (red) or ``title`` (dark) for the first line, then
    ``wrong``, ``right`` (the two lines of code) and ``note``. The note is
    there only when the mistake cannot show in ``interpolation`` (see
    :func:`phonglab.render.shading.mistake_note`).
    """
    m = shading.get_mistake(mistake)
    lines = [(heading_kind, heading), ("wrong", f"wrong: {m.wrong}"), ("right", f"right: {m.right}")]
    note = shading.mistake_note(mistake, interpolation)
    if note:
        lines.append(("note", note))
    return lines


#: how each kind of band line is drawn: colour, matplotlib font options, size relative to the unit
BAND_STYLES = {
    "heading": (WRONG_COLOR, {"weight": "bold"}, 1.05),
    "title": ("#212121", {"weight": "bold"}, 1.05),
    "wrong": (WRONG_COLOR, {"family": "monospace"}, 0.8),
    "right": (RIGHT_COLOR, {"family": "monospace"}, 0.8),
    "note": (NOTE_COLOR, {"style": "italic"}, 0.8),
}
#: the most of the figure's height the band may take before its text is made smaller
BAND_MAX_FRACTION = 0.35


def mistake_banner(mistake, interpolation, size, heading, heading_kind="heading"):
    """A ``band(fig) -> pixels`` drawing the mistake's lines at the top of a figure (see :func:`draw_band`)."""
    lines = mistake_caption(mistake, interpolation, heading, heading_kind)
    return lambda fig: draw_band(fig, size, lines)


def draw_band(fig, size, lines) -> int:
    """Draw ``lines`` centred at the top of ``fig``, each wrapped to the width; return the band's height.

    The text is made smaller (at most four times) while the band would take
    more than :data:`BAND_MAX_FRACTION` of the figure's height.
    """
    W, H = size
    u = unit(size)
    pad = 0.4 * u
    renderer = fig.canvas.get_renderer()
    scale = 1.0
    for attempt in range(5):
        drawn = []
        y = pad
        for kind, text in lines:
            color, style, relative = BAND_STYLES[kind]
            fs = u * 0.72 * relative * scale
            for piece in wrap(fig, renderer, text, W - 2 * pad, fs, style):
                t = fig.text(0.5, 1 - y / H, piece, ha="center", va="top", fontsize=fs, color=color, **style)
                fit_width(t, renderer, W - 2 * pad)  # a single word wider than the figure
                drawn.append(t)
                y += t.get_window_extent(renderer).height + 0.12 * u * scale
            y += 0.12 * u * scale
        if y <= BAND_MAX_FRACTION * H or attempt == 4:
            return int(np.ceil(y))
        for t in drawn:
            t.remove()
        scale *= 0.8
    raise AssertionError("unreachable")
