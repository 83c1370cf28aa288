"""The numbers at the probe point, and the equation with them substituted.

Everything here is the core's record of the sum at the probe
(:func:`phonglab.scene.trace`: the reference kernel with ``trace=True``):
the vectors, the cosines, the light factors, each term and the formula it
was computed by. This module only formats them (the formulas through
:mod:`phonglab.app.equation`, as MathML through :func:`phonglab.app.text.mathml`);
it computes no physics, so every worked equation holds with its own numbers.

With a common mistake shown in the picture, the numbers are the ones the
mistaken code computes (its own record: the same kernel with one step
swapped, the code that coloured the mesh), its formulas are the mistaken
ones, and each term that differs carries the correct value and the wrong line
of code beside the right one.

The numbers are linear light, as the model computes them; the colour
swatches are encoded for the display as the picture is (the scene's
``display`` and ``exposure``, :func:`phonglab.core.display.display_bytes`).

With more than one light (an area light counts), the dot products and the
worked equation belong to one light, the one whose vectors are drawn: the
readout names it ("light 1"), shows that light's own diffuse and specular
beside its n·l and r·v (or n·h), and ends the equation with the parts that
add up to the total (the ambient with light 1, what each other light adds,
the total).
"""

from __future__ import annotations

import numpy as np

from phonglab.app import equation
from phonglab.app.text import mathml
from phonglab.app.wording import symbols_html
from phonglab.core.display import display_bytes
from phonglab.core.record import names_in, resolve
from phonglab.render import shadows
from phonglab.scene import trace


def _vec_text(v, digits: int = 3) -> str:
    return "(" + ", ".join(f"{float(c):+.{digits}f}" for c in v) + ")"


#: said once beside the numbers: they are the model's, the picture is encoded for the screen
DISPLAY_NOTES = {
    "srgb": "Numbers are linear light; the picture and the swatches are sRGB-encoded.",
    "linear": "Numbers are linear light; the picture and the swatches show them raw (display = linear, no sRGB curve).",
}


def display_note(scene) -> str:
    """:data:`DISPLAY_NOTES` for the scene's display, and its exposure when that is not 1.

    The swatches (and the picture) are drawn with the exposure applied, the
    numbers are not: at lesson 13's exposure 0.05 a specular of 1.402 shows
    as a dark swatch, and the note says why.
    """
    note = DISPLAY_NOTES[scene.display]
    if scene.exposure != 1:
        note = note.removesuffix(".") + f" after exposure ×{scene.exposure:g} (the numbers are not multiplied by it)."
    return note


#: said once when the picture does not shade each pixel: the numbers are exact at the probe, the picture is not
INTERPOLATION_NOTES = {
    "flat": "Numbers: the model evaluated exactly at the probe; the picture shows one colour per face (flat).",
    "gouraud": "Numbers: the model evaluated exactly at the probe; the picture interpolates vertex colours (Gouraud).",
}


#: a factor's row label where its recorded name is not the one the lesson writes
FACTOR_LABELS = {"k_D": "(1 − F)(1 − m)"}


def _rgb_text(rgb) -> str:
    return "(" + ", ".join(f"{float(c):.3f}" for c in rgb) + ")"


def swatch_hex(scene, rgb) -> str:
    """A linear colour as the ``#rrggbb`` the display shows (the scene's display encoding and exposure)."""
    return _hexes(scene, [rgb])[0]


def _hexes(scene, colours) -> list[str]:
    """:func:`swatch_hex` of each linear colour, encoded together in one call."""
    rows = display_bytes(np.asarray(colours, dtype=np.float64).reshape(-1, 3), encoding=scene.display,
                         exposure=scene.exposure)
    return ["#%02x%02x%02x" % tuple(int(c) for c in row) for row in rows]


class _Swatches:
    """The readout's colour swatches: asked for one by one, encoded together (:meth:`paint`)."""

    def __init__(self, scene):
        self.scene = scene
        self._wanted: list[tuple[dict, str, object]] = []

    def put(self, target: dict, key: str, rgb) -> None:
        """``target[key]`` will be the swatch of ``rgb`` (its place in ``target`` kept)."""
        target[key] = None
        self._wanted.append((target, key, rgb))

    def paint(self) -> None:
        if self._wanted:
            for (target, key, _), text in zip(self._wanted, _hexes(self.scene, [rgb for _, _, rgb in self._wanted])):
                target[key] = text


def _differs(a, b) -> bool:
    return bool(np.any(np.abs(np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)) > 5e-4))


def _name(light) -> str:
    """How the page names a recorded light: ``light 1``, or ``area light``."""
    return "area light" if light.index is None else f"light {light.index}"


