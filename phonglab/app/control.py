"""One control: a widget's value, checked, written into a scene field.

A :class:`Control` reads its widget's value from a scene (``read``) and writes
a widget value back into a new scene (:meth:`Control.apply`). Every value that
arrives from the browser goes through :meth:`Control.apply`, which checks its
type and range first (:meth:`Control.check`) and then lets the scene check the
result (:meth:`phonglab.scene.Scene.replace`), so a refused value raises
:class:`ControlError` naming the control, the value and what is allowed, and
the previous scene stays.

Which controls a scene gets, and what each one edits, is
:mod:`phonglab.app.controls`.
"""

from __future__ import annotations

import functools
import math
import numbers
import re
from dataclasses import dataclass
from typing import Callable

import numpy as np

from phonglab.app.equation import exponent
from phonglab.app.keys import state_key
from phonglab.core.display import display_bytes, srgb_decode
from phonglab.scene import SceneError

#: a colour as the browser's colour picker sends it
_HEX = re.compile(r"#[0-9a-fA-F]{6}")


class ControlError(ValueError):
    """A browser value was refused; the message says which control, the value and what is allowed.

    ``rule`` is what is allowed in the field's own words (``"must be a finite
    number >= 0"``) when the refusal states one, else None: what a notice in
    plain words is made from (:mod:`phonglab.app.wording`).
    """

    def __init__(self, message: str, rule: str | None = None):
        super().__init__(message)
        self.rule = rule


@dataclass(frozen=True)
class Control:
    """One widget on the page and the scene field behind it.

    Attributes
    ----------
    path : str
        The field path the widget edits (a scene field or one of the
        presentation fields listed in the module docstring).
    label : str
        The widget's label; may hold ``$...$`` maths.
    kind : str
        ``"slider"``, ``"color"``, ``"select"``, ``"switch"``, or ``"value"``
        (no widget: the state key mirrors a scene field in its file form).
    low, high, step : float
        Slider range and step (in widget units: ``log10 α`` for shininess).
    items : tuple of (value, title)
        Choices of a select.
    read : callable
        ``read(scene, view_options) -> widget value``.
    write : callable
        ``write(scene, widget value, view_options) -> (scene, view_options)``;
        the value has passed the type and range checks already.
    unit : str
        Shown after a slider's value ("°").
    fmt : str
        How the widget value is shown; ``"alpha"`` shows ``10**value``.
    key_step : float
        How far one arrow key moves a slider, when that should be more than
        ``step`` (which is also what dragging snaps to); 0 means ``step``.
    """

    path: str
    label: str
    kind: str
    read: Callable
    write: Callable
    low: float = 0.0
    high: float = 1.0
    step: float = 0.01
    items: tuple = ()
    unit: str = ""
    fmt: str = "{:.2f}"
    group: str = ""
    key_step: float = 0.0
    #: the models the control acts in (empty: every model); under another the page greys it and says so
    models: tuple = ()

    @property
    def key(self) -> str:
        """The trame state key (:func:`phonglab.app.keys.state_key`)."""
        return state_key(self.path)

    def check(self, value):
        """The browser value as the widget's type, or :class:`ControlError`."""
        if self.kind == "slider":
            if not isinstance(value, numbers.Real) or isinstance(value, bool):
                raise ControlError(f"{self.path}: must be a number, got {_show(value)}", "must be a number")
            value = float(value)
            if not math.isfinite(value):
                raise ControlError(f"{self.path}: must be a finite number, got {_show(value)}", "must be a finite number")
            slack = 1e-9 * max(1.0, abs(self.high - self.low))
            if not (self.low - slack <= value <= self.high + slack):
                rule = f"must be between {self.low:g} and {self.high:g}"
                raise ControlError(f"{self.path}: {rule}, got {_show(value)}", rule)
            return min(max(value, self.low), self.high)
        if self.kind == "switch":
            if not isinstance(value, bool):
                raise ControlError(f"{self.path}: must be true or false, got {_show(value)}", "must be true or false")
            return value
        if self.kind == "select":
            allowed = [v for v, _ in self.items]
            if not isinstance(value, str) or value not in allowed:
                rule = f"must be one of {', '.join(allowed)}"
                raise ControlError(f"{self.path}: {rule}, got {_show(value)}", rule)
            return value
        if self.kind == "value":
            return _check_plain(self.path, value)
        if self.kind == "color":
            if not isinstance(value, str) or not _HEX.fullmatch(value.strip()):
                raise ControlError(f"{self.path}: must be a colour #rrggbb, got {_show(value)}", "must be a colour #rrggbb")
            return value.strip().lower()
        raise AssertionError(self.kind)

    def apply(self, scene, value, options: dict):
        """Check ``value`` and return ``(new scene, new view options)``.

        Raises
        ------
        ControlError
            The value's type or range is wrong, or the scene refuses the result.
        """
        value = self.check(value)
        try:
            return self.write(scene, value, dict(options))
        except SceneError as exc:
            errors = getattr(exc, "errors", None) or [exc]
            raise ControlError(f"{self.path}: {_scene_reason(exc, self.path)}", errors[0].problem) from None
        except (ValueError, TypeError, ArithmeticError) as exc:  # core validation
            raise ControlError(f"{self.path}: {exc}") from None

    def same(self, a, b) -> bool:
        """Whether two widget values mean the same setting (sliders: within half a step)."""
        if self.kind == "slider":
            try:
                return abs(float(a) - float(b)) <= 0.5 * self.step
            except (TypeError, ValueError):
                return False
        return a == b


