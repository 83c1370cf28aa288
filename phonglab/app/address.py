"""The page's address is the view: ``?lesson=04-specular&material.ks=0.8&interpolation=pixel``.

The address names the lesson and every setting that differs from the
lesson's own, one query parameter per setting, in the form a student reads
(the lesson file's field paths and values), so a reload, back/forward, a
bookmark or a link pasted to a classmate opens the same view.

How it travels:

- the server writes the query of the view on screen into the state key
  :data:`QUERY_KEY` (:meth:`ViewAddress.query`, after every new scene);
  ``www/phonglab.js`` puts it in the address bar with
  ``history.replaceState``, a moment after the last change (no history
  entry per slider step);
- when the page loads, it sends its own query once in :data:`REQUEST_KEY`;
  :func:`lesson_index` finds the lesson, :func:`read_query` reads the
  settings within bounds and :func:`apply_settings` applies them, each
  through the page's own control for that key
  (:class:`~phonglab.app.control.Control`), so an address value is checked
  exactly like a value a browser writes. A refused value or an unknown key
  becomes a notice and is dropped; the rest still applies.

Which settings (keys are field paths; :func:`setting_paths`):

- scene fields in their file form: ``material.ka`` … ``material.emission``,
  ``material.shininess``, ``lights[i].position`` / ``direction`` /
  ``attenuation``, ``probe`` (numbers joined by commas; a grey coefficient
  as one number);
- what a widget sets: ``lights[i].type``, ``lights[i].color`` (six hex
  digits, sRGB as the colour picker shows it), ``intensity``, ``cutoff``,
  ``no_cone``, ``exponent``; ``model``, ``interpolation``, ``two_sided``,
  ``camera.infinite_viewer``, ``display``, ``exposure``; the shape
  (``geometry.kind``, ``geometry.resolution``); the view options
  ``view.term`` and ``view.mistake``;
- the eye as ``camera.azimuth`` / ``elevation`` / ``distance`` (the eye
  sliders, around the focal point in the lesson's frame): a turned view
  comes back with the same eye, so the picture's shading and the readout
  are the same. The roll, pan and view angle of a dragged view are not kept.

Slider values are written to a tenth of the slider's step, file-form numbers
to :data:`FIELD_DECIMALS` decimals: short, and the same view after a reload.
"""

from __future__ import annotations

import math
import re
from urllib.parse import parse_qs, parse_qsl, urlencode

from phonglab.app import wording
from phonglab.app.control import ControlError
from phonglab.app.keys import state_key

#: state key: the query of the view the page shows (set by the server)
QUERY_KEY = "url_query"
#: state key: the query the page was opened with (set by the browser, once)
REQUEST_KEY = "url_request"
#: longest query read from the browser, in characters
MAX_QUERY_CHARS = 2000
#: most settings read from one address (the rest are dropped with a notice)
MAX_SETTINGS = 64
#: longest value of one setting, in characters
MAX_SETTING_CHARS = 200
#: longest key of one setting, in characters
MAX_KEY_CHARS = 64
#: decimals of a file-form number in the address
FIELD_DECIMALS = 4

#: widgets whose field the address carries in file form instead (or not at all)
_PRESENTATION = re.compile(
    r"material\.(ka|kd|ks)\.(level|color)|material\.shininess\.log"
    r"|lights\[\d+\]\.(azimuth|elevation|distance)|lights\[\d+\]\.attenuation\[\d+\]"
)
#: file-form fields whose three equal numbers may be written as one
_GREY = re.compile(r"material\.(ka|kd|ks|emission)")
_HEX6 = re.compile(r"[0-9a-fA-F]{6}")
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
#: the default view options of a lesson (lesson_app resets to these)
DEFAULT_OPTIONS = {"term": "color"}


def lesson_key(entry) -> str:
    """How the address names a lesson: its file's stem (``04-specular``)."""
    return entry.path.stem


def query_for(entry) -> str:
    """``?lesson=04-specular`` for a catalogue entry."""
    return "?" + urlencode({"lesson": lesson_key(entry)})


def lesson_index(query, entries):
    """The index of the lesson a query names: ``(index, None)`` or ``(None, problem)``.

    No query, or a missing or empty ``lesson``, gives ``(None, None)`` (nothing asked).
    Anything else that does not name a lesson gives a problem to show.
    """
    if query is None:
        return None, None
    if not isinstance(query, str) or len(query) > MAX_QUERY_CHARS:
        return None, wording.unreadable(MAX_QUERY_CHARS)
    values = parse_qs(query.lstrip("?")).get("lesson", [])
    if not values or not values[0]:
        return None, None
    name = values[0]
    for i, entry in enumerate(entries):
        if lesson_key(entry) == name:
            return i, None
    return None, wording.no_lesson(name, [lesson_key(e) for e in entries])


