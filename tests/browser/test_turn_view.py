"""Lesson 4 in a real browser, in each interpolation mode (flat, Gouraud, per pixel).

Turning the view moves the eye: dragging the view makes the browser's camera
the model's eye, r·v at the probe changes to the core's value for that eye,
and the specular-only picture the student sees equals a server-side render
for that camera within the image tolerance of :mod:`phonglab.render.compare`
(mean |diff| <= 2/255 per channel, at most 0.5 % of pixels off by > 16/255).
In flat and Gouraud mode that picture is the browser's WebGL mesh; in per-pixel
mode it is the server's image over the view. The stale picture (flat and
Gouraud: colours baked for the old eye and turned with the mesh; per pixel:
the image for the old camera) must fail the same tolerance.

The arrows carry their letters N, L, R, V, H in every mode, before and after
the turn: each letter is inside the view, shown, next to its arrow's tip, and
on top (not covered by the per-pixel image); in per-pixel mode the tips the
letters follow are where the server's image draws them (within 2 px), also in
a view taller than wide.
"""

from __future__ import annotations

import base64
import io
from pathlib import Path

import msgpack
import numpy as np
import pytest

import phonglab as pl
from phonglab.app import client, protocol
from phonglab.app.eye import scene_camera
from phonglab.render import SceneView
from phonglab.render.compare import image_difference
from phonglab.scene import load_lesson

from conftest import Page
from waiting import wait_for

LESSON = Path(__file__).resolve().parents[2] / "lessons" / "04-specular.md"

# the view's WebGL pixels with only the mesh shown (glyphs hidden for the read), its camera and size
READ_MESH_JS = r"""
() => {
  const view = window.phonglabView;
  const renderer = view.renderer;
  const actors = renderer.getActors();
  const points = (a) => { const d = a.getMapper() && a.getMapper().getInputData(); return d && d.getNumberOfPoints ? d.getNumberOfPoints() : 0; };
  const mesh = actors.reduce((best, a) => (points(a) > points(best) ? a : best), actors[0]);
  const shown = actors.map((a) => a.getVisibility());
  actors.forEach((a) => a.setVisibility(a === mesh));
  view.renderWindow.render();
  const canvas = document.querySelector(".phonglab-view canvas");
  const gl = canvas.getContext("webgl2") || canvas.getContext("webgl");
  const w = canvas.width, h = canvas.height;
  const rgba = new Uint8Array(w * h * 4);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
  actors.forEach((a, i) => a.setVisibility(shown[i]));
  view.renderWindow.render();
  let text = "";
  for (let i = 0; i < rgba.length; i += 0x8000) text += String.fromCharCode.apply(null, rgba.subarray(i, i + 0x8000));
  const c = renderer.getActiveCamera();
  return { size: [w, h], rgba: btoa(text),
           camera: { position: c.getPosition(), focalPoint: c.getFocalPoint(), viewUp: c.getViewUp(),
                     viewAngle: c.getViewAngle() } };
}
"""


@pytest.fixture(scope="module")
def lesson4_server(serve_app):
    return serve_app(LESSON, timeout=120)


MODES = ("flat", "gouraud", "pixel")

# every letter at the arrow tips: its box, whether it is shown and on top, and its arrow's tip on screen
LETTERS_JS = r"""
() => {
  const view = window.phonglabView;
  const renderer = view && view.renderer;
  const canvas = document.querySelector(".phonglab-view canvas");
  if (!renderer || !canvas) return null;
  const box = canvas.getBoundingClientRect();
  const tips = {};
  for (const t of window.trame.state.get("arrow_tips") || []) {
    const d = renderer.worldToNormalizedDisplay(t.tip[0], t.tip[1], t.tip[2], box.width / box.height);
    tips[t.letter] = [box.left + d[0] * box.width, box.top + (1 - d[1]) * box.height];
  }
  // hit-test as if everything in the view took the pointer: the topmost element at a point
  const probe = document.createElement("style");
  probe.textContent = ".phonglab-view, .phonglab-view * { pointer-events: auto !important; }";
  document.head.appendChild(probe);
  const letters = [...document.querySelectorAll(".phonglab-letter")].map((e) => {
    const r = e.getBoundingClientRect();
    const x = r.left + r.width / 2, y = r.top + r.height / 2;
    const top = document.elementFromPoint(x, y);
    let shown = true;
    for (let n = e; n && n !== document.body; n = n.parentElement) {
      const c = getComputedStyle(n);
      if (c.display === "none" || c.visibility === "hidden" || Number(c.opacity) === 0) shown = false;
    }
    return { letter: e.dataset.letter, text: e.textContent, box: [r.left, r.top, r.right, r.bottom], centre: [x, y],
             shown, onTop: !!top && (top === e || e.contains(top)),
             topIs: top ? `${top.tagName}.${top.className}` : null };
  });
  probe.remove();
  const img = document.querySelector(".phonglab-pixel img");
  return { view: [box.left, box.top, box.right, box.bottom], tips, letters,
           pixelMode: window.trame.state.get("pixel_mode"),
           image: img && img.complete ? [img.naturalWidth, img.naturalHeight] : null };
}
"""