def _check_plain(path, value, depth=0):
    """A file-form value (number, bool, string, list of those); ControlError otherwise.

    The scene checks the meaning; this only keeps odd objects out.
    """
    if isinstance(value, (bool, str)) or (isinstance(value, numbers.Real)):
        if isinstance(value, str) and len(value) > 200:
            raise ControlError(f"{path}: text too long ({len(value)} characters)")
        return value
    if isinstance(value, (list, tuple)) and depth == 0 and len(value) <= 4:
        return [_check_plain(path, v, 1) for v in value]
    if value is None and path == "probe":
        return None
    raise ControlError(f"{path}: must be a number, true/false, a text or a short list, got {_show(value)}")


def _show(value) -> str:
    if isinstance(value, str):
        return repr(value[:60])
    if isinstance(value, float) and math.isnan(value):
        return "NaN"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _scene_reason(exc: SceneError, path: str = "") -> str:
    """The part of a SceneError that helps a student: problem, value, hint.

    The error's field is left out when it is the control's own (or contains it).
    """
    errors = getattr(exc, "errors", None) or [exc]
    parts = []
    for e in errors:
        text = e.problem
        if e.field and not (path.startswith(e.field) or e.field.startswith(path)):
            text = f"{e.field}: {text}"
        if e.has_value:
            text += f", got {_show(e.value)}"
        if e.hint:
            text += f"; {e.hint}"
        parts.append(text)
    return "; ".join(parts)


# ---------------------------------------------------------------------------
# colour helpers


def rgb_to_hex(rgb) -> str:
    """A linear colour ``(r, g, b)`` in [0, 1] (clipped) as the sRGB ``#rrggbb`` a colour picker shows.

    Pickers show and return sRGB, as colour-managed tools do; the scene stores
    linear values (:func:`hex_to_rgb` decodes). Linear 0.5 shows as ``#bcbcbc``.
    """
    return _srgb_hex(tuple(float(c) for c in rgb))


@functools.lru_cache(maxsize=1024)
def _srgb_hex(rgb: tuple) -> str:
    """:func:`rgb_to_hex` of a tuple of floats, remembered (the colours of a scene seldom change)."""
    encoded = display_bytes(np.asarray(rgb, dtype=np.float64), encoding="srgb")
    return "#" + "".join(f"{int(c):02x}" for c in encoded)


def hex_to_rgb(text: str) -> tuple[float, float, float]:
    """An sRGB ``#rrggbb`` from a colour picker as the three linear values in [0, 1] the scene stores."""
    encoded = np.array([int(text[i : i + 2], 16) / 255.0 for i in (1, 3, 5)])
    return tuple(float(c) for c in srgb_decode(encoded))


def split_level(rgb) -> tuple[float, tuple[float, float, float]]:
    """An RGB coefficient as (level, hue): level = largest channel, hue = rgb / level."""
    level = max(rgb)
    if level <= 0:
        return 0.0, (1.0, 1.0, 1.0)
    return level, tuple(c / level for c in rgb)


#: decimals the shininess slider's α is rounded to when it is written into the scene
ALPHA_DECIMALS = 6


def slider_alpha(log_alpha: float) -> float:
    """The shininess α the log slider's value ``log_alpha`` writes into the scene."""
    return round(10.0**log_alpha, ALPHA_DECIMALS)


def format_value(control: Control, value) -> str:
    """A slider value as the page shows it (α for the log slider).

    α is written as the readout writes the exponent (:func:`~phonglab.app.equation.exponent`):
    a whole number as it is, else with two decimals, so the slider and the
    readout's ``max(0, c)^α`` show the same number.
    """
    if control.fmt == "alpha":
        return exponent(slider_alpha(value))
    return control.fmt.format(value) + control.unit


def finite3(p) -> list[float]:
    """A point from the browser as 3 finite floats, or ValueError."""
    values = [float(c) for c in p]
    if len(values) != 3 or not all(math.isfinite(c) for c in values):
        raise ValueError(f"a point must be 3 finite numbers, got {p!r}")
    return values
