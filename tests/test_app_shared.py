"""What every tab of a server shares, read-only: the lesson list, the lessons' HTML, the controls templates.

A class opens its tabs at once; each tab used to parse every lesson, typeset
its text and draw the controls again. These tests open thirty tabs at once
through the session server with raw wslink clients and check that each gets
its own lesson and settings while the lesson files are read once; and that
what is shared is what a tab would have made itself, and follows a lesson
file edited on disk.
"""

from __future__ import annotations

import asyncio
import os
import re
from pathlib import Path
from types import SimpleNamespace

import pytest
from app_support import in_thread
from test_app_security import logged_in, run

from phonglab.app import shared
from phonglab.app.server import SessionServer

LESSONS = Path(__file__).resolve().parent.parent / "lessons"
#: tabs opened at once
TABS = 30
#: seconds a tab may wait for its session (a guard against a hang: on a loaded 2-core machine the
#: thirty sessions are built one after another while the tests' other workers run)
PATIENCE = 600


@pytest.fixture
def reads(monkeypatch):
    """Every lesson file read by the scene layer while the test runs, by name."""
    from phonglab.scene import lessons

    seen = []
    load_entry = lessons.load_entry

    def counting(path):
        seen.append(Path(path).name)
        return load_entry(path)

    monkeypatch.setattr(lessons, "load_entry", counting)
    shared._catalogs.clear()  # a list kept by an earlier test is not read here
    return seen


@pytest.fixture
def class_server(tmp_path, reads):
    """A SessionServer on a copy of the course's lessons, in a thread, with the default session limit."""
    from phonglab.app import make_app

    folder = tmp_path / "lessons"
    folder.mkdir()
    for path in LESSONS.glob("[0-9]*.md"):
        (folder / path.name).write_text(path.read_text(encoding="utf-8"), encoding="utf-8")
    server = SessionServer(make_app(folder))
    with in_thread(server) as port:
        yield SimpleNamespace(server=server, port=port, folder=folder)


async def open_tab(port: int, ks: float) -> dict:
    """A tab opened at ``?lesson=04-specular&material.ks=KS``: the state it is left with."""
    client = await logged_in(port, timeout=PATIENCE)
    try:
        await client.call("trame.state.get", timeout=PATIENCE)
        query = f"?lesson=04-specular&material.ks={ks}"
        answer = await client.call("trame.state.update", [[{"key": "url_request", "value": query}]], timeout=PATIENCE)
        assert answer is not None and "error" not in answer, (query, answer)
        state = await client.call("trame.state.get", timeout=PATIENCE)
        return state["result"]["state"]
    finally:
        await client.__aexit__()


def test_thirty_tabs_opened_at_once_each_get_their_lesson_and_the_lessons_are_read_once(class_server, reads):
    files = sorted(p.name for p in class_server.folder.glob("*.md"))
    assert sorted(reads) == files, "the server's start reads each lesson once"

    async def together():
        return await asyncio.gather(*(open_tab(class_server.port, round(0.01 * (i + 1), 2)) for i in range(TABS)))

    states = run(together(), timeout=PATIENCE)
    for i, state in enumerate(states):
        ks = round(0.01 * (i + 1), 2)  # never the lesson's own 0.6, so the address carries it
        assert state["lesson_number"] == 4, (i, state.get("lesson_number"), state.get("notice"))
        assert state["material__ks"] == [ks, ks, ks], (i, ks, state["material__ks"])  # its own setting
        assert f"material.ks={ks:g}" in state["url_query"], (i, ks, state["url_query"])
        assert state["lesson_html"] and "<math" in state["lesson_html"], i
    assert sorted(reads) == files, f"{TABS} tabs read the lessons again: {len(reads)} reads of {len(files)} files"