#: how far a letter's centre may be from its arrow's tip on screen, in CSS pixels: the letter sits
#: 11 px past the tip and steps aside by 17 px from a letter it would cover (www/phonglab.js)
LETTER_REACH = 11 + 2 * 17


def _read(page):
    raw = page.page.evaluate(READ_MESH_JS)
    w, h = raw["size"]
    rgba = np.frombuffer(base64.b64decode(raw["rgba"]), np.uint8).reshape(h, w, 4)
    return rgba[::-1, :, :3].copy(), raw["camera"], (w, h)  # WebGL rows start at the bottom


def _read_pixels(page):
    """Per-pixel mode: the server's image over the view (what the student sees), and the browser's camera."""
    from PIL import Image

    source = page.state("pixel_src")
    assert source.startswith("data:image/png;base64,"), f"no per-pixel image on the page: {source[:40]!r}"
    image = np.asarray(Image.open(io.BytesIO(base64.b64decode(source.split(",", 1)[1]))).convert("RGB"))
    raw = page.page.evaluate(READ_MESH_JS)
    return image, raw["camera"], (image.shape[1], image.shape[0])


def _server_render(scene, size, *, lit_by=None):
    """The mesh alone, specular term, as the render layer draws it for the scene's camera.

    ``lit_by``: shade for this scene's eye instead (today's baked colours).
    In per-pixel mode the picture is the page's: the core's image with the
    arrows and markers, without letters (the browser draws those).
    """
    first = lit_by or scene
    glyphs = {} if scene.interpolation == "pixel" else {"vectors": "", "markers": False}
    view = SceneView(first, size=size, labels=False, vtk_text=False, term="specular", **glyphs)
    try:
        if lit_by is not None:
            c = scene.camera
            view.set_camera(c.eye, c.focal_point, c.up, c.view_angle)  # the picture turns, the eye stays
        else:
            view.update(scene, keep_view_angle=True)
        return view.screenshot(annotate=False)
    finally:
        view.close()