def _sum_tex(values) -> str:
    """Recorded values added up, as LaTeX (a negative one in brackets)."""
    texts = [equation.value(x) for x in values]
    return " + ".join(rf"\left({t}\right)" if t.startswith("-") and i else t for i, t in enumerate(texts))


def _worked(formula, lookup, result) -> str:
    """``symbols = numbers = result`` for one recorded formula (the gates resolved by the core).

    A shadow gate is written as the factor S with its recorded 1 or 0
    (:func:`~phonglab.app.equation.shadow_factor`), as lesson 14 writes it.
    """
    formula = equation.shadow_factor(formula)
    written = equation.symbols(formula)
    substituted = equation.numbers(resolve(formula, lookup), lookup)
    result = equation.value(result)
    return f"{written} = {result}" if substituted == result else f"{written} = {substituted} = {result}"


def _lookup(record, light=None):
    return lambda name: record.lookup(name, light)


def _rows(record, color, shown, several: bool) -> tuple[list[tuple[str, str]], list[tuple[str, np.ndarray]]]:
    """The worked equation's rows ``(label, tex)`` and the parts that add up to the total ``(name, rgb)``."""
    glow = bool(np.any(record["emission"]))
    base_tex = (["k_e"] if glow else []) + [equation.symbols(record.terms["ambient"])]
    base = ([record["emission"]] if glow else []) + [record["ambient"]]
    others = [lr for lr in record.lights if lr is not shown]
    # the model, in the formulas the (possibly mistaken) code used
    lights_tex = []
    if shown is not None:
        own = " + ".join(equation.symbols(equation.shadow_factor(shown.terms[t])) for t in shown.terms)
        directed = sum(lr.index is not None for lr in record.lights)
        lights_tex.append(rf"\sum_l \left[{own}\right]" if directed > 1 else own)
    lights_tex += [equation.symbols(equation.shadow_factor(lr.terms[t]))
                   for lr in others if lr.index is None for t in lr.terms]
    rows = [("model", "I = " + " + ".join(base_tex + lights_tex))]
    rows.append(("ambient", _worked(record.terms["ambient"], _lookup(record), record["ambient"])))
    if glow:
        rows.append(("emission", _worked(record.terms["emission"], _lookup(record), record["emission"])))
    if shown is not None:
        # the model's own factors first (Cook–Torrance's D, V, F), then the terms they make
        rows += [(FACTOR_LABELS.get(name, name), _worked(formula, _lookup(record, shown), shown[name]))
                 for name, formula in shown.factors.items()]
        rows += [(t, _worked(shown.terms[t], _lookup(record, shown), shown[t])) for t in shown.terms]
    if not several:
        # one light (or none): its terms added to the ambient (and emission)
        for lr in others:
            rows += [(_name(lr), _worked(lr.terms[t], _lookup(record, lr), lr[t])) for t in lr.terms]
        addends = base + [lr[t] for lr in record.lights for t in lr.terms]
        if len(addends) > 1:
            rows.append(("sum", f"I = {_sum_tex(addends)} = {equation.value(color)}"))
        return rows, []
    # several lights: the shown light with the ambient, what each other light adds, the total
    first = base + ([shown[t] for t in shown.terms] if shown is not None else [])
    first_value = np.sum(first, axis=0)
    first_name = ("emission + " if glow else "") + "ambient" + (f" + {_name(shown)}" if shown is not None else "")
    first_tex = " + ".join(base_tex + ([rf"\text{{{_name(shown)}}}"] if shown is not None else []))
    label = _name(shown) if shown is not None else "ambient"
    rows.append((label, f"{first_tex} = {_sum_tex(first)} = {equation.value(first_value)}"))
    parts = [(first_name, first_value)]
    for lr in others:
        name = _name(lr)
        if len(lr.terms) == 1:
            (t,) = lr.terms
            worked = _worked(lr.terms[t], _lookup(record, lr), lr["adds"])
        else:
            worked = (" + ".join(equation.symbols(t) if t in equation.SYMBOLS else rf"\text{{{t}}}" for t in lr.terms)
                      + f" = {_sum_tex([lr[t] for t in lr.terms])} = {equation.value(lr['adds'])}")
        rows.append((name, rf"\text{{{name}:}}\;{worked}"))  # the colon is words too: spaced from the row
        parts.append((f"{name} adds", lr["adds"]))
    rows.append(("total", f"I = {_sum_tex([rgb for _, rgb in parts])} = {equation.value(color)}"))
    parts.append(("total", color))
    return rows, parts


