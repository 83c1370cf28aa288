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
  ``material.shininess``, ``roughness``, ``metallic``, ``lights[i].position``
  / ``direction`` / ``attenuation``, ``probe``, ``shadows``,
  ``shadow_bias``, and in a scene of several objects each object's
  ``objects[i].name``, ``objects[i].material.*`` and
  ``objects[i].geometry.kind`` / ``resolution`` / ``center`` / ``scale`` (numbers joined by commas; a grey
  coefficient as one number);
- what a widget sets: ``lights[i].type``, ``lights[i].color`` (six hex
  digits, sRGB as the colour picker shows it), ``intensity``, ``cutoff``,
  ``no_cone``, ``exponent``; ``model``, ``interpolation``, ``two_sided``,
  ``camera.infinite_viewer``, ``display``, ``exposure``; the shape
  (``geometry.kind``, ``geometry.resolution``); the view options
  ``view.term`` and ``view.mistake``;
- the eye as ``camera.azimuth`` / ``elevation`` / ``distance`` (the eye
  sliders, around the focal point in the lesson's frame); what the sliders
  cannot say (a roll, a pan, an eye nearer than the distance slider goes)
  as ``camera.eye`` / ``up`` / ``focal_point`` in file form, and
  ``view.turned=true`` for a view turned by the mouse (shown through the
  browser's camera as it is: its view angle is not widened to hold the
  arrows), so the picture is framed the same.

An address reopens the scene on screen, whatever changed it (a slider, an
experiment, a pick, a turn, Reset): :meth:`ViewAddress.query` writes the
settings in the widgets' form, reopens them as a fresh tab would
(:func:`apply_settings`) and writes in file form, with every digit, each
scene field that did not come back: a value beyond its slider's range (an
experiment's intensity 5), a colour that is not an sRGB hex code, a cutoff
of 120°, a turned camera's up vector. A slider's value is written with the
digits it needs to read back (``0.8``, ``31.7``; more for an eye turned by
the mouse), a file-form number as Python writes it back exactly.
Reading, a value its widget refuses is tried in file form, which the scene
checks (:func:`apply_settings`).
"""

from __future__ import annotations

import math
import re
from urllib.parse import parse_qs, parse_qsl, urlencode

from phonglab.app import wording
from phonglab.app.control import Control, ControlError
from phonglab.app.keys import state_key
from phonglab.scene import SceneError, field_value, scene_to_dict

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
#: a number read back within this fraction of its size (at least 1) is the same number
SAME = 1e-9
#: most decimals a slider's value is written with
MAX_DECIMALS = 12

#: widgets whose field the address carries in file form instead (or not at all)
_PRESENTATION = re.compile(
    r"material\.(ka|kd|ks)\.(level|color)|material\.shininess\.log"
    r"|lights\[\d+\]\.(azimuth|elevation|distance)|lights\[\d+\]\.attenuation\[\d+\]"
)
#: file-form fields whose three equal numbers may be written as one
_GREY = re.compile(r"(objects\[\d+\]\.)?material\.(ka|kd|ks|emission)")
_HEX6 = re.compile(r"[0-9a-fA-F]{6}")
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
#: scene fields an address may set in their file form (the scene checks the value)
FILE_FIELDS = re.compile(
    r"(objects\[\d+\]\.)?material\.(ka|kd|ks|shininess|emission|opacity|roughness|metallic)"
    r"|lights\[\d+\]\.(position|direction|color|intensity|attenuation|cutoff|exponent|diffuse|specular)"
    r"|camera\.(eye|focal_point|up|view_angle|infinite_viewer)"
    r"|(objects\[\d+\]\.)?geometry\.(kind|resolution|center|scale)|objects\[\d+\]\.name"
    r"|model|interpolation|two_sided|display|exposure|probe|shadows|shadow_bias"
    r"|area_light\.(position|edge_u|edge_v|color|intensity|method|samples)"
)
#: the default view options of a lesson (lesson_app resets to these)
DEFAULT_OPTIONS = {"term": "color"}
#: keys of an address that trame's own page reads (its iframe in a notebook opens ``?ui=main&reconnect=auto``)
CLIENT_KEYS = frozenset(("ui", "reconnect"))


#: a view turned by the mouse is shown through the browser's camera as it is (its view angle not widened
#: to hold the arrows, :meth:`phonglab.render.SceneView.update`): the address says so, the picture is the same
TURNED = Control(
    path="view.turned",
    label="the view as turned by the mouse",
    kind="switch",
    read=lambda scene, options: bool(options.get("turned", False)),
    write=lambda scene, value, options: (scene, {**options, "turned": True} if value
                                         else {k: v for k, v in options.items() if k != "turned"}),
    group="View",
)
#: settings only the address has (no widget on the page): path -> control
ADDRESS_ONLY = {TURNED.path: TURNED}


def turned(options: dict, value: bool) -> dict:
    """View ``options`` saying whether the view shows a camera turned by the mouse (:data:`TURNED`)."""
    return TURNED.write(None, value, options)[1]


def _control(controls, path):
    """The control of an address key: the page's, or one only the address has; None for an unknown key."""
    try:
        key = state_key(path)
    except ValueError:
        return None
    return controls.by_key.get(key) or ADDRESS_ONLY.get(path)


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
    for path in types + rest + others + list(ADDRESS_ONLY):
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


def exact_number(x) -> str:
    """``x`` in the fewest digits that read back as the same float (``0.35``, ``5``, ``0.30000000000000004``)."""
    x = float(x)
    if x == 0:
        return "0"
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def _same_number(a, b) -> bool:
    """Whether two numbers are the same to :data:`SAME` of their size (at least 1)."""
    return abs(a - b) <= SAME * max(1.0, abs(a), abs(b))


def slider_text(control, value) -> str | None:
    """A slider's value in the fewest decimals (at least a tenth of its step) that read back as it.

    None past the slider's ends: a value there is written in file form instead
    (:meth:`ViewAddress.query`), the slider could not take it.
    """
    value = float(value)
    slack = 1e-9 * max(1.0, abs(control.high - control.low))
    if not (control.low - slack <= value <= control.high + slack):
        return None
    for decimals in range(_decimals(control.step), MAX_DECIMALS + 1):
        if _same_number(round(value, decimals), value):
            break
    return compact_number(value, decimals)


def format_setting(control, value) -> str | None:
    """A control's value as the address writes it; None when the widget cannot say it (see :func:`slider_text`)."""
    if control.kind == "slider":
        return slider_text(control, value)
    if control.kind == "switch":
        return "true" if value else "false"
    if control.kind == "color":
        return str(value).lstrip("#").lower()
    if control.kind == "select":
        return str(value)
    return _format_plain(control.path, value)


def _format_plain(path, value) -> str | None:
    """A file-form value, exactly: numbers joined by commas, a grey coefficient as one number."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return exact_number(value)
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)) and value and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        parts = [exact_number(v) for v in value]
        if _GREY.fullmatch(path) and len(set(parts)) == 1:
            return parts[0]
        return ",".join(parts)
    return None


def _fields(data, prefix=""):
    """``{path: value}`` of the file-form fields a scene's dictionary holds (lights and tables walked into)."""
    out = {}
    for key, value in data.items():
        path = f"{prefix}.{key}" if prefix else key
        if key in ("lights", "objects") and not prefix:
            for i, item in enumerate(value):
                out.update(_fields(item, f"{key}[{i}]"))
        elif isinstance(value, dict):
            out.update(_fields(value, path))
        else:
            out[path] = value
    return out


def _same_value(a, b) -> bool:
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same_value(x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool) or not all(isinstance(x, (int, float)) for x in (a, b)):
        return a == b
    return _same_number(float(a), float(b))


def differing_fields(scene, other) -> list[str]:
    """The file-form fields (:data:`FILE_FIELDS`) in which ``other`` is not ``scene``, to :data:`SAME`."""
    return _differing(_fields(scene_to_dict(scene)), _fields(scene_to_dict(other)))


def _differing(a: dict, b: dict) -> list[str]:  # differing_fields of two scenes' _fields
    return [path for path in a if FILE_FIELDS.fullmatch(path)
            and (path not in b or not _same_value(a[path], b[path]))]


def _stands_for(field: str, setting: str) -> bool:
    """Whether the widget ``setting`` presents the file-form ``field`` (a light's azimuth its position)."""
    if field in ("camera.eye", "camera.focal_point"):
        return setting in ("camera.azimuth", "camera.elevation", "camera.distance")
    m = re.fullmatch(r"(lights\[\d+\])\.(position|direction|cutoff)", field)
    if m:
        names = ("no_cone",) if m.group(2) == "cutoff" else ("azimuth", "elevation", "distance")
        return setting in {f"{m.group(1)}.{name}" for name in names}
    return False


_UNREAD = object()


def _keep_last(kept: dict, count: int) -> None:
    """Forget the oldest entries of ``kept`` (insertion order) past ``count``."""
    while len(kept) > count:
        kept.pop(next(iter(kept)))


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
        # (lesson scene id, settings) -> [what they open, its file-form fields once asked]: the last few kept
        self._reopened: dict = {}
        # (lesson scene id, setting paths) -> ({index: text read}, what the widget settings gave): the last few
        self._widget_steps: dict = {}

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
        """``(path, text)`` for every widget setting of ``scene``/``options`` that differs from the lesson's.

        ``values`` (state key -> widget value, :meth:`ControlSet.values`) saves reading them again.
        A value its widget cannot say is left out (:meth:`query` writes its field instead).
        """
        current = []
        for path in setting_paths(controls):
            key = state_key(path)
            control = _control(controls, path)
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

    def reopen(self, entry, settings, controls):
        """What a fresh tab opens for ``settings``: ``(scene, options, problems)`` (the last few are kept)."""
        return self._kept(entry, settings, controls)[0]

    def _kept(self, entry, settings, controls) -> list:
        """``[reopen(...), its scene's file-form fields or None until asked]`` for ``settings``."""
        key = (id(entry.scene), tuple(settings))
        if key not in self._reopened:
            self._reopened[key] = [self._reopen(entry, settings, controls), None]
            _keep_last(self._reopened, 8)
        return self._reopened[key]

    def _reopen(self, entry, settings, controls):
        """:func:`apply_settings` of ``settings`` on the lesson's scene, in a fresh tab's controls.

        A slider step usually changes one file-form field's text (the shininess
        of a lesson that shows no shininess slider): the widget settings before
        the fields are then the same as the last time, and only the fields are
        applied again on the scene they gave (:func:`_widget_settings` says
        which texts it read; the others it leaves for :func:`_apply_fields`).
        """
        paths = tuple(path for path, _ in settings)
        shape = (id(entry.scene), paths)
        seen = self._widget_steps.get(shape)
        if seen is None or any(settings[i][1] != text for i, text in seen[0].items()):
            scratch = type(controls)(controls.frame, controls.lesson_paths, controls.extra)
            scene, options, problems, fields, read = _widget_settings(settings, entry.scene, dict(DEFAULT_OPTIONS),
                                                                     scratch)
            seen = ({i: settings[i][1] for i in read}, (scene, options, problems, fields))
            self._widget_steps[shape] = seen
            _keep_last(self._widget_steps, 8)
        scene, options, problems, fields = seen[1]
        options, problems = dict(options), list(problems)
        if fields:
            scene, refusals = _apply_fields(scene, [(path, settings[i][1], refused) for i, path, _, refused in fields])
            problems += refusals
        return scene, options, problems

    def _reopened_differ(self, entry, settings, controls, fields) -> list[str]:
        """:func:`differing_fields` of the scene with ``fields`` and what ``settings`` reopen (its fields kept with it)."""
        kept = self._kept(entry, settings, controls)
        if kept[1] is None:
            kept[1] = _fields(scene_to_dict(kept[0][0]))
        return _differing(fields, kept[1])

    def faithful(self, entry, scene, options, controls, settings) -> list[tuple[str, str]]:
        """``settings`` with, in file form, each scene field they do not bring back.

        The settings are reopened as a fresh tab would (:meth:`reopen`); a field
        that comes back otherwise is written with every digit, in place of a
        widget setting of the same path or after the rest, and the widget
        settings that stand for it (a light's azimuth for its position) go.
        Three rounds at most: the field values are exact, so one usually does.
        """
        settings = list(settings)
        fields = _fields(controls.file_form(scene))  # the file form the controls read the scene's values from
        for _ in range(3):
            missing = self._reopened_differ(entry, settings, controls, fields)
            if not missing:
                break
            for path in missing:
                text = _format_plain(path, field_value(scene, path))
                if text is None:
                    continue
                settings = [(p, t) for p, t in settings if not _stands_for(path, p)]
                at = [i for i, (p, _) in enumerate(settings) if p == path]
                if at:
                    settings[at[0]] = (path, text)
                else:
                    settings.append((path, text))
        return settings

    def query(self, entry, scene, options, controls, values=None) -> str:
        """``?lesson=…&path=value…`` for the view on screen (``entry``'s lesson, ``scene``, view ``options``).

        ``controls`` is the tab's :class:`~phonglab.app.controls.ControlSet`, fitted to ``scene``;
        ``values`` its widget values for ``scene``, if already read. Opening the
        address gives ``scene`` and the view options back (:meth:`faithful`).
        """
        settings = self.settings(entry, scene, options, controls, values)
        settings = self.faithful(entry, scene, options, controls, settings)[:MAX_SETTINGS]
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
    pairs = [(k, v) for k, v in pairs if k != "lesson" and k not in CLIENT_KEYS]
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


def file_control(path: str) -> Control:
    """A control that sets the scene field ``path`` in its file form (the scene checks the value)."""

    def read(scene, options):
        return field_value(scene, path)

    def write(scene, value, options):
        return scene.replace(path, value), options

    return Control(path=path, label=path, kind="value", read=read, write=write)


def _has_field(scene, path: str) -> bool:
    """Whether ``path`` is a file-form field an address may set (:data:`FILE_FIELDS`) and ``scene`` has."""
    if not FILE_FIELDS.fullmatch(path):
        return False
    try:
        field_value(scene, path)
    except SceneError:
        return False
    return True


def apply_settings(pairs, scene, options, controls):
    """Apply address settings ``[(path, text)]`` to ``scene`` and view ``options`` through the page's controls.

    ``controls`` is a :class:`~phonglab.app.controls.ControlSet` of this
    lesson that only this call uses: it is fitted to each new scene, so a
    light's type applies before its cone. Light types are applied first,
    then the widget settings in address order, then the file-form fields
    (:data:`FILE_FIELDS`) together, as one edit the scene checks once (a
    camera's eye and up vector may make sense only together). A value its
    widget refuses (an intensity of 5, past the slider) is tried as the
    field's file form: the address takes what a lesson file takes.

    Returns
    -------
    scene, options, problems
        The new scene and options; one line per refused value or unknown key.
    """
    scene, options, problems, fields, _ = _widget_settings(pairs, scene, options, controls)
    if fields:
        scene, refusals = _apply_fields(scene, [field[1:] for field in fields])
        problems += refusals
    return scene, options, problems


def _widget_settings(pairs, scene, options, controls):
    """:func:`apply_settings` up to the file-form fields: the widget settings applied, the fields gathered.

    Returns ``scene, options, problems, fields, read``: ``fields`` are
    ``(index in pairs, path, text, the widget's refusal or None)`` in the
    order to apply them; ``read`` the indices of ``pairs`` whose text this
    step read. A field no widget refused is the only setting it leaves unread:
    its text waits for :func:`_apply_fields`, so settings that differ only in
    such texts come this far alike (:meth:`ViewAddress.reopen` keeps it).
    """
    options = dict(options)
    problems = []
    fields = []
    read = set()
    order = sorted(range(len(pairs)), key=lambda i: not pairs[i][0].endswith(".type"))  # stable: address order
    for index in order:
        path, text = pairs[index]
        controls.update(scene)
        control = _control(controls, path)
        refused = None
        if control is not None and control.kind != "value" and path != "lesson":
            read.add(index)
            try:
                scene, options = control.apply(scene, parse_setting(control, text), options)
                continue
            except ControlError as exc:
                refused = (control, exc)
        if _has_field(scene, path):
            fields.append((index, path, text, refused))
        else:
            read.add(index)
            problems.append(wording.unknown_setting(path, text) if refused is None
                            else wording.refusal(path, text, *refused))
    return scene, options, problems, fields, read


def _apply_fields(scene, fields):
    """The file-form ``fields`` ``[(path, text, refusal)]`` applied together; one by one if the scene refuses that.

    Returns the scene and a sentence per refused field (the scene's rule: what a lesson file takes).
    """
    controls = [(path, text, file_control(path), refused) for path, text, refused in fields]
    try:
        values = [(path, control.check(parse_setting(control, text))) for path, text, control, _ in controls]
        return scene.replace_many(values), []
    except (ControlError, SceneError, ValueError, TypeError, ArithmeticError):
        pass
    problems = []
    for path, text, control, refused in controls:
        try:
            scene, _ = control.apply(scene, parse_setting(control, text), {})
        except ControlError as exc:
            # a slider's range is not the field's: the field's rule; a select's choices or a colour's form are
            if refused is not None and refused[0].kind != "slider":
                control, exc = refused
            problems.append(wording.refusal(path, text, control, exc))
    return scene, problems


def notice(problems) -> str:
    """The problems of one address (plain sentences, :mod:`phonglab.app.wording`) as the page's one-line notice."""
    return wording.address_notice(problems)