def _lesson4_page(browser, server, mode, init_script=None, listen=None):
    """A fresh tab on lesson 4 in interpolation ``mode``, settled (``init_script`` runs before the page's;
    ``listen`` is given the Playwright page before it opens)."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    if init_script:
        context.add_init_script(init_script)
    tab = context.new_page()
    if listen:
        listen(tab)
    page = Page(tab, server)
    page.open()
    if page.state("interpolation") != mode:
        page.set_state("interpolation", repr(mode))
    page.page.wait_for_function("(pixel) => window.trame.state.get('pixel_mode') === pixel",
                                arg=mode == "pixel", timeout=60_000)
    page.wait_settled()
    return context, page


CAMERA_JS = "() => window.phonglabView.renderer.getActiveCamera().getPosition()"
# the view 380 x 560 pixels, as on a narrow screen (the view angle then spans its width)
TALL_VIEW_JS = """() => { const v = document.querySelector('.phonglab-view');
  v.style.flex = '0 0 auto'; v.style.width = '380px'; v.style.height = '560px'; }"""
CAMERA_STATE_JS = """() => { const c = window.phonglabView.renderer.getActiveCamera();
  return { position: c.getPosition(), focalPoint: c.getFocalPoint(), viewUp: c.getViewUp(), viewAngle: c.getViewAngle() }; }"""


def _drag(page, tries: int = 3):
    """Drag the view 90 px left and 15 px down; again if the browser's camera did not turn.

    A drag that lands while the view is being synchronised (just after the
    page opened or the mode changed) can be lost; the test waits for the
    turn, not for a time.
    """
    start = page.page.evaluate(CAMERA_JS)
    for _ in range(tries):
        box = page.page.locator(".phonglab-view canvas").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.page.mouse.move(x, y)
        page.page.mouse.down()
        page.page.mouse.move(x - 90, y + 15, steps=6)
        page.page.mouse.up()
        try:
            page.page.wait_for_function(f"(p) => {{ const q = ({CAMERA_JS})(); "
                                        "return Math.hypot(q[0] - p[0], q[1] - p[1], q[2] - p[2]) > 0.05; }",
                                        arg=start, timeout=10_000)
            return
        except Exception:  # playwright's TimeoutError: drag again
            page.wait_settled()
    pytest.fail(f"{tries} drags did not turn the browser's camera from {start}")


@pytest.mark.parametrize("mode", MODES)
def test_dragging_the_view_moves_the_eye_in_picture_and_numbers(browser, lesson4_server, mode, tmp_path):
    context, page = _lesson4_page(browser, lesson4_server, mode)
    try:
        scene = load_lesson(LESSON).scene.replace("interpolation", mode)
        _check_letters(page, mode, tmp_path / f"letters-{mode}.png", scene)
        before = page.readout()
        page.set_state("view__term", "'specular'")
        page.wait_settled()
        _drag(page)
        after = wait_for(lambda: (lambda r: r if r["dots"]["r·v"] != before["dots"]["r·v"] else None)(page.readout()),
                         f"r·v at the probe to change after the drag ({mode})", timeout=60)
        assert after["point"] == before["point"], "the drag moved the probe"

        # the picture the student sees settles on the server's render for the browser's camera
        read = _read_pixels if mode == "pixel" else _read
        last = {}

        def close_enough():
            page.wait_settled()
            image, camera, size = read(page)
            turned = scene_camera(scene, camera)
            expected = _server_render(turned, size)
            difference = image_difference(image, expected)
            last["difference"] = str(difference)
            return (difference, image, turned, size) if difference.within() else None

        found = wait_for(close_enough, f"the view's specular picture ({mode}) to match the server's render "
                         f"(last: {last})", timeout=60)
        difference, image, turned, size = found
        print(f"{mode}: browser picture against the server's render: {difference}")  # shown with pytest -s
        assert turned.camera.eye != pytest.approx(scene.camera.eye, abs=0.05), f"the drag did not turn: {turned.camera}"
        # r·v on the page is the core's, for the browser's camera as the eye
        readout = page.readout()
        point = np.array(readout["point"])
        normal = point / np.linalg.norm(point)  # lesson 4's unit sphere
        v = pl.vectors(point, normal, eye=turned.camera.eye, light=turned.lights[1])
        assert readout["dots"]["r·v"] == pytest.approx(v.rv, abs=0.01), (mode, readout, turned.camera.eye)
        # the stale picture is told apart by the same tolerance: colours baked for the old eye and turned
        # with the mesh (flat, Gouraud), or the image for the old camera (per pixel)
        stale = _server_render(scene, size) if mode == "pixel" else _server_render(turned, size, lit_by=scene)
        assert not image_difference(image, stale).within(), \
            f"{mode}: the stale picture passes too: {image_difference(image, stale)}"
        _check_letters(page, mode, tmp_path / f"letters-{mode}-turned.png", scene)  # they follow the camera
        if mode == "pixel":  # a view taller than wide: the browser frames it as the server's image does
            page.page.evaluate(TALL_VIEW_JS)
            _check_letters(page, mode, tmp_path / f"letters-{mode}-tall.png", scene)
        assert not page.errors, page.errors
    finally:
        context.close()


def _image_tips(scene, camera, size):
    """Where the server's image puts each arrow's tip (image pixels) for the browser's ``camera``."""
    turned = scene_camera(scene, camera)
    view = SceneView(turned, size=size, labels=False, vtk_text=False)
    try:
        view.update(turned, keep_view_angle=True)
        return {letter: tip for letter, (tip, _) in view.vector_marks().items()}
    finally:
        view.close()


