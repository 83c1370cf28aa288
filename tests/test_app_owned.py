"""Keys the browser can write cannot wedge a tab; notices stay short and name no exception class."""

from __future__ import annotations

import pytest

from phonglab.app import owned

from test_app_page import MISTAKE_LESSON  # the lesson with a mistake switch


@pytest.fixture
def app(lesson_app):
    return lesson_app("01-raw.md", MISTAKE_LESSON, "test-owned")


@pytest.mark.parametrize("written", ["abc", 3, [1, 2], {"available": True}, None])
def test_a_browser_write_to_the_mistake_key_is_undone_and_controls_keep_working(app, written):
    ours = app.state.mistake
    app.state.ready()  # change handlers run on flush once the state is ready, as in a served page
    app.state.mistake = written  # what trame.state.set('mistake', ...) from a tab does
    app.state.flush()
    assert app.state.mistake == ours, f"mistake = {written!r} stayed in the state"
    app._on_control("view__mistake", True)
    assert app.view.mistake == "unnormalised-normals", app.state.notice
    app._on_control("material__ks__level", 0.3)
    assert app.state.notice is None or app.state.notice["kind"] != "error", app.state.notice


def test_a_light_past_the_coordinate_bound_is_refused_like_check_refuses_it(app):
    scene = app.scene
    key = next(k for k, c in app.controls.by_key.items() if c.path.endswith("position") and c.kind == "value")
    app._on_control(key, [-1e308, 0, 0])
    assert app.scene is scene
    text = app.state.notice["text"]
    assert "Refused" in text and "1,000,000" in text, text


def test_a_huge_value_is_not_echoed_whole(app):
    app._on_control("material__ks__level", list(range(100_000)))
    text = app.state.notice["text"]
    assert len(text) <= owned.NOTICE_CHARS and "99999" not in text, text[:400]


def test_notices_carry_the_reason_not_the_exception_class(app, monkeypatch):
    def broken(*args, **kwargs):
        raise AttributeError("'str' object has no attribute 'get'")

    monkeypatch.setattr(app.view, "update", broken)
    app._on_control("material__ks__level", 0.3)
    text = app.state.notice["text"]
    assert "AttributeError" not in text and "no attribute" in text, text
    assert owned.reason(RuntimeError("")).startswith("an internal error")
    assert len(owned.short("x" * 10_000)) == owned.NOTICE_CHARS


@pytest.mark.parametrize("bad", ["\x00", "\u202e", "\x1b[31m"])
def test_a_page_value_is_echoed_with_hidden_characters_escaped(app, bad):
    key = next(k for k, c in app.controls.by_key.items() if c.path == "material.kd" and c.kind == "value")
    app._on_control(key, [f"0.5{bad}", 1, 1])
    text = app.state.notice["text"]
    assert "Refused" in text and bad[0] not in text, text
    assert "\\x00" in text or "\\u202e" in text or "\\x1b" in text, text
    app.notify("error", f"no such lesson: {bad}")  # any notice, whatever made it
    assert bad[0] not in app.state.notice["text"], app.state.notice
