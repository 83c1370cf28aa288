"""One simulated student for ``phonglab bench load``: the page's own calls over one WebSocket, no browser.

A student does what the page does (:mod:`phonglab.app.page`, the trame
client, ``www/phonglab.js``), with wslink's chunked msgpack messages
(:mod:`phonglab.app.protocol`):

1. ``POST /paraview/`` with the page's ``Origin``: the launcher answers the
   ``sessionURL`` (``ws://USE_HOST/...``; ``USE_HOST`` is the page's host) and
   the session secret;
2. open that WebSocket, send the hello with the secret, then the page's first
   calls: ``trame.state.get``, ``trame.lifecycle.update`` and the view's size;
3. act: move a slider (``trame.state.update`` of a slider's state key), click
   the view (the view's click trigger with a ray through the scene, which
   moves the probe), or turn the view (the drag's camera trigger, then the
   drag's end). The trigger names and the sliders with their ranges are read
   from the page's own template, as the browser reads them.

For every action it records the time from sending to the reply, and to the
first pushed picture (the mesh's colours, ``view_colors``, or the per-pixel
image, ``pixel_src``) that follows.
"""

from __future__ import annotations

import asyncio
import itertools
import math
import random
import re
import time
from dataclasses import dataclass, field
from urllib.parse import urlsplit

import aiohttp
import msgpack

from phonglab.app import protocol

#: the state keys that carry a new picture to the browser
PICTURE_KEYS = ("view_colors", "pixel_src")
#: the state key of a local view's whole scene starts with this (``scene_phonglab_view``)
SCENE_PREFIX = "scene_"
#: the view's size a student's browser reports (a laptop's half of the page)
VIEW_SIZE = {"width": 640, "height": 480}
#: seconds to wait for a reply before the action counts as lost
REPLY_TIMEOUT = 60.0
#: the share of actions that click the view, and that turn it (the rest move sliders)
CLICK_SHARE = 0.1
TURN_SHARE = 0.1


class StudentError(Exception):
    """A simulated student could not open its session (refused, full, no answer)."""


@dataclass
class Timing:
    """One action's times, in seconds from sending it (None: not seen)."""

    kind: str
    reply: float | None = None
    picture: float | None = None


@dataclass
class PageCalls:
    """What a student reads from the page's template: its sliders and the view's triggers."""

    sliders: list = field(default_factory=list)  #: ``(key, low, high, step)``
    click: str | None = None
    turn: str | None = None
    turn_end: str | None = None


_SLIDER = re.compile(r"<VSlider\b[^>]*>")
#: a control's box in the page's template, and the class of those in the "all controls" panel
_CONTROL_BLOCK = re.compile(r'<div class="(phonglab-control(?: [^"]*)?)"')
ALL_CONTROLS_CLASS = "phonglab-control-all"  # page._widget(control, suffix="all")
_ATTRIBUTE = re.compile(r'(:?[\w-]+)="([^"]*)"')


def page_calls(state: dict) -> PageCalls:
    """The sliders and view triggers of the page whose state is ``state`` (from ``trame.state.get``)."""
    calls = PageCalls()
    templates = [value for key, value in state.items() if key.startswith("trame__template_") and isinstance(value, str)]
    every = []  # the "all controls" panel's sliders: moved only when the lesson shows none of its own
    for template in templates:
        blocks = [(m.start(), m.group(1).split()) for m in _CONTROL_BLOCK.finditer(template)]
        for match in _SLIDER.finditer(template):
            block = next((classes for start, classes in reversed(blocks) if start < match.start()), [])
            attributes = dict(_ATTRIBUTE.findall(match.group(0)))
            try:  # a bound (":min") or a plain ("min") attribute: the page writes a number either way
                key = attributes["v-model"]
                low, high = float(_attribute(attributes, "min")), float(_attribute(attributes, "max"))
                step = float(_attribute(attributes, "step", "0") or 0)
            except (KeyError, ValueError):
                continue
            chosen = every if ALL_CONTROLS_CLASS in block else calls.sliders
            if high > low and all(key != seen[0] for seen in chosen):
                chosen.append((key, low, high, step))
        for name, attribute in (("click", "@click"), ("turn", "@Animation"), ("turn_end", "@EndAnimation")):
            match = re.search(attribute + r"=\"trigger\('([\w]+)', \[(?:\$event|trame\.refs\.phonglab_view)", template)
            if match and getattr(calls, name) is None:
                setattr(calls, name, match.group(1))
    calls.sliders = calls.sliders or every
    return calls