def _check_letters(page, mode, shot, scene):
    """Every arrow of lesson 4 has its letter: shown, inside the view, on top and next to its tip.

    In per-pixel mode the server's image must be the view's size first (an
    image of another size is scaled, and its arrows leave the letters), and
    the tips the letters follow are where the image draws them.
    """
    expected = sorted(t["letter"] for t in page.state("arrow_tips"))
    assert expected == sorted("NLRVH"), f"lesson 4 shows the arrows {expected}"

    def letters():
        found = page.page.evaluate(LETTERS_JS)
        if not found or sorted(e["letter"] for e in found["letters"]) != expected:
            return None
        if mode == "pixel":
            width, height = found["view"][2] - found["view"][0], found["view"][3] - found["view"][1]
            if not found["image"] or abs(found["image"][0] - width) > 1 or abs(found["image"][1] - height) > 1:
                return None
        return found

    found = wait_for(letters, f"a letter for each arrow ({mode})", timeout=30)
    page.page.screenshot(path=str(shot))
    assert found["pixelMode"] == (mode == "pixel"), found
    left, top, right, bottom = found["view"]
    for e in found["letters"]:
        where = f"{mode}: letter {e} (view {found['view']}, screenshot {shot})"
        assert e["text"] == e["letter"] and e["shown"], where
        x0, y0, x1, y1 = e["box"]
        assert left <= x0 < x1 <= right and top <= y0 < y1 <= bottom, f"outside the view: {where}"
        assert e["onTop"], f"covered by {e['topIs']}: {where}"
        tip = found["tips"][e["letter"]]
        gap = float(np.hypot(e["centre"][0] - tip[0], e["centre"][1] - tip[1]))
        assert gap <= LETTER_REACH, f"{gap:.0f} px from its tip {tip}: {where}"
    if mode == "pixel":  # the letters label the arrows of the picture shown, the server's image
        camera = page.page.evaluate(CAMERA_STATE_JS)
        drawn = _image_tips(scene, camera, tuple(found["image"]))
        assert sorted(drawn) == sorted("NLRVH"), f"the server's image draws the arrows {sorted(drawn)}"
        for letter, (x, y) in drawn.items():
            tip = found["tips"][letter]
            assert np.hypot(left + x - tip[0], top + y - tip[1]) <= 2, \
                f"{letter}: the image draws its tip at {(left + x, top + y)}, the letter follows {tip} ({shot})"


# every frame vtk.js really draws from here on: the camera and the colours (how many pushes) it shows
DRAWS_JS = r"""
(slow) => {
  const view = window.phonglabView, d = view.phonglabDraw, camera = view.renderer.getActiveCamera();
  if (slow) { d.frameMs = 5000; d.roundTripMs = 1; }  // frames far slower than the colours' round trip
  const draws = (window.__draws = []);
  view.interactor.onRenderEvent(() => {
    if (view.interactor.getEnableRender()) {
      draws.push({ position: camera.getPosition(), colours: d.colours, at: performance.now() });
    }
  });
  return { position: camera.getPosition(), colours: d.colours };
}
"""


def _moved(a, b) -> bool:
    return float(np.linalg.norm(np.subtract(a, b))) > 1e-6


def test_where_frames_are_slow_a_turned_view_is_not_drawn_with_the_old_colours(browser, lesson4_server):
    # Chromium without a GPU draws a frame of a large mesh in ~0.5 s, ten times the colours' round trip:
    # the turned mesh is held until its re-shaded colours come, then drawn once with them
    context, page = _lesson4_page(browser, lesson4_server, "gouraud")
    try:
        before = page.page.evaluate(DRAWS_JS, True)
        _drag(page)
        wait_for(lambda: any(_moved(d["position"], before["position"]) and d["colours"] > before["colours"]
                             for d in page.page.evaluate("() => window.__draws")),
                 "a frame of the turned view with re-shaded colours", timeout=30)
        draws = page.page.evaluate("() => window.__draws")
        stale = [d for d in draws if _moved(d["position"], before["position"]) and d["colours"] == before["colours"]]
        assert not stale, f"turned frames drawn with the colours of the old eye: {stale} (before: {before}, all: {draws})"
        assert not page.errors, page.errors
    finally:
        context.close()


