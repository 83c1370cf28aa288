"""Over the core's per-pixel picture, the numbers are those of the eye the picture shows.

The picture for a new eye takes its time (its NumPy half is made in a thread,
:mod:`phonglab.app.pixel_picture`); the readout and the letters' tips for that
eye arrive with it, in the same state update, and the page says "updating"
meanwhile (``pixel_pending``). Here the thread is held until the test lets it
go, so the moment between the turn and its picture can be looked at.
"""

from __future__ import annotations

import asyncio
import threading
import time
from pathlib import Path

import pytest
from app_support import browser_camera

from phonglab.app import pixel_picture

LESSONS = Path(__file__).resolve().parents[1] / "lessons"


@pytest.fixture
def app(tmp_path):
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    folder = tmp_path / "lessons"
    folder.mkdir()
    (folder / "07-light-sources.md").write_text((LESSONS / "07-light-sources.md").read_text(encoding="utf-8"),
                                                encoding="utf-8")
    application = LessonApp(get_server(f"picture-sync-{tmp_path.name}", client_type="vue3"), target=folder)
    application.view.set_size((200, 150))
    yield application
    application.close()


async def _until(condition, what, seconds=60.0):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        await asyncio.sleep(0.01)


@pytest.mark.parametrize("change", ["turn", "slider"])
def test_the_readout_waits_for_the_picture_of_its_eye(app, monkeypatch, change):
    gate = threading.Event()
    made = pixel_picture.picture_url

    def held(job):
        assert gate.wait(60), "the picture was never let go"
        return made(job)

    async def scenario():
        app._refresh_pixels()  # a picture with a loop running, as the server makes it
        gate.set()
        await _until(lambda: not app.pictures.busy, "the first picture")
        gate.clear()
        before = {"readout": app.state.readout, "picture": app.state.pixel_src, "tips": app.state.arrow_tips}
        if change == "turn":
            app.on_camera(browser_camera(app.scene, 25.0))  # the drag's end
        else:
            app._on_control("lights_1__azimuth", 40.0)
        await _until(lambda: app.pictures.busy, "the new eye's picture to be started")
        await asyncio.sleep(0.05)  # the turn's deferred refresh has run (PANEL_DELAY)
        # the picture is still the old eye's: so are the numbers and the letters, and the page says it is updating
        assert app.state.pixel_src == before["picture"]
        assert app.state.readout == before["readout"], (change, "the readout changed before its picture",
                                                        before["readout"]["dots"], app.state.readout["dots"])
        assert app.state.arrow_tips == before["tips"], (change, before["tips"], app.state.arrow_tips)
        assert app.state[pixel_picture.PENDING_KEY] is True, change
        gate.set()
        await _until(lambda: not app.pictures.busy and not app.state[pixel_picture.PENDING_KEY], "the new picture")
        # picture and numbers for the new eye, together
        assert app.state.pixel_src != before["picture"], change
        assert app.state.readout != before["readout"], change
        assert app.state.readout == app._probe_panels()["readout"], change

    monkeypatch.setattr(pixel_picture, "picture_url", held)
    asyncio.run(scenario())
