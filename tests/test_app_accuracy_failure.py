"""The accuracy lesson's studies that cannot finish: plain words, the last figures kept, and "Try again".

The worker processes are replaced by futures the test completes (or never does); the wait for them is
cut from 3 minutes to a fraction of a second. What a student reads must carry no exception's name.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import concurrent.futures.process
import time

import pytest

from phonglab.app import accuracy_panel as panel
from phonglab.bench.scenes import LESSONS

#: words of Python's, not a student's
RAW = ("Error", "Exception", "Traceback", "no result after", "concurrent", "Future")


@pytest.fixture
def work(monkeypatch):
    """Every submitted call, as ``[name, args, future]``; nothing runs unless the test completes the future."""
    made = []

    def submit(function, *args):
        future = concurrent.futures.Future()
        made.append([function.__name__, args, future])
        return future

    monkeypatch.setattr(panel, "submit", submit)
    monkeypatch.setattr(panel, "_plot", None)
    monkeypatch.setattr(panel, "TIMEOUT", 0.2)
    return made


async def _until(condition, what, seconds=30.0):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        await asyncio.sleep(0.01)


def _plain(text, what):
    assert text and not any(word in text for word in RAW), (what, text)


def test_a_study_that_cannot_finish_says_so_keeps_the_last_figures_and_offers_to_try_again(work, tmp_path):
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    (tmp_path / "11-accuracy.md").write_text(LESSONS["11-accuracy.md"], encoding="utf-8")
    first_images = {"method": "gouraud", "figures": [{"name": "RMSE", "value": "0.01"}]}

    async def scenario():
        app = LessonApp(get_server(f"accuracy-failure-{tmp_path.name}", client_type="vue3"),
                        target=tmp_path / "11-accuracy.md")
        try:
            s = app.state
            s.ready()  # as when the page has connected: the state's change handlers run on a flush
            pending = lambda name: [w for w in work if w[0] == name and not w[2].done()]  # noqa: E731
            # the first error images come; the plot's studies never do
            await _until(lambda: pending("error_panel"), "the first error images to be asked for")
            pending("error_panel")[0][2].set_result(first_images)
            await _until(lambda: s.accuracy_plot["status"] == "failed", "the plot to give up")
            _plain(s.accuracy_plot["error"], "the plot's failure")
            assert "did not finish" in s.accuracy_plot["error"], s.accuracy_plot
            assert s.accuracy_view == first_images
            # a new pick whose images never come: the last images stay, and the page says why, in words
            s.accuracy_resolution = 64
            app.accuracy._on_pick("accuracy_resolution", panel.check_resolution)
            assert s.accuracy_busy and "64 segments" in s.accuracy_measuring, s.accuracy_measuring
            await _until(lambda: s.accuracy_failed, "the images to give up")
            _plain(s.accuracy_failed, "the images' failure")
            assert "64 segments" in s.accuracy_failed and "The last figures stay" in s.accuracy_failed, s.accuracy_failed
            assert s.accuracy_view == first_images and not s.accuracy_busy
            assert s.notice is None or not any(word in s.notice["text"] for word in RAW), s.notice
            # "Try again": both are asked for once more, and this time they come
            asked = len(work)
            s.accuracy_retry = s.accuracy_retry + 1
            s.flush()
            names = sorted(w[0] for w in work[asked:])
            assert names == ["error_panel", "plot_data_url"], names
            for name, args, future in work[asked:]:
                future.set_result("data:image/png;base64,cGxvdA==" if name == "plot_data_url"
                                  else {**first_images, "resolution": args[1]})
            await _until(lambda: s.accuracy_plot["status"] == "ready" and not s.accuracy_busy, "the second try")
            assert s.accuracy_view["resolution"] == 64 and s.accuracy_failed == "", (s.accuracy_view, s.accuracy_failed)
        finally:
            app.close()

    asyncio.run(scenario())


@pytest.mark.parametrize("exc, words", [
    (TimeoutError("no result after 180 s"), "did not finish within 3 minutes: the server is busy"),
    (concurrent.futures.process.BrokenProcessPool("A child process terminated abruptly"),
     "stopped: the process measuring it ended"),
    (RuntimeError("matplotlib is missing"), "stopped with an error (the server's log has the details)"),
])
def test_every_failure_is_a_plain_sentence(exc, words):
    text = panel.failure_words(exc, "The accuracy plot's four studies", kept=True)
    assert text == f"The accuracy plot's four studies {words}. The last figures stay.", text
    _plain(text, exc)