def test_holding_the_button_still_draws_no_frames(browser, lesson4_server):
    # vtk.js animates while a button is down; a frame in which nothing changed is not drawn again
    context, page = _lesson4_page(browser, lesson4_server, "gouraud")
    try:
        page.page.evaluate(DRAWS_JS, False)
        box = page.page.locator(".phonglab-view canvas").bounding_box()
        page.page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        page.page.mouse.down()
        animating = page.page.evaluate("() => new Promise((done) => setTimeout(() => "
                                       "done(window.phonglabView.interactor.isAnimating()), 1500))")
        draws = page.page.evaluate("() => window.__draws.length")
        page.page.mouse.up()
        assert animating, "vtk.js did not animate while the button was down: the test shows nothing"
        assert draws == 0, f"{draws} frames drawn in 1.5 s of a button held still"
        page.wait_settled()
        assert not page.errors, page.errors
    finally:
        context.close()


# the server's messages can be kept from the page (window.__dropMessages): a server that does not answer
DROP_MESSAGES_JS = r"""
(() => {
  const Socket = window.WebSocket;
  window.__dropMessages = false;
  const guard = (socket, handler) => (event) => { if (!window.__dropMessages) handler.call(socket, event); };
  window.WebSocket = class extends Socket {
    set onmessage(handler) { super.onmessage = handler && guard(this, handler); }
    get onmessage() { return super.onmessage; }
    addEventListener(type, handler, options) {
      return super.addEventListener(type, type === "message" ? guard(this, handler) : handler, options);
    }
  };
})();
"""


def test_a_turned_view_whose_colours_never_come_is_drawn_after_its_hold(browser, lesson4_server):
    # a held camera must not freeze the view: without colours it is drawn, with the old ones, after the hold
    context, page = _lesson4_page(browser, lesson4_server, "gouraud", init_script=DROP_MESSAGES_JS)
    try:
        before = page.page.evaluate(DRAWS_JS, True)  # frames of 5 s: a hold of the longest, 1 s
        page.page.evaluate("() => { window.__dropMessages = true; }")
        box = page.page.locator(".phonglab-view canvas").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.page.mouse.move(x, y)
        pressed_at = page.page.evaluate("() => performance.now()")
        page.page.mouse.down()
        page.page.mouse.move(x - 60, y, steps=3)
        page.page.mouse.up()
        turned = wait_for(lambda: [d for d in page.page.evaluate("() => window.__draws")
                                   if _moved(d["position"], before["position"])],
                          "the turned view drawn without its colours", timeout=30)
        colours = page.page.evaluate("() => window.phonglabView.phonglabDraw.colours")
        assert colours == before["colours"], f"colours came although the server's messages were dropped: {colours}"
        waited = turned[0]["at"] - pressed_at
        assert turned[0]["colours"] == before["colours"], turned
        assert waited >= 900, f"the turned view was drawn {waited:.0f} ms after the press, before its hold of 1 s ended"
    finally:
        context.close()


def test_over_the_per_pixel_picture_a_drag_draws_nothing_and_the_letters_wait_for_the_new_picture(
        browser, lesson4_server):
    # the core's picture covers vtk.js's canvas: its frames are never seen, and letters placed for the turning
    # camera would leave the picture's arrows; they come back with the picture for the new eye
    context, page = _lesson4_page(browser, lesson4_server, "pixel")
    try:
        page.page.evaluate(DRAWS_JS, False)
        picture = page.state("pixel_src")
        box = page.page.locator(".phonglab-view canvas").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.page.mouse.move(x, y)
        page.page.mouse.down()
        for step in range(1, 6):
            page.page.mouse.move(x - 15 * step, y)
            page.page.wait_for_timeout(60)
        during = page.page.evaluate("() => ({ draws: window.__draws.length, letters: getComputedStyle("
                                    "document.querySelector('.phonglab-letters')).display })")
        page.page.mouse.up()
        assert during["draws"] == 0, f"{during['draws']} frames drawn under the per-pixel picture during the drag"
        assert during["letters"] == "none", f"letters shown over the old picture during the drag: {during}"
        wait_for(lambda: page.state("pixel_src") != picture, "the per-pixel picture for the new eye", timeout=60)
        wait_for(lambda: page.page.evaluate("() => getComputedStyle(document.querySelector('.phonglab-letters'))"
                                            ".display") != "none", "the letters back on the new picture", timeout=30)
        assert not page.errors, page.errors
    finally:
        context.close()


