"""Controls and refusals in a student's words: a slider's spoken name, an address notice's sentences.

The page labels a control with maths (``$k_s$``, ``shininess $\\alpha$``) and
a group heading; a screen reader and a sentence need plain text that says
which control is meant (:func:`spoken_label`: "specular k_s", "light 1
azimuth").

A setting in the page's address that cannot apply (:mod:`phonglab.app.address`)
is told as one plain sentence: the setting's name on the page and its address
key, the value as typed, what is wrong with it and what is allowed, in words
(:func:`refusal`)::

    The address asks for specular k_s (material.ks) = abc, which is not a
    number; it takes a number of 0 or more, or three of them (red, green,
    blue) separated by commas.

No Python quoting, no ``>=``: what is allowed comes from the control (a
slider's range, a select's choices) or from the scene's own rule, put into
words by :func:`plain_rule`.
"""

from __future__ import annotations

import html
import re

from phonglab.scene.errors import printable
from phonglab.scene.schema import CORE_FIELDS, VECTOR_RULE

#: the coefficients' symbols with the term each one scales
_SYMBOL_NAMES = {"k_a": "ambient k_a", "k_d": "diffuse k_d", "k_s": "specular k_s", "k_e": "emission k_e"}
#: LaTeX commands the labels use, as the letters a reader sees
_TEX = {r"\alpha": "α", r"\cdot": "·", r"\,": " "}
#: longest value quoted back in a sentence, in characters
SHOWN_CHARS = 40


def plain_label(label: str) -> str:
    """A label without its ``$...$`` maths markup: ``shininess $\\alpha$`` -> ``shininess α``."""

    def unmath(match):
        tex = match.group(1)
        for command, letter in _TEX.items():
            tex = tex.replace(command, letter)
        tex = tex.replace("{", "").replace("}", "")
        return _SYMBOL_NAMES.get(tex, tex)

    return " ".join(re.sub(r"\$(.+?)\$", unmath, label).split())


def _light_prefix(group: str) -> str:
    """``Light 1 (point)`` -> ``light 1``; ``Ambient light 0`` -> ``ambient light 0``; others nothing."""
    m = re.fullmatch(r"(Ambient light|Light) (\d+).*", group)
    return f"{m.group(1).lower()} {m.group(2)}" if m else ""


def spoken_label(control) -> str:
    """What a control is called in plain text: its label, with its light where the label alone is ambiguous.

    >>> from phonglab.app.control import Control
    >>> spoken_label(Control(path="lights[1].azimuth", label="azimuth", kind="slider", read=None, write=None,
    ...                      group="Light 1 (point)"))
    'light 1 azimuth'
    """
    label = plain_label(control.label)
    prefix = _light_prefix(control.group)
    return f"{prefix} {label}" if prefix else label


# ---------------------------------------------------------------------------
# what is allowed, in words


def _choices(words) -> str:
    """``a, b or c``."""
    words = [str(w) for w in words]
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _quoted_choices(text: str) -> str:
    return _choices([w.strip().strip('"').strip("'") for w in text.split(",") if w.strip()])


