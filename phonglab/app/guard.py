"""Who may reach the session server, and how fast: origins, hosts, a per-tab call budget.

A web page on any site can open a WebSocket to ``ws://127.0.0.1:8080/ws``;
the browser then sends that site's origin in the ``Origin`` header. The
server answers its launcher (``POST /paraview/``, where the page learns the
session secret) and opens ``/ws`` only when :meth:`OriginPolicy.refusal`
finds nothing wrong:

- ``Origin`` is the page's own origin, ``scheme://Host`` of the request, or
  one of the origins given with ``serve --allow-origin`` (a deployment
  behind a proxy, whose public address differs);
- ``Host`` names this server: an IP address, ``localhost``, this machine's
  name, or the host of an allowed origin. A page on another site whose name
  was made to point at this machine (DNS rebinding) sends its own name as
  ``Host`` and is refused.

:class:`CallBudget` spaces one tab's calls (a count per second and a share
of the server's time, each a :class:`TokenBucket`) so that a flood from one
connection leaves the event loop to the other tabs.
"""

from __future__ import annotations

import asyncio
import ipaddress
import socket
import time
from urllib.parse import urlsplit

#: sessions (tabs) open at once, unless told otherwise
DEFAULT_MAX_SESSIONS = 60
#: calls one connection may make per second, sustained
CALLS_PER_SECOND = 100.0
#: calls one connection may make at once after a pause
CALL_BURST = 200.0
#: the share of the server's time one connection's calls may take, sustained
SERVER_SHARE = 0.15
#: seconds of server time one connection may take at once after a pause
SERVER_BURST_SECONDS = 2.0
#: the longest a connection waits for its share after one long call, in seconds
MAX_SHARE_WAIT = 1.0


class OriginPolicy:
    """The origins and host names the server answers to.

    Parameters
    ----------
    allow_origins : iterable of str
        Extra origins (``https://phong.school.org``), each ``scheme://host[:port]``.

    Raises
    ------
    ValueError
        For an allowed origin that is not ``http(s)://host[:port]``.
    """

    def __init__(self, allow_origins=()):
        self.origins = frozenset(normal_origin(origin) for origin in allow_origins)
        names = {"localhost", socket.gethostname().lower(), socket.getfqdn().lower()}
        names |= {f"{name}.local" for name in list(names) if "." not in name}
        names |= {urlsplit(origin).hostname for origin in self.origins}
        self.host_names = frozenset(names)

    def refusal(self, request) -> str | None:
        """Why ``request`` (an aiohttp request) is refused, or None when it may go on."""
        host = (request.host or "").lower()
        if not self._host_allowed(host):
            return f"Host {host[:100]!r} does not name this server"
        origin = request.headers.get("Origin")
        if origin is None:
            return "no Origin header"
        try:
            origin = normal_origin(origin)
        except ValueError:
            return f"Origin {origin[:100]!r} is not allowed"
        if origin == f"{request.scheme}://{host}" or origin in self.origins:
            return None
        return f"Origin {origin[:100]!r} is not allowed"

    def _host_allowed(self, host: str) -> bool:
        name = urlsplit(f"//{host}").hostname if host else None
        if not name:
            return False
        try:
            ipaddress.ip_address(name)
            return True
        except ValueError:
            return name in self.host_names


def normal_origin(origin: str) -> str:
    """``origin`` as browsers send it: lower case ``scheme://host[:port]``, default port left out.

    Raises
    ------
    ValueError
        When ``origin`` is not ``http(s)://host[:port]`` (``null`` included).
    """
    parts = urlsplit(origin.strip().rstrip("/"))
    if parts.scheme not in ("http", "https") or not parts.hostname or parts.path or parts.query or parts.username:
        raise ValueError(f"origin must be http(s)://host[:port], got {origin!r}")
    host = parts.hostname.lower()
    if ":" in host:
        host = f"[{host}]"
    try:
        port = parts.port
    except ValueError:
        raise ValueError(f"origin must be http(s)://host[:port] with a port up to 65535, got {origin!r}") from None
    default = {"http": 80, "https": 443}[parts.scheme]
    return f"{parts.scheme}://{host}" + (f":{port}" if port not in (None, default) else "")