def _messages(tab, sent: list, received: list) -> None:
    """Every whole wslink message of ``tab``'s sockets, decoded, into ``sent`` and ``received``."""
    def on_socket(socket):
        def keep(assembler, into):
            def on_frame(payload):
                whole = assembler.feed(payload) if isinstance(payload, bytes) else None
                if whole is not None:
                    into.append(msgpack.unpackb(whole, strict_map_key=False))
            return on_frame
        socket.on("framesent", keep(protocol.Assembler(), sent))
        socket.on("framereceived", keep(protocol.Assembler(), received))
    tab.on("websocket", on_socket)


def _told(sent: list) -> list:
    """The values of the colours-shown key the page sent."""
    return [change["value"] for m in sent if m.get("method") == "trame.state.update"
            for change in (m.get("args") or [[]])[0] if change.get("key") == client.SHOWN_KEY]


def _pushes(received: list, page=None) -> list:
    """The colour pushes the page received, oldest first (with ``page``, after letting Playwright, which
    delivers a socket's frames only during its own calls, hand over those that came)."""
    if page is not None:
        page.page.evaluate("() => 0")
    return [m["result"]["view_colors"] for m in received if str(m.get("id", "")).startswith("publish:")
            and isinstance(m.get("result"), dict) and isinstance(m["result"].get("view_colors"), dict)]


SHOWN_HASH_JS = "() => window.phonglabView.phonglabColours.shown"


def test_the_page_names_its_colours_to_the_server_for_a_turn_not_after_each_slider_step(browser, lesson4_server):
    # a slider's colours come whole, so the page's answer naming them was one more message per step for the
    # server; a turn's colours come as the rows that change, from the colours the page said it shows
    sent, received = [], []
    context, page = _lesson4_page(browser, lesson4_server, "gouraud", listen=lambda tab: _messages(tab, sent, received))
    try:
        slider = page.slider("material__shininess__log")
        told_before = len(_told(sent))
        for key in ("ArrowRight", "ArrowRight", "ArrowLeft"):
            pushed = len(_pushes(received))
            slider.focus()
            page.page.keyboard.press(key)
            wait_for(lambda: len(_pushes(received, page)) > pushed, f"the colours for the shininess after {key}",
                     timeout=30)
            last = _pushes(received)[-1]
            wait_for(lambda: page.page.evaluate(SHOWN_HASH_JS) == last.get("hash"),
                     f"the page showing the colours {last.get('hash')}", timeout=30)
        page.wait_settled()
        steps = _told(sent)[told_before:]
        assert not steps, f"the page named its colours after slider steps, one message each: {steps}"
        assert "rows" not in last, f"a slider's colours came as a change: {sorted(last)}"

        pushed = len(_pushes(received))
        _drag(page)
        wait_for(lambda: len(_pushes(received, page)) > pushed
                 and page.page.evaluate(SHOWN_HASH_JS) == _pushes(received)[-1].get("hash"),
                 "the turned view's colours shown", timeout=60)
        told = _told(sent)[told_before:]
        assert told and told[0] == last["hash"], (
            f"the drag did not start by naming the colours on screen {last['hash']}: told {told}")
        turn = _pushes(received)[pushed:]
        # the first of them too: named as the drag starts, the colours of the last key press are its base
        assert "rows" in turn[0] and turn[0].get("base") == last["hash"], (
            f"the drag's first colours came whole, not as a change from {last['hash']}: "
            f"{[(sorted(push), push.get('base')) for push in turn]}")
        assert not page.errors, page.errors
    finally:
        context.close()