#: the scene's and the controls' rules (``must be ...``) as what a field takes, in words; first match wins
_RULES = [
    (r"must be a finite number >= 0 or (a list of 3 of them \(RGB\)|an RGB triple of them)",
     lambda m: "a number of 0 or more, or three of them (red, green, blue) separated by commas"),
    (r"must be a finite number in \[(\S+), (\S+)\] or (a list of 3 of them \(RGB\)|an RGB triple of them)",
     lambda m: f"a number from {_number(m.group(1))} to {_number(m.group(2))}, or three of them (red, green, blue) "
               "separated by commas"),
    (r"must be a list of 3 finite numbers, not all zero",
     lambda m: "three numbers separated by commas (x, y, z), not all zero"),
    (r"must be a list of 3 finite numbers", lambda m: "three numbers separated by commas (x, y, z)"),
    (r"must be a list of 4 finite numbers \[x, y, z, w\].*",
     lambda m: "four numbers x, y, z, w separated by commas, with w = 1 for a point light or 0 for a directional one"),
    (r"must be between (\S+) and (\S+)", lambda m: f"a number from {m.group(1)} to {m.group(2)}"),
    (r"must be a finite number in \[(\S+), (\S+)\]",
     lambda m: f"a number from {_number(m.group(1))} to {_number(m.group(2))}"),
    (r"must be a finite number in \((\S+), (\S+)\]",
     lambda m: f"a number above {_number(m.group(1))} and at most {_number(m.group(2))}"),
    (r"must be a finite number in \((\S+), (\S+)\)",
     lambda m: f"a number between {m.group(1)} and {m.group(2)}, neither end included"),
    (r"must be a finite number >= (\S+)", lambda m: f"a number of {m.group(1)} or more"),
    (r"must be a finite number > (\S+)", lambda m: f"a number above {m.group(1)}"),
    (r"must be a finite number <= (\S+)", lambda m: f"a number of {m.group(1)} or less"),
    (r"must be a (finite )?number", lambda m: "a number"),
    (r"must be a whole number from (\S+) to (\S+)", lambda m: f"a whole number from {m.group(1)} to {m.group(2)}"),
    (r"must be a whole number >= (\S+)", lambda m: f"a whole number of {m.group(1)} or more"),
    (r"must be one of (.+)", lambda m: _quoted_choices(m.group(1))),
    (r"must be true or false", lambda m: "true or false"),
    (r"must be a colour #rrggbb", lambda m: "a colour as six hex digits, such as ff8000"),
    (r"must be \(a, b, c\) with a \+ b·d \+ c·d² > 0 at every distance.*",
     lambda m: "three numbers a, b, c with a + b·d + c·d² above 0 at every distance d, "
               "such as 1,0,0 (no fall-off) or 0,0,1 (inverse square)"),
    (r"must be \(a, b, c\) with every coefficient within ±(\S+)",
     lambda m: f"three numbers a, b, c, each at most {_number(m.group(1))} in size"),
    (r"must have every coordinate within ±(\S+) scene units", lambda m: f"coordinates of at most {m.group(1)} in size"),
]


def _number(text: str) -> str:
    """A number as a rule writes it, as a student reads it: ``1e6`` -> ``1,000,000``; others as written."""
    m = re.fullmatch(r"1e\+?(\d+)", text)
    return f"{10 ** int(m.group(1)):,}" if m else text


#: comparison signs in a rule no pattern knew, as words
_SIGNS = ((">=", "at least"), ("<=", "at most"), (">", "more than"), ("<", "less than"), ("≥", "at least"),
          ("≤", "at most"))


def plain_rule(rule: str) -> str:
    """A field's rule (``"must be a finite number >= 0"``) as what it takes (``"a number of 0 or more"``).

    A rule no pattern knows loses its "must be" and its comparison signs and quotes.
    """
    rule = " ".join(str(rule).split())
    for pattern, words in _RULES:
        m = re.fullmatch(pattern, rule)
        if m:
            return words(m)
    text = re.sub(r"^must (be )?", "", rule)
    for sign, word in _SIGNS:
        text = text.replace(f" {sign} ", f" {word} ").replace(sign, f" {word} ")
    return " ".join(text.replace('"', "").replace("'", "").split())


def _field_rule(path: str) -> str | None:
    """The scene's rule for a file-form field (``material.ks``, ``lights[1].position``, ``probe``), if known."""
    if path == "probe":
        return VECTOR_RULE
    name = re.sub(r"\[\d+\]$", "", path.rsplit(".", 1)[-1])
    shape, rule = CORE_FIELDS.get(name, (None, None))
    return rule


def _counts(rule: str) -> tuple[int, ...]:
    """How many numbers a rule takes: ``(1, 3)`` for a grey or RGB coefficient, ``(3,)`` for a vector."""
    if "or a list of 3" in rule or "RGB triple" in rule:
        return (1, 3)
    m = re.search(r"list of (\d+)", rule)
    if m:
        return (int(m.group(1)),)
    if rule.startswith("must be (a, b, c)"):
        return (3,)
    if re.match(r"must be a (finite|whole) number", rule):
        return (1,)
    return ()


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


# ---------------------------------------------------------------------------
# an address notice's sentences


def shown_value(text: str) -> str:
    """The value as typed, short enough for a sentence (never quoted).

    Characters that would act instead of show (NUL, a right-to-left
    override) are escaped (:func:`phonglab.scene.errors.printable`).
    """
    text = printable(" ".join(str(text).split()))
    if not text:
        return "nothing"
    return text if len(text) <= SHOWN_CHARS else text[: SHOWN_CHARS - 1] + "…"