class TokenBucket:
    """A budget refilled at ``rate`` per second, holding ``burst`` at most.

    :meth:`take` returns at once while the budget lasts, then sleeps until
    enough has come back: the connection's messages wait in the operating
    system's buffers, and the client is slowed down by TCP itself.
    :meth:`spend` may take the budget below zero (a call that took longer
    than its share), down to ``floor``; the next :meth:`take` then waits for
    the debt.
    """

    def __init__(self, rate: float = CALLS_PER_SECOND, burst: float = CALL_BURST, clock=time.monotonic,
                 *, floor: float = float("-inf")):
        self.rate = rate
        self.burst = burst
        self.floor = floor
        self._clock = clock
        self._tokens = burst
        self._last = clock()

    def _refill(self) -> None:
        now = self._clock()
        self._tokens = min(self.burst, self._tokens + (now - self._last) * self.rate)
        self._last = now

    def wait_time(self, need: float = 1.0) -> float:
        """Seconds until the budget holds ``need`` (0 when it does now)."""
        self._refill()
        return max(0.0, (need - self._tokens) / self.rate)

    def spend(self, amount: float) -> None:
        """Take ``amount`` from the budget, below zero if need be (not below ``floor``)."""
        self._refill()
        self._tokens = max(self.floor, self._tokens - amount)

    async def take(self, need: float = 1.0) -> None:
        """Wait until the budget holds ``need``, then spend it."""
        delay = self.wait_time(need)
        if delay > 0:
            await asyncio.sleep(delay)
        self.spend(need)


class CallBudget:
    """One connection's pace: :data:`CALLS_PER_SECOND` calls, and :data:`SERVER_SHARE` of the server's time.

    The server's time is what the calls took from sending to the app to its
    reply (one call runs at a time per connection). It is counted only while
    ``crowded()`` says other sessions are open: a lone tab's per-pixel
    shading goes at full speed, while among several tabs a flood of calls
    that each re-shade a scene is held to its share, however cheap or dear
    each call is. A slider drag of a few seconds goes at full speed on the
    burst either way.

    Parameters
    ----------
    crowded : callable
        ``crowded() -> bool``: True while other sessions share the server.
    """

    def __init__(self, crowded=lambda: True, clock=time.monotonic):
        self.crowded = crowded
        self.calls = TokenBucket(CALLS_PER_SECOND, CALL_BURST, clock)
        # one long call (opening a lesson) costs a wait of MAX_SHARE_WAIT at most;
        # a stream of calls is held to the share
        self.time = TokenBucket(SERVER_SHARE, SERVER_BURST_SECONDS, clock, floor=-SERVER_SHARE * MAX_SHARE_WAIT)

    async def take(self) -> None:
        """Wait for the next call's turn."""
        await self.calls.take()
        if self.crowded():
            await self.time.take(0.0)

    def spent(self, seconds: float) -> None:
        """Record that a call kept the server busy for ``seconds``."""
        if self.crowded():
            self.time.spend(seconds)


# ---------------------------------------------------------------------------
# the page's side

#: added to the served index page: when the server closes the session's socket
#: for a reason the student can act on (server full: 1013; refused: 1008),
#: say so on the page instead of leaving it loading
PAGE_SCRIPT = """<script>
(() => {
  const Native = window.WebSocket;
  const show = (text) => {
    let box = document.getElementById("phonglab-refused");
    if (!box) {
      box = document.createElement("div");
      box.id = "phonglab-refused";
      box.setAttribute("role", "alert");
      box.style.cssText = "position:fixed;inset:0;z-index:100000;display:flex;align-items:center;"
        + "justify-content:center;padding:2em;background:#fff;color:#222;font:20px sans-serif;text-align:center";
      document.body.appendChild(box);
    }
    box.textContent = text;
  };
  window.WebSocket = class extends Native {
    constructor(...args) {
      super(...args);
      this.addEventListener("close", (event) => {
        if (event.code === 1013 || event.code === 1008) show(event.reason || "The server refused this page.");
      });
    }
  };
})();
</script>
"""


def inject_page_script(html: str) -> str:
    """``html`` (the trame client's index page) with :data:`PAGE_SCRIPT` first in its head."""
    marker = "<head>"
    at = html.find(marker)
    if at < 0:
        return PAGE_SCRIPT + html
    at += len(marker)
    return html[:at] + "\n" + PAGE_SCRIPT + html[at:]