def probe_readout(scene, point, normal, light_index, *, mistake=None) -> dict:
    """The readout beside the view, as plain data.

    Parameters
    ----------
    scene : Scene
    point, normal : (3,) arrays
        The probe and the unit normal there.
    light_index : int or None
        The light whose vectors are drawn (a point, directional or spot light
        of ``scene.lights``); None when the scene has none.
    mistake : str, optional
        The common mistake the picture shows (a name from
        :data:`phonglab.teaching.MISTAKES`): the numbers and formulas are then
        the mistaken code's.

    Returns
    -------
    dict
        ``point``, ``dots`` (list of {name, tex, value}), ``terms`` (list of
        {name, value, hex}, with ``correct`` and ``correct_hex`` where a
        mistake changes the term), ``equation`` (HTML: one row per worked
        formula, each ``symbols = numbers = value``), ``notes`` (list of
        str; in flat and Gouraud mode the last one says the numbers are exact
        at the probe while the picture is not, :data:`INTERPOLATION_NOTES`;
        ``notes_html`` the same as the page shows them, :func:`~phonglab.app.wording.symbols_html`),
        ``vectors`` (letter -> "(x, y, z)"), ``display_note``, and
        ``mistake`` (None or {name, title, wrong, right}), ``light_name``
        (``"light 1"`` when the scene has more than one light, else None) and
        ``parts`` (with more than one light: {name, value, hex} for the
        ambient with the shown light, what each other light adds, and the
        total; else empty), ``shadows`` (with ``shadows`` on: per light
        {light, state: "lit" or "in shadow", blocker, text}, its text also
        the first notes). With more than one light, the dot n·l carries the
        shown light's diffuse and r·v (n·h for Blinn-Phong) its specular as
        ``term`` ({name, value, hex}).

    Notes
    -----
    Every number comes from the record of :func:`phonglab.scene.trace` at
    the probe; each row of the equation is a formula of that record with its
    own values substituted, so it holds to the digits shown.
    """
    p = np.asarray(point, dtype=np.float64).reshape(1, 3)
    n = np.asarray(normal, dtype=np.float64).reshape(1, 3)
    # the object the probe lies on (its material) and, with shadows, which lights reach it
    obj, seen, blocked_by = shadows.at_probe(scene, p[0]) if _objects_or_shadows(scene) else (0, None, {})
    correct, right = trace(scene, p, n, obj=obj, visibility=seen)
    right = right.at(0)
    total, record = correct, right
    if mistake is not None:
        # the numbers that made the picture: the mistaken kernel's own record
        with np.errstate(over="ignore", invalid="ignore"):
            total, record = trace(scene, p, n, mistake=mistake, obj=obj, visibility=seen)
        record = record.at(0)
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
        "display_note": display_note(scene),
        "mistake": None,
    }
    if mistake is not None:
        from phonglab.teaching import get_mistake

        m = get_mistake(mistake)
        out["mistake"] = {"name": m.name, "title": m.title, "wrong": m.wrong, "right": m.right}
    swatches = _Swatches(scene)
    for name in ("ambient", "diffuse", "specular", "emission", "color"):
        rgb = getattr(total, name)[0]
        if name == "emission" and not any(rgb):
            continue
        term = {"name": "total" if name == "color" else name, "value": _rgb_text(rgb)}
        swatches.put(term, "hex", rgb)
        right_rgb = getattr(correct, name)[0]
        if mistake is not None and _differs(rgb, right_rgb):
            # the correct value next to the mistaken one, with the line of code that differs
            term["correct"] = _rgb_text(right_rgb)
            swatches.put(term, "correct_hex", right_rgb)
            term.update(wrong=out["mistake"]["wrong"], right=out["mistake"]["right"])
        out["terms"].append(term)

    recorded = [lr.index for lr in record.lights]
    shown = record.light(light_index) if light_index is not None and light_index in recorded else None
    several = len(record.lights) > 1
    if shown is not None:
        # the vectors and cosines the model recorded (a model records those it uses)
        out["vectors"] = {k: _vec_text(record.lookup(k, shown)) for k in "nlrvh"
                          if k in shown.values or k in record.values}
        out["dots"] = [{"name": name, "tex": mathml(equation.symbol(name)), "value": f"{float(shown[name]):+.3f}"}
                       for name in ("n·l", "n·v", "r·v", "n·h", "v·h") if name in shown.values]
        if several:
            # which light the dots and the equation belong to, and its own terms beside its dots
            out["light_name"] = _name(shown)
            # the specular term beside the cosine its formula reads (r·v for Phong, n·h for Blinn-Phong)
            cosine = next((x for x in names_in(shown.terms["specular"]) if x in ("r·v", "n·h")), None)
            beside = {"n·l": "diffuse", cosine: "specular"}
            for dot in out["dots"]:
                term = beside.get(dot["name"])
                if term is not None:
                    dot["term"] = {"name": term, "value": _rgb_text(shown[term])}
                    swatches.put(dot["term"], "hex", shown[term])
    rows, parts = _rows(record, total.color[0], shown, several)
    out["parts"] = [{"name": name, "value": _rgb_text(rgb)} for name, rgb in parts]
    for part, (_, rgb) in zip(out["parts"], parts):
        swatches.put(part, "hex", rgb)
    swatches.paint()
    out["equation"] = "".join(
        f'<div class="eq-row"><span class="eq-label">{label}</span>{equation.as_mathml(tex)}</div>' for label, tex in rows
    )
    if several and shown is not None:
        out["equation"] = (f'<div class="phonglab-eq-head">Worked for {out["light_name"]} (its vectors are drawn) '
                           "with the ambient light; the last rows add the other lights.</div>" + out["equation"])
    out["notes"] = _notes(scene, right, record, shown, out, mistake)
    out["shadows"] = _shadow_lines(scene, right, blocked_by)
    objects = scene.all_objects
    out["notes"][:0] = [line["text"] for line in out["shadows"]] + (
        [f"The probe is on the {objects[obj].label}: its material's k_a, k_d, k_s and α are used."]
        if len(objects) > 1 else [])
    out["notes_html"] = [symbols_html(note) for note in out["notes"]]  # what the page shows: k_a with its subscript
    return out


