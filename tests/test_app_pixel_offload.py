"""The per-pixel picture is finished off the event loop, and the newest scene's picture comes last.

``phonglab.render.pixel_job`` splits a screenshot into its VTK part (in the
loop's thread) and its NumPy part (any thread); ``phonglab.app.pixel_picture``
runs the second in a worker thread, one job per tab, coalescing the
requests made meanwhile. Checked here:

1. the split gives the screenshot byte for byte, even when the view has
   changed before the NumPy part runs in another thread; the app's picture
   made in a running loop is the view's screenshot;
2. with ``phonglab serve`` in its own process, tab B's round trips stay near
   their idle value while tab A has 1600 × 1600 per-pixel pictures made
   (the measure and helpers of ``tests/test_app_offload.py``). Tab A's view
   is first resized to 1600 × 1600 and its first picture awaited: the new
   size's G-buffer is rendered by VTK, which stays in the loop's thread, and
   is not what is measured. Then each move of the specular slider re-shades
   every pixel. Made in the loop (before this split), each picture held it
   for seconds: tab B's median round trip grew 150-290 times on 2 loaded cores;
3. requests made while a job runs are coalesced into one, for the newest
   scene; each finished picture is shown in turn, the newest last, and none
   after the page left pixel mode; a failure in the thread is a one-line notice.
"""

from __future__ import annotations

import asyncio
import base64
import io
import logging
import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from app_support import serving
from phonglab.app import pixel_picture
from phonglab.app.pixel_picture import PixelPicture
from phonglab.bench.scenes import lesson, red_sphere, red_sphere_tables
from phonglab.render import SceneView, pixel_job, pixels
from phonglab.render._vtk import hidden, read_depth, read_rgb
from phonglab.scene import Camera

SIZE = (220, 170)


def pixel_sphere(**changes):
    scene = red_sphere(24, camera=Camera(), probe=(0.35, 0.45, 0.82), interpolation="pixel")
    for path, value in changes.items():
        scene = scene.replace(path.replace("__", "."), value)
    return scene


def composed_the_old_way(view) -> np.ndarray:
    """The pixel-mode screenshot as it was made in one piece: render, G-buffer, shade, composite, letters."""
    with hidden(view.glyph_actors.text_actors() + [view.mesh_actor]):
        view.render()
        image = read_rgb(view.render_window)
        image = pixels.composite(image, read_depth(view.render_window), view.gbuffer(), view.pixel_image(),
                                 view.renderer.GetActiveCamera())
    return view.annotate(image)


def in_other_thread(function):
    out = {}
    thread = threading.Thread(target=lambda: out.update(value=function()))
    thread.start()
    thread.join(120)
    return out["value"]


def decoded(url: str) -> np.ndarray:
    from PIL import Image

    assert url.startswith("data:image/png;base64,"), url[:40]
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB"))


@pytest.mark.parametrize("mistake", [None, "unnormalised-normals"])
def test_the_split_is_the_screenshot_byte_for_byte_even_after_the_view_moved_on(mistake):
    view = SceneView(pixel_sphere(), size=SIZE, mistake=mistake)
    try:
        expected = composed_the_old_way(view)
        assert np.array_equal(view.screenshot(), expected), mistake
        job = pixel_job.prepare(view, annotate=True)
        # the view changes before the NumPy part runs, in another thread: the job keeps its moment
        view.update(pixel_sphere(material__ks=0.0, camera__eye=[1.0, 0.5, 4.0]))
        view.set_mistake(None)
        view.screenshot()
        finished = in_other_thread(job.finish)
        changed = np.count_nonzero((finished != expected).any(axis=2))
        assert changed == 0, f"mistake {mistake!r}: {changed} pixels differ from the screenshot of its moment"
        assert not np.array_equal(view.screenshot(), expected), "the changed view should look different"
    finally:
        view.close()


def half_opaque(scene):
    return scene.replace("material.opacity", 0.5)


@pytest.mark.parametrize("interpolation", ["pixel", "gouraud"])
def test_a_translucent_meshs_job_keeps_its_moment_in_another_thread(interpolation):
    view = SceneView(half_opaque(pixel_sphere(interpolation=interpolation)), size=SIZE)
    try:
        expected = view.screenshot()
        job = pixel_job.prepare(view, annotate=True)
        view.update(half_opaque(pixel_sphere(interpolation=interpolation, material__ks=0.0,
                                             camera__eye=[1.0, 0.5, 4.0])))
        view.screenshot()
        finished = in_other_thread(job.finish)
        changed = np.count_nonzero((finished != expected).any(axis=2))
        assert changed == 0, f"{interpolation}: {changed} pixels differ from the screenshot of its moment"
    finally:
        view.close()