def setting_name(path: str, control) -> str:
    """A setting's name in a sentence: the page's label where it has one (without its explanation), else its field."""
    if control.kind != "value":
        return re.split(r" \(|: ", spoken_label(control))[0]
    m = re.fullmatch(r"material\.(ka|kd|ks)", path)
    if m:
        return _SYMBOL_NAMES["k_" + m.group(1)[1]]
    if path == "material.shininess":
        return "shininess α"
    if path == "probe":
        return "probe point"
    m = re.fullmatch(r"lights\[(\d+)\]\.(\w+)", path)
    if m:
        return f"light {m.group(1)} {m.group(2)}"
    return path.rsplit(".", 1)[-1].replace("_", " ")


def refusal(path: str, text: str, control, error) -> str:
    """The sentence for an address setting its control refused (``error``, a ControlError).

    Names the setting (:func:`setting_name`) and its address key, the value
    as typed, what is wrong with it and what the setting takes.
    """
    name, value = setting_name(path, control), shown_value(text)
    name = name if name == path else f"{name} ({path})"
    rule = getattr(error, "rule", None)
    parts = [p.strip() for p in str(text).split(",")] if str(text).strip() else [""]
    numbers = [p for p in parts if re.fullmatch(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", p)]
    if control.kind == "slider":
        unit = " degrees" if control.unit == "°" else ""
        allowed = f"a number from {control.low:g} to {control.high:g}{unit}"
        wrong = "which is not a number" if len(parts) != 1 or not numbers else "which is out of range"
        return f"The address asks for {name} = {value}, {wrong}: it takes {allowed}."
    if control.kind == "switch":
        return f"The address asks for {name} = {value}, which is neither true nor false: it takes true or false."
    if control.kind == "select":
        allowed = _choices([v for v, _ in control.items])
        return f"The address asks for {name} = {value}, which is not one of its choices: it takes {allowed}."
    if control.kind == "color":
        return (f"The address asks for {name} = {value}, which is not a colour: "
                f"it takes {plain_rule('must be a colour #rrggbb')}.")
    # a file-form field: the scene's rule
    field_rule = _field_rule(path)
    rule = rule if rule and (rule.startswith("must") or not field_rule) else field_rule
    counts = _counts(rule) if rule else ()
    if len(numbers) < len(parts):
        wrong = "which is not a number" if len(parts) == 1 else "which holds something that is not a number"
    elif counts and len(parts) not in counts:
        wrong = f"which has {len(parts)} numbers"
    elif rule and re.search(r">|<|between| in [\[(]", rule):
        wrong = "which is out of range"
    else:
        wrong = "which is not allowed"
    allowed = plain_rule(rule) if rule else "another value"
    return f"The address asks for {name} = {value}, {wrong}: it takes {allowed}."


def unknown_setting(path: str, text: str) -> str:
    """The sentence for an address key this lesson has no setting for."""
    return f"The address asks for {shown_value(path)} = {shown_value(text)}, but this lesson has no setting called that."


def long_key(key: str) -> str:
    """The sentence for an address key too long to be a setting's."""
    return f"The address names a setting {shown_value(key)}, which is longer than the name of any setting."


def long_value(key: str, length: int, limit: int) -> str:
    """The sentence for an address value longer than ``limit`` characters."""
    return f"The address gives {shown_value(key)} a value of {length} characters; a value may have at most {limit}."


def too_many(limit: int) -> str:
    """The sentence for an address with more than ``limit`` settings."""
    return f"The address has more than {limit} settings; only the first {limit} are read."


def unreadable(limit: int) -> str:
    """The sentence for an address that is not a query of at most ``limit`` characters."""
    return f"The address could not be read: it is not a page address of at most {limit} characters (not a query string)."


def no_lesson(name: str, known) -> str:
    """The sentence for an address that names no lesson."""
    return f"The address asks for a lesson called {shown_value(name)}, but there is none; the lessons are {', '.join(known)}."


def address_notice(problems) -> str:
    """The sentences of one address's problems as the page's one-line notice."""
    without = "without it" if len(problems) == 1 else "without them"
    return " ".join(problems) + f" The lesson opened {without}; the rest of the address applies."


#: a symbol with a one-letter subscript as plain text writes it (k_a, I_d, f_l): letter, underscore, letter
_SUBSCRIPTED = re.compile(r"(?<![\w])([A-Za-z])_([a-z])(?![\w])")


def symbols_html(text: str) -> str:
    """Plain text from the core or the planner as HTML with its symbols' subscripts set: ``k_a`` as k<sub>a</sub>.

    The text is escaped first; only the subscripts are markup. A sentence a
    student reads then shows the symbols as the formulas beside it do.
    """
    return _SUBSCRIPTED.sub(r"<i>\1</i><sub>\2</sub>", html.escape(str(text), quote=False))