def _objects_or_shadows(scene) -> bool:
    return scene.shadows or len(scene.all_objects) > 1


def _shadow_lines(scene, record, blocked_by) -> list[dict]:
    """Per directed light, whether it reaches the probe ("lit") or not ("in shadow", and what blocks it).

    ``lit`` is the record's (what the model used); the blocking object is
    the ray caster's. Empty when the scene has no shadows.
    """
    if not scene.shadows:
        return []
    lines = []
    objects = scene.all_objects
    for light in record.lights:
        if light.index is None or "lit" not in light.values:
            continue
        name = _name(light)
        if bool(light["lit"]):
            # the shadow ray starts shadow_bias along l: say so when that start may have passed an object
            start = (f", which starts {scene.shadow_bias:g} from the point towards the light"
                     if scene.shadow_bias >= 0.01 else "")
            lines.append({"light": name, "state": "lit", "blocker": None,
                          "text": f"{name.capitalize()}: lit here, S = 1 (no object blocks its shadow ray{start})."})
        else:
            by = objects[blocked_by[light.index]].label
            lines.append({"light": name, "state": "in shadow", "blocker": by,
                          "text": f"{name.capitalize()}: in shadow here (blocked by the {by}): S = 0, so it adds "
                                  "neither diffuse nor specular light."})
    return lines


def _notes(scene, right, record, shown, out, mistake) -> list[str]:
    """What the numbers mean here: the mistake, a light behind the surface, f, the flip, the interpolation."""
    notes = []
    if mistake is not None:
        changed = [t["name"] for t in out["terms"] if "correct" in t]
        notes.append(f"Deliberately wrong ({out['mistake']['title']}): these are the mistaken code's "
                     "numbers, the ones that made the picture"
                     + (f"; {', '.join(changed)} differ from the correct values." if changed
                        else "; here they equal the correct ones."))
    if shown is None:
        alone = not record.lights
        notes.append("No point, directional or spot light" + (": only the ambient term is lit." if alone else "."))
    else:
        several = out["light_name"] is not None
        behind = float(right.light(shown.index)["n·l"]) <= 0  # the correct code's n·l: where the light really is
        if behind:
            who, its = (f"{out['light_name']} is", "its ") if several else ("the light is", "")
            notes.append(f"n·l ≤ 0: {who} behind the surface here, so "
                         + (f"{its}diffuse and specular are 0." if mistake is None else
                            f"correct code gives {its}diffuse and specular 0; the mistaken code gives diffuse "
                            f"{_rgb_text(shown['diffuse'])} and specular {_rgb_text(shown['specular'])}."))
        if scene.model == "cook-torrance" and float(right["n·v"]) <= 0:
            # its D and V rows then read "= 0": say why, in words
            notes.append("n·v ≤ 0: the eye is below the surface here, and Cook–Torrance is one-sided, so D, V and "
                         "the light the point sends to the eye are 0.")
        if float(shown["f"]) != 1.0:
            # f is the recorded product of the factors the kernel used: each named with its own value
            factors = []
            if "d" in shown.values:
                factors.append(f"attenuation {float(shown['attenuation']):.3f} (at distance {float(shown['d']):.2f})")
            if "spot" in shown.values:
                factors.append(f"spot factor {float(shown['spot']):.3f}")
            notes.append((f"For {out['light_name']}, " if several else "")
                         + f"f = {float(shown['f']):.3f} = " + " × ".join(factors) + ".")
    if bool(right["flipped"]):
        notes.append("Two-sided lighting flipped the normal: it faced away from the eye.")
    if scene.interpolation in INTERPOLATION_NOTES:
        notes.append(INTERPOLATION_NOTES[scene.interpolation])
    return notes