GLOSSY = lesson('number = 1\ntitle = "Glossy"\ninterpolation = "pixel"\ncontrols = ["material.ks"]\n',
                red_sphere_tables(24), "# Glossy\n")


@pytest.fixture
def app(tmp_path):
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    (tmp_path / "01-glossy.md").write_text(GLOSSY, encoding="utf-8")
    application = LessonApp(get_server(f"test-pixel-offload-{tmp_path.name}", client_type="vue3"), target=tmp_path)
    yield application
    application.close()


class Recorder:
    """A state that records every value written to it, then passes it on."""

    def __init__(self, state):
        self.state, self.written = state, []

    def __setitem__(self, key, value):
        self.written.append((key, value))
        self.state[key] = value

    def flush(self):
        self.state.flush()


async def settled(pictures: PixelPicture, seconds: float = 120.0) -> None:
    deadline = time.monotonic() + seconds
    while pictures.busy and time.monotonic() < deadline:
        await asyncio.sleep(0.01)
    assert not pictures.busy, "the picture's job did not end"


def test_without_a_loop_the_picture_comes_at_once(app):
    # scripts and tests: the picture is there when the call returns
    assert app.state.pixel_mode is True
    assert np.array_equal(decoded(app.state.pixel_src), app.view.screenshot(annotate=True))


def test_in_a_running_loop_the_last_picture_is_the_newest_scenes(app):
    scenes = [app.scene.replace("material.ks", ks) for ks in (0.0, 0.3, 0.9)]
    recorder = Recorder(app.state)
    app.pictures.state = recorder

    async def slide():
        for scene in scenes:  # one after the other, faster than a picture is made
            app._show_scene(scene)
        assert app.pictures.busy, "the first picture should still be in its thread"
        await settled(app.pictures)

    asyncio.run(slide())
    written = [url for key, url in recorder.written if key == pixel_picture.STATE_KEY]
    # the first scene's picture (started at once), then one for the newest: ks 0.3 was coalesced away
    assert len(written) == 2, f"expected 2 pictures for ks 0.0, 0.3, 0.9 set at once, got {len(written)}"
    assert np.array_equal(decoded(written[-1]), app.view.screenshot(annotate=True)), "not the newest scene's picture"


class Gate:
    """A job whose NumPy part waits for the test to let it finish."""

    def __init__(self, name, prepared):
        self.name, self.release = name, threading.Event()
        prepared.append(name)

    def finish(self):
        assert self.release.wait(60), f"job {self.name} was never released"
        if self.name == "broken":
            raise ValueError("the G-buffer is empty\nsecond line")
        return np.full((2, 2, 3), ord(self.name[0]), np.uint8)


class FakeState:
    def __init__(self):
        self.values = []

    def __setitem__(self, key, value):
        if key == pixel_picture.STATE_KEY:
            self.values.append(value)

    def flush(self):
        pass


def fake_tab():
    notices, state = [], FakeState()
    return PixelPicture(state, lambda kind, text: notices.append((kind, text))), state.values, notices


def test_requests_during_a_job_are_coalesced_and_each_finished_picture_follows():
    pictures, values, notices = fake_tab()
    prepared, gates = [], {}

    def request(name):
        pictures.request(lambda: gates.setdefault(name, Gate(name, prepared)))

    async def scenario():
        request("a")
        request("b")  # while "a" runs: remembered
        request("c")  # overtakes "b", which is never prepared
        assert prepared == ["a"], prepared
        gates["a"].release.set()
        for _ in range(2000):
            if "c" in gates:
                break
            await asyncio.sleep(0.005)
        assert prepared == ["a", "c"], f"after a, only the newest request should be prepared: {prepared}"
        gates["c"].release.set()
        await settled(pictures)

    asyncio.run(scenario())
    # "a" is shown when it is made (the picture keeps up during a drag), then "c", the newest; never "b"
    shown = [chr(decoded(v)[0, 0, 0]) for v in values]
    assert shown == ["a", "c"], f"shown: {shown}"
    assert notices == []


def test_a_picture_still_being_made_when_the_page_leaves_pixel_mode_is_not_shown():
    pictures, values, _ = fake_tab()
    gate = {}

    async def scenario():
        pictures.request(lambda: gate.setdefault("x", Gate("x", [])))
        pictures.drop()
        gate["x"].release.set()
        await settled(pictures)

    asyncio.run(scenario())
    assert values == [], "a picture arrived after the page left pixel mode"