# ---------------------------------------------------------------------------
# writing settings


def setting_paths(controls) -> list[str]:
    """The field paths the address may carry for a :class:`~phonglab.app.controls.ControlSet`, in order.

    Light types come first (they decide which other controls exist), then the
    widgets in page order, then the file-form fields, then the view options.
    """
    widgets = [c.path for c in controls.widgets if not _PRESENTATION.fullmatch(c.path)]
    types = [p for p in widgets if p.endswith(".type")]
    rest = [p for p in widgets if not p.endswith(".type")]
    others = [c.path for c in controls.by_key.values()
              if not _PRESENTATION.fullmatch(c.path) and c.path not in widgets]
    seen, out = set(), []
    for path in types + rest + others:
        if path not in seen:
            seen.add(path)
            out.append(path)
    return out


def _decimals(step: float) -> int:
    """Decimals that write a tenth of ``step`` (0.01 -> 3, 1 -> 1)."""
    return max(0, -math.floor(math.log10(step / 10.0) + 1e-9))


def compact_number(x, decimals: int) -> str:
    """``x`` rounded to ``decimals``, as short as Python writes it (``0.8``, ``30``, never ``-0``)."""
    r = round(float(x), decimals)
    if r == 0:
        return "0"
    if r.is_integer() and abs(r) < 1e15:
        return str(int(r))
    return repr(r)


def format_setting(control, value) -> str | None:
    """A control's value as the address writes it; None when it cannot be written.

    A slider's value past its ends (the view zoomed in with the wheel beyond the eye's
    distance slider, say) is written at the nearest end: an address this app writes is
    one it reads back without a refusal.
    """
    if control.kind == "slider":
        value = min(max(float(value), control.low), control.high)
        return compact_number(value, _decimals(control.step))
    if control.kind == "switch":
        return "true" if value else "false"
    if control.kind == "color":
        return str(value).lstrip("#").lower()
    if control.kind == "select":
        return str(value)
    return _format_plain(control.path, value)


def _format_plain(path, value) -> str | None:
    """A file-form value: numbers joined by commas, a grey coefficient as one number."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return compact_number(value, FIELD_DECIMALS)
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)) and value and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        parts = [compact_number(v, FIELD_DECIMALS) for v in value]
        if _GREY.fullmatch(path) and len(set(parts)) == 1:
            return parts[0]
        return ",".join(parts)
    return None


_UNREAD = object()


class ViewAddress:
    """The address of one tab's view: the lesson plus the settings that differ from the lesson's.

    A light whose type changed is written as its type alone, then whatever
    differs from the lesson's light retyped that way (opening the address
    retypes first, :func:`apply_settings`): switching a point light to a spot
    adds ``lights[1].type=spot``, not the spot's default cone. The lesson's
    own values are read once per lesson and set of types, and kept.
    """

    def __init__(self):
        self._reference_key = None
        self._reference = None
        self._defaults: dict = {}

    def _reference_scene(self, entry, controls, types) -> object:
        """The lesson's scene with the light ``types`` (``[(path, text)]``) applied: what the other settings differ from."""
        key = (id(entry.scene), tuple(types))
        if key != self._reference_key:
            scene = entry.scene
            for path, text in types:
                control = controls.by_key[state_key(path)]
                try:
                    scene, _ = control.apply(scene, parse_setting(control, text), dict(DEFAULT_OPTIONS))
                except ControlError:
                    pass
            self._reference_key, self._reference, self._defaults = key, (entry.scene, scene), {}
        return self._reference[1]

    def _default(self, key, control, scene) -> object:
        """The address text of ``control`` (state ``key``) on the reference ``scene``, or a mark that it has none."""
        key = (key, control.kind)
        if key not in self._defaults:
            try:
                self._defaults[key] = format_setting(control, control.read(scene, dict(DEFAULT_OPTIONS)))
            except Exception:  # the lesson has no such field (a light of another type)
                self._defaults[key] = _UNREAD
        return self._defaults[key]

    def settings(self, entry, scene, options, controls, values=None) -> list[tuple[str, str]]:
        """``(path, text)`` for every setting of ``scene``/``options`` that differs from the lesson's.

        ``values`` (state key -> widget value, :meth:`ControlSet.values`) saves reading them again.
        """
        current = []
        for path in setting_paths(controls):
            key = state_key(path)
            control = controls.by_key.get(key)
            if control is None:
                continue
            try:
                value = values[key] if values is not None and key in values else control.read(scene, options)
                text = format_setting(control, value)
            except Exception:
                continue
            if text is not None:
                current.append((path, key, control, text))
        # light types first: against the lesson's own lights
        types = []
        for path, key, control, text in current:
            if path.endswith(".type"):
                try:
                    lesson = format_setting(control, control.read(entry.scene, dict(DEFAULT_OPTIONS)))
                except Exception:
                    lesson = _UNREAD
                if text != lesson:
                    types.append((path, text))
        # the rest: against the lesson's scene with those types
        reference = self._reference_scene(entry, controls, types)
        return types + [(path, text) for path, key, control, text in current
                        if not path.endswith(".type") and text != self._default(key, control, reference)]

    def query(self, entry, scene, options, controls, values=None) -> str:
        """``?lesson=…&path=value…`` for the view on screen (``entry``'s lesson, ``scene``, view ``options``).

        ``controls`` is the tab's :class:`~phonglab.app.controls.ControlSet`, fitted to ``scene``;
        ``values`` its widget values for ``scene``, if already read.
        """
        settings = self.settings(entry, scene, options, controls, values)[:MAX_SETTINGS]
        while True:  # an address this app writes is one it reads back: within the bounds
            query = "?" + urlencode([("lesson", lesson_key(entry))] + settings, safe=",[]")
            if len(query) <= MAX_QUERY_CHARS or not settings:
                return query
            settings = settings[:-1]


