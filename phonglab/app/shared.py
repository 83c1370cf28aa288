"""What every tab of one server reads and none changes: made once per process, not once per tab.

A server builds one :class:`~phonglab.app.lesson_app.LessonApp` per browser
tab, and a class opens its tabs all at once. Three things a tab needs are
the same for every tab and were made again for each:

* the lesson list (:func:`lesson_catalog`): every lesson file parsed and
  checked, its claims included;
* a lesson's text as HTML (:func:`lesson_texts`): Markdown and MathML;
* the controls panel's template (:func:`controls_template`): the page's
  widgets for a set of controls, a template string the browser draws.

They are kept here and handed to every tab. Nothing here is written after
it is made, and no tab's state is kept here: only what a file or the code
decides. A lesson file that changes on disk (its size or modification
time) is read again by the next tab that opens, as before.
"""

from __future__ import annotations

import copy
import dataclasses
import threading
from pathlib import Path

from phonglab.app import text
from phonglab.app.control import Control
from phonglab.scene.lessons import catalog
from phonglab.scene.loader import lesson_files

_lock = threading.Lock()
#: resolved target -> (the files' signature, (entries, first))
_catalogs: dict = {}
#: id(lesson) -> (lesson, its texts); the lesson is kept so its id is not reused while the entry lives
_texts: dict = {}
#: the controls' drawn fields -> the template's HTML
_templates: dict = {}
#: templates kept at most (a lesson's set of controls each, and one per set of light types it passes through)
MAX_TEMPLATES = 256


def _files(target: Path) -> list[Path]:
    """The files :func:`~phonglab.scene.lessons.catalog` reads for ``target``."""
    if target.is_dir():
        return lesson_files(target)
    if target.suffix.lower() == ".toml":
        return [target]
    return [target, *lesson_files(target.parent)]


def _signature(target: Path) -> tuple:
    """Each file's path, size and modification time: a change to any of them reads the list again."""
    out = []
    for path in _files(target):
        try:
            stat = path.stat()
        except OSError:
            out.append((str(path), None))
        else:
            out.append((str(path), stat.st_size, stat.st_mtime_ns))
    return tuple(out)


def lesson_catalog(target) -> tuple[list, int]:
    """:func:`phonglab.scene.lessons.catalog` of ``target``, read once while its files stay as they are.

    Returns
    -------
    (entries, first)
        A new list of the shared entries (read-only: a tab must not change
        them) and the index to open first.
    """
    target = Path(target)
    key = target.resolve()
    signature = _signature(target)
    with _lock:
        kept = _catalogs.get(key)
        if kept is None or kept[0] != signature:
            entries, first = catalog(target)
            kept = _catalogs[key] = (signature, (tuple(entries), first))
            # the texts of lessons no list holds any more are not needed
            alive = {id(e.lesson) for signature_, (listed, _) in _catalogs.values() for e in listed}
            for stale in [k for k in _texts if k not in alive]:
                del _texts[stale]
    entries, first = kept[1]
    return list(entries), first


#: the page's texts of no lesson (a file with errors, or a scene file)
NO_TEXTS = {"lesson_goal_html": "", "lesson_html": "", "experiments": [], "question_html": "", "answer_html": ""}


def lesson_texts(lesson) -> dict:
    """The page's HTML of ``lesson``: goal, body, experiments, question and answer (state key -> value).

    Each call returns new containers (a tab's state holds them); the strings are shared.
    ``lesson`` None gives :data:`NO_TEXTS`.
    """
    if lesson is None:
        return copy.deepcopy(NO_TEXTS)
    with _lock:
        kept = _texts.get(id(lesson))
        if kept is None or kept[0] is not lesson:
            kept = _texts[id(lesson)] = (lesson, _make_texts(lesson))
    return copy.deepcopy(kept[1])


def _make_texts(lesson) -> dict:
    return {
        "lesson_goal_html": text.inline(lesson.goal) if lesson.goal else "",
        "lesson_html": text.render_markdown(text.strip_title(lesson.body, lesson.title)),
        "experiments": [
            {"index": i, "label": text.inline(x.label), "text": text.inline(x.text) if x.text else ""}
            for i, x in enumerate(lesson.experiments)
        ],
        "question_html": text.inline(lesson.question) if lesson.question else "",
        "answer_html": text.render_markdown(text.symbols_as_math(lesson.answer)) if lesson.answer else "",
    }


#: what of a control its widget shows (everything but how it reads and writes the scene)
_DRAWN = tuple(f.name for f in dataclasses.fields(Control) if f.name not in ("read", "write"))


def _drawn(controls) -> tuple:
    return tuple(tuple(getattr(c, name) for name in _DRAWN) for c in controls)


def controls_template(server, name: str, chosen, widgets, build) -> None:
    """Put the controls panel's template (trame template ``name``) for ``chosen`` and ``widgets`` into ``server``'s state.

    ``build(server, chosen, widgets)`` draws it (:func:`phonglab.app.page.build_controls`)
    the first time a set of controls is seen; every later tab with the same
    set gets the same HTML without drawing the widgets again. The widgets
    bind state keys and carry browser-side expressions only: drawing them
    leaves nothing else on the server.
    """
    state_key = f"trame__template_{name}"
    key = (name, _drawn(chosen), _drawn(widgets))
    with _lock:
        html = _templates.get(key)
    if html is None:
        build(server, chosen, widgets)
        html = server.state[state_key]
        with _lock:
            if len(_templates) >= MAX_TEMPLATES:
                _templates.pop(next(iter(_templates)))
            _templates[key] = html
    else:
        server.state[state_key] = html