def test_a_failure_in_the_thread_is_logged_and_the_tab_gets_one_line(caplog):
    pictures, values, notices = fake_tab()
    gate = {}

    async def scenario():
        pictures.request(lambda: gate.setdefault("broken", Gate("broken", [])))
        gate["broken"].release.set()
        await settled(pictures)

    with caplog.at_level(logging.ERROR, logger="phonglab.app.pixel_picture"):
        asyncio.run(scenario())
    assert values == []
    assert len(notices) == 1 and notices[0][0] == "error", notices
    text = notices[0][1]
    assert "the G-buffer is empty" in text and "\n" not in text and "Traceback" not in text, text
    assert any(record.exc_info for record in caplog.records), "the traceback should be in the server's log"


# ---------------------------------------------------------------------------
# 2. a real server: tab A's large per-pixel pictures, tab B's round trips

#: per-pixel pictures tab A must receive in its busy phase
PICTURES = 3


@pytest.fixture(scope="module")
def glossy_server(tmp_path_factory):
    lessons = tmp_path_factory.mktemp("lessons")
    (lessons / "01-glossy.md").write_text(GLOSSY, encoding="utf-8")
    with serving(lessons, log_path=tmp_path_factory.mktemp("serve") / "serve.log") as server:
        yield SimpleNamespace(port=server["port"], process=server["process"], log=server["log"])


def test_large_per_pixel_pictures_for_one_tab_leave_another_tab_responsive(glossy_server):
    from test_app_offload import BUSY_SECONDS, Messages, measure_within_bound, published

    async def shading(client, tab):
        pictures, sent = [], 0

        def seen(message):
            for change in published(message, "pixel_src"):
                if change["pixel_src"]:
                    pictures.append(time.perf_counter())

        async def state(key, value):
            nonlocal sent
            sent += 1
            await client.send({"wslink": "1.0", "id": f"rpc:c1:set{sent}", "method": "trame.state.update",
                               "args": [[{"key": key, "value": value}]], "kwargs": {}})

        messages = Messages(client, seen)
        pump = asyncio.create_task(messages.pump(lambda: tab["stop"]))
        deadline = time.monotonic() + BUSY_SECONDS
        started = time.perf_counter()
        try:
            # the page's largest view: its G-buffer is rendered by VTK, in the loop, before the measure
            await state("view_size", {"size": {"width": 1600, "height": 1600}})
            while not pictures and time.monotonic() < deadline:
                await asyncio.sleep(0.05)
            tab["resized s"] = round(time.perf_counter() - started, 2)
            # then the specular slider, moved each time a picture arrives: only the shading is new
            pictures.clear()
            started = time.perf_counter()
            tab["started"] = True
            while len(pictures) < PICTURES and time.monotonic() < deadline:
                before = len(pictures)
                await state("material__ks", round(0.2 + 0.15 * len(pictures), 2))
                while len(pictures) == before and time.monotonic() < deadline:
                    await asyncio.sleep(0.05)
        finally:
            tab["done"] = True
            tab["stop"] = True
            await pump
        spent = (pictures[-1] - started) if pictures else None
        return {"pictures": len(pictures), "s per picture": round(spent / len(pictures), 2) if pictures else None,
                "first picture at 1600 x 1600 after (s)": tab.get("resized s")}

    measure_within_bound(glossy_server, "per-pixel pictures", shading,
                         lambda report: None if report.get("pictures", 0) >= PICTURES else "tab A got too few pictures")


def test_the_pictures_threads_are_all_there_from_the_first_picture_and_overlap_adds_none():
    """However many pictures overlap, the server's threads stay as the first picture left them.

    The event loop's default pool started a thread only when all it had were busy, so pictures that
    overlapped on a slow moment left the server more threads for good (the session-leak test: 23 -> 25).
    """
    pool = pixel_picture.picture_threads()
    before = threading.active_count()
    release = threading.Event()
    jobs = [pool.submit(release.wait, 30) for _ in range(pixel_picture.PICTURE_THREADS + 3)]
    during = threading.active_count()
    release.set()
    for job in jobs:
        job.result(timeout=30)
    assert pixel_picture.picture_threads() is pool, "one pool per process"
    assert len(pool._threads) == pixel_picture.PICTURE_THREADS, (len(pool._threads), pixel_picture.PICTURE_THREADS)
    assert during == before, (f"{len(jobs)} overlapping jobs on {pixel_picture.PICTURE_THREADS} threads: "
                              f"threads {before} -> {during}")