def test_a_lesson_edited_on_disk_is_read_again_by_the_next_tab(tmp_path, reads):
    lesson = tmp_path / "04-specular.md"
    lesson.write_text((LESSONS / "04-specular.md").read_text(encoding="utf-8"), encoding="utf-8")
    first, _ = shared.lesson_catalog(tmp_path)
    again, _ = shared.lesson_catalog(tmp_path)
    assert reads == ["04-specular.md"] and again[0] is first[0], reads
    text = lesson.read_text(encoding="utf-8").replace('title = "Specular highlights (Phong)"', 'title = "Edited"')
    lesson.write_text(text, encoding="utf-8")
    stat = lesson.stat()
    os.utime(lesson, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000))  # a later time, however coarse the clock
    edited, _ = shared.lesson_catalog(tmp_path)
    assert reads == ["04-specular.md"] * 2 and edited[0].title == "Edited", (reads, edited[0].title)


def test_the_shared_lesson_html_is_what_the_lesson_renders_to():
    from phonglab.app import text
    from phonglab.scene import load_lesson

    lesson = load_lesson(LESSONS / "04-specular.md")
    texts = shared.lesson_texts(lesson)
    assert texts["lesson_html"] == text.render_markdown(text.strip_title(lesson.body, lesson.title))
    assert texts["answer_html"] == text.render_markdown(lesson.answer)
    assert [x["label"] for x in texts["experiments"]] == [text.inline(x.label) for x in lesson.experiments]
    texts["experiments"].clear()  # one tab's copy: the next tab's is whole
    assert len(shared.lesson_texts(lesson)["experiments"]) == len(lesson.experiments)


def test_the_controls_template_is_drawn_once_and_is_the_same_for_every_tab(tmp_path, monkeypatch):
    from trame.app import get_server

    from phonglab.app import page
    from phonglab.app.lesson_app import LessonApp

    (tmp_path / "04-specular.md").write_text((LESSONS / "04-specular.md").read_text(encoding="utf-8"),
                                             encoding="utf-8")
    shared._templates.clear()
    drawn = []
    build_controls = page.build_controls

    def counting(server, chosen, all_controls=()):
        drawn.append(len(all_controls))
        return build_controls(server, chosen, all_controls)

    monkeypatch.setattr(page, "build_controls", counting)
    key = f"trame__template_{page.CONTROLS_TEMPLATE}"

    def same(template: str) -> str:
        # trame numbers every widget it draws (":key" w<n>-...): unique within a page, not the same twice
        return re.sub(r"w\d+-", "w-", template)

    apps = [LessonApp(get_server(f"shared-{tmp_path.name}-{i}", client_type="vue3"), target=tmp_path) for i in range(3)]
    try:
        templates = [app.state[key] for app in apps]
        assert len(drawn) == 1, drawn
        assert templates[0] and templates.count(templates[0]) == 3, "the tabs' templates differ"
        monkeypatch.setattr(page, "build_controls", build_controls)
        shared._templates.clear()
        fresh = LessonApp(get_server(f"shared-{tmp_path.name}-fresh", client_type="vue3"), target=tmp_path)
        apps.append(fresh)
        assert same(fresh.state[key]) == same(templates[0]), "a template drawn for the tab itself differs from the shared one"
    finally:
        for app in apps:
            app.close()


def test_a_spots_cutoff_slider_says_no_cone_while_its_switch_holds_the_cutoff_at_180(tmp_path):
    """The slider stops at 90°: beside a cutoff of 180° it read "90°" (lesson 7's first experiment)."""
    from trame.app import get_server

    from phonglab.app import page
    from phonglab.app.lesson_app import LessonApp

    (tmp_path / "07-light-sources.md").write_text((LESSONS / "07-light-sources.md").read_text(encoding="utf-8"),
                                                  encoding="utf-8")
    shared._templates.clear()
    app = LessonApp(get_server(f"cone-{tmp_path.name}", client_type="vue3"), target=tmp_path)
    try:
        template = app.state[f"trame__template_{page.CONTROLS_TEMPLATE}"]
        widget = re.search(r'<div class="phonglab-control phonglab-control-(lights_\d+)__cutoff".*?<VSlider',
                           template, re.S)
        assert widget, template[:2000]
        light, text = widget.group(1), widget.group(0)
        assert f"{light}__no_cone ? '180° (no cone)' : control_values['{light}__cutoff']" in text, text
        assert f"({light}__no_cone) ? 'opacity: 0.6'" in text, text
    finally:
        app.close()