def _attribute(attributes: dict, name: str, default=None):
    """A tag's attribute ``name``, bound (``:name``) or plain; KeyError when it has neither and no default."""
    for spelled in (f":{name}", name):
        if spelled in attributes:
            return attributes[spelled]
    if default is None:
        raise KeyError(name)
    return default


def _camera_of(state: dict) -> tuple[list, list, list, float]:
    """The view's camera (position, focal point, up, view angle) in the scene state trame-vtk sent."""
    found = {}

    def visit(node, depth=0):
        if depth > 12 or found:
            return
        if isinstance(node, dict):
            props = node.get("properties") if isinstance(node.get("properties"), dict) else node
            if all(k in props for k in ("position", "focalPoint", "viewUp")):
                found.update(props)
                return
            for value in node.values():
                visit(value, depth + 1)
        elif isinstance(node, list):
            for value in node:
                visit(value, depth + 1)

    visit(state.get("scene_phonglab_view"))
    if found:
        try:
            return ([float(c) for c in found["position"]], [float(c) for c in found["focalPoint"]],
                    [float(c) for c in found["viewUp"]], float(found.get("viewAngle", 30.0)))
        except (TypeError, ValueError):
            pass
    return [0.0, 0.0, 5.5], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 30.0


class Student:
    """One simulated student on ``url`` (the page's address, e.g. ``http://127.0.0.1:8080/``).

    Parameters
    ----------
    url : str
        The page's address; the launcher is ``POST url + "paraview/"``.
    seed : int
        Seeds the student's choice of actions and values.
    query : str
        The page's address query sent at opening (``lesson=04-specular``), as a browser opening a link.
    """

    def __init__(self, url: str, *, seed: int = 0, query: str = ""):
        self.url = url if url.endswith("/") else url + "/"
        parts = urlsplit(self.url)
        self.origin = f"{parts.scheme}://{parts.netloc}"
        self.query = query
        self.random = random.Random(seed)
        self.ids = itertools.count(1)
        self.calls = PageCalls()
        self.timings: list[Timing] = []
        self.lost = 0
        self._http = self._ws = self._reader = None
        self._replies: dict[str, asyncio.Future] = {}
        self._picture_waiters: list[tuple[asyncio.Future, float]] = []
        self._camera = ([0.0, 0.0, 5.5], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 30.0)
        self._turn = 0.0
        self.closed = asyncio.Event()

    # ------------------------------------------------------------------
    # opening and closing

    async def open(self, timeout: float = 120.0) -> float:
        """Open the session as the page does; the seconds it took (launcher to the page's state).

        Raises
        ------
        StudentError
            When the launcher or the WebSocket refuses, or the hello is not answered.
        """
        started = time.perf_counter()
        self._http = aiohttp.ClientSession(timeout=aiohttp.ClientTimeout(total=timeout))
        try:
            async with self._http.post(self.url + "paraview/", json={"application": "phonglab"},
                                       headers={"Origin": self.origin}) as answer:
                if answer.status != 200:
                    raise StudentError(f"launcher answered HTTP {answer.status}: {(await answer.text())[:200]}")
                launch = await answer.json()
            where = urlsplit(launch["sessionURL"].replace("USE_HOST", urlsplit(self.url).netloc))
            ws_url = f"{'https' if where.scheme == 'wss' else 'http'}://{where.netloc}{where.path}"
            ws_url += f"?{where.query}" if where.query else ""
            self._ws = await self._http.ws_connect(ws_url, headers={"Origin": self.origin}, max_msg_size=0,
                                                   autoping=True)
            self._reader = asyncio.create_task(self._read())
            hello = await self._rpc(protocol.HELLO_ID, "wslink.hello", [{"secret": launch["secret"]}], timeout)
            if hello is None or "error" in hello:
                raise StudentError(f"hello refused: {self._why(hello)}")
            state = await self.call("trame.state.get", timeout=timeout)
            if state is None or "result" not in state:
                raise StudentError(f"no page state: {self._why(state)}")
            values = state["result"].get("state", {})
            self.calls = page_calls(values)
            self._camera = _camera_of(values)
            await self.call("trame.lifecycle.update", ["client_connected"], timeout=timeout)
            changes = [{"key": "view_size", "value": {"size": VIEW_SIZE, "pixelRatio": 1}}]
            if self.query:
                changes.append({"key": "url_request", "value": self.query})
            await self.call("trame.state.update", [changes], timeout=timeout)
        except (aiohttp.ClientError, asyncio.TimeoutError, KeyError, TypeError, ValueError) as exc:
            await self.close()
            raise StudentError(f"{type(exc).__name__}: {exc}"[:300]) from None
        except BaseException:
            await self.close()
            raise
        return time.perf_counter() - started

    def _why(self, answer) -> str:
        if answer is None:
            code = self._ws.close_code if self._ws is not None else None
            return f"socket closed (code {code})"
        return str(answer.get("error", answer))[:200]

    async def close(self) -> None:
        """Close the socket (the tab closes)."""
        if self._ws is not None and not self._ws.closed:
            await self._ws.close()
        if self._reader is not None:
            self._reader.cancel()
            await asyncio.gather(self._reader, return_exceptions=True)
        if self._http is not None:
            await self._http.close()
        self.closed.set()

    # ------------------------------------------------------------------
    # messages

    async def _read(self) -> None:
        pending: dict[int, bytearray] = {}
        try:
            async for message in self._ws:
                if message.type != aiohttp.WSMsgType.BINARY or len(message.data) < protocol.HEADER.size:
                    continue
                key, offset, size = protocol.HEADER.unpack_from(message.data)
                body = pending.setdefault(key, bytearray())
                body += message.data[protocol.HEADER.size:]
                if len(body) < size:
                    continue
                del pending[key]
                self._dispatch(bytes(body))
        finally:
            for future in self._replies.values():
                if not future.done():
                    future.set_result(None)
            self.closed.set()

    def _dispatch(self, body: bytes) -> None:
        try:
            answer = msgpack.unpackb(body, strict_map_key=False)
        except Exception:
            return
        if not isinstance(answer, dict):
            return
        rpc_id = answer.get("id")
        if isinstance(rpc_id, str) and rpc_id.startswith("publish:"):
            if self._picture_waiters and _carries_picture(answer.get("result")):
                now = time.perf_counter()
                for future, sent in self._picture_waiters:
                    if not future.done():
                        future.set_result(now - sent)
                self._picture_waiters.clear()
            return
        future = self._replies.pop(rpc_id, None)
        if future is not None and not future.done():
            future.set_result(answer)

    async def _rpc(self, rpc_id: str, method: str, args, timeout: float):
        future = asyncio.get_running_loop().create_future()
        self._replies[rpc_id] = future
        message = {"wslink": "1.0", "id": rpc_id, "method": method, "args": list(args), "kwargs": {}}
        await self._ws.send_bytes(protocol.chunk(msgpack.packb(message)))
        try:
            return await asyncio.wait_for(future, timeout)
        except asyncio.TimeoutError:
            self._replies.pop(rpc_id, None)
            return None

    async def call(self, method: str, args=(), *, timeout: float = REPLY_TIMEOUT):
        """Call ``method``; its reply (None when the socket closed or the time ran out)."""
        return await self._rpc(f"rpc:c1:{next(self.ids)}", method, args, timeout)

    # ------------------------------------------------------------------
    # actions

    async def act(self) -> Timing:
        """One action: mostly a slider move, sometimes a click on the view or a turn of it."""
        draw = self.random.random()
        if draw < CLICK_SHARE and self.calls.click:
            kind, method, args = "click", "trame.trigger", [self.calls.click, [{"ray": self._ray()}], {}]
        elif draw < CLICK_SHARE + TURN_SHARE and self.calls.turn and self.calls.turn_end:
            return await self._turn_view()
        elif self.calls.sliders:
            key, low, high, step = self.random.choice(self.calls.sliders)
            value = low + (high - low) * self.random.random()
            value = round(round(value / step) * step, 6) if step > 0 else value
            kind, method, args = "slider", "trame.state.update", [[{"key": key, "value": value}]]
        else:
            kind, method, args = "state", "trame.lifecycle.update", ["client_unmounted"]
        return await self._timed(kind, method, args, picture=kind == "slider")

    async def _timed(self, kind, method, args, *, picture: bool) -> Timing:
        sent = time.perf_counter()
        waiter = None
        if picture:
            waiter = asyncio.get_running_loop().create_future()
            self._picture_waiters.append((waiter, sent))
        answer = await self.call(method, args)
        timing = Timing(kind)
        if answer is None:
            self.lost += 1
        else:
            timing.reply = time.perf_counter() - sent
            if waiter is not None:
                try:  # the picture usually left before the reply; else it follows soon after
                    timing.picture = await asyncio.wait_for(asyncio.shield(waiter), 2.0 + 2 * timing.reply)
                except asyncio.TimeoutError:
                    pass
        if waiter is not None:
            self._picture_waiters = [(f, s) for f, s in self._picture_waiters if f is not waiter]
        self.timings.append(timing)
        return timing

    async def _turn_view(self) -> Timing:
        """A short drag: one camera during it, then the drag's end (timed: what the student waits for)."""
        self._turn += self.random.uniform(5.0, 20.0) * self.random.choice((-1, 1))
        camera = self._turned(self._turn)
        await self.call("trame.trigger", [self.calls.turn, [self._turned(self._turn / 2)], {}])
        return await self._timed("turn", "trame.trigger", [self.calls.turn_end, [camera], {}], picture=True)

    def _turned(self, degrees: float) -> dict:
        position, focal, up, angle = self._camera
        a = math.radians(degrees)
        x, y, z = (p - f for p, f in zip(position, focal))
        turned = [x * math.cos(a) + z * math.sin(a), y, -x * math.sin(a) + z * math.cos(a)]
        return {"position": [f + t for f, t in zip(focal, turned)], "focalPoint": focal, "viewUp": up, "viewAngle": angle}

    def _ray(self) -> list:
        """A ray from the eye through a point near the focal point (the page sends the click's ray)."""
        position, focal, _, _ = self._camera
        target = [f + self.random.uniform(-0.4, 0.4) for f in focal]
        far = [p + 3.0 * (t - p) for p, t in zip(position, target)]
        return [list(position), far]


def _carries_picture(result) -> bool:
    """True when a published state change (a map of changed keys) carries a new picture.

    The picture is the mesh's colours, the per-pixel image, or the view's
    whole scene (``scene_<ref>``, trame-vtk's local view): a light or the
    camera moved by a slider moves the arrows too, and the scene is sent again.
    """
    changes = result[0] if isinstance(result, list) and result else result
    return isinstance(changes, dict) and any(key in PICTURE_KEYS or key.startswith(SCENE_PREFIX) for key in changes
                                             if isinstance(key, str))