# ---------------------------------------------------------------------------
# reading settings


def read_query(query) -> tuple[list[tuple[str, str]], list[str]]:
    """The settings a query asks for, ``[(path, text)]`` without ``lesson``, and the problems found.

    Bounded: at most :data:`MAX_QUERY_CHARS` characters and :data:`MAX_SETTINGS`
    settings; a longer key or value is dropped with a problem.
    """
    if query is None or query == "":
        return [], []
    if not isinstance(query, str) or len(query) > MAX_QUERY_CHARS:
        return [], [wording.unreadable(MAX_QUERY_CHARS)]
    # at most one field more than a full address (the lesson and MAX_SETTINGS settings): enough to tell
    fields = query.lstrip("?").split("&")[: MAX_SETTINGS + 2]
    pairs = parse_qsl("&".join(fields), keep_blank_values=True)
    pairs = [(k, v) for k, v in pairs if k != "lesson"]
    problems = []
    if len(pairs) > MAX_SETTINGS:
        problems.append(wording.too_many(MAX_SETTINGS))
        pairs = pairs[:MAX_SETTINGS]
    out = []
    for key, text in pairs:
        if len(key) > MAX_KEY_CHARS:
            problems.append(wording.long_key(key))
        elif len(text) > MAX_SETTING_CHARS:
            problems.append(wording.long_value(key, len(text), MAX_SETTING_CHARS))
        else:
            out.append((key, text))
    return out, problems


def _word(text: str):
    """One part of a file-form value: a number, true/false, or the text itself."""
    if text in ("true", "false"):
        return text == "true"
    if _NUMBER.fullmatch(text):
        return float(text)
    return text


def parse_setting(control, text: str):
    """An address text as the value a browser would send for ``control`` (unchecked: the control checks it)."""
    text = text.strip()
    if control.kind == "slider":
        return float(text) if _NUMBER.fullmatch(text) else text
    if control.kind == "switch":
        return {"true": True, "false": False}.get(text, text)
    if control.kind == "color":
        return "#" + text if _HEX6.fullmatch(text) else text
    if control.kind == "select":
        return text
    parts = [_word(p.strip()) for p in text.split(",")] if text else [text]
    return parts[0] if len(parts) == 1 else parts


def apply_settings(pairs, scene, options, controls):
    """Apply address settings ``[(path, text)]`` to ``scene`` and view ``options`` through the page's controls.

    ``controls`` is a :class:`~phonglab.app.controls.ControlSet` of this
    lesson that only this call uses: it is fitted to each new scene, so a
    light's type applies before its cone. Light types are applied first,
    then the rest in address order.

    Returns
    -------
    scene, options, problems
        The new scene and options; one line per refused value or unknown key.
    """
    options = dict(options)
    problems = []
    ordered = sorted(pairs, key=lambda pair: not pair[0].endswith(".type"))  # stable: address order kept
    for path, text in ordered:
        controls.update(scene)
        try:
            control = controls.by_key.get(state_key(path))
        except ValueError:
            control = None
        if control is None or path == "lesson":
            problems.append(wording.unknown_setting(path, text))
            continue
        try:
            scene, options = control.apply(scene, parse_setting(control, text), options)
        except ControlError as exc:
            problems.append(wording.refusal(path, text, control, exc))
    return scene, options, problems


def notice(problems) -> str:
    """The problems of one address (plain sentences, :mod:`phonglab.app.wording`) as the page's one-line notice."""
    return wording.address_notice(problems)
