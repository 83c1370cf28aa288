"""The wslink messages a browser tab may send, checked before its lesson app sees them.

The page talks to its trame app over one WebSocket with wslink's protocol:
every message is a msgpack map ``{"wslink": "1.0", "id": ID, "method": NAME,
"args": [...], "kwargs": {...}}``, cut into binary chunks that each start
with a 12-byte header ``struct.pack("<III", message_id, offset, total_size)``.
The first message is the hello, ``method = "wslink.hello"``, whose
``args[0]["secret"]`` must match the server's secret.

wslink itself allocates ``total_size`` bytes when a message's first chunk
arrives, answers errors with a full Python traceback and serves every RPC its
protocols register (remote rendering included). This module is what the
session server (:mod:`phonglab.app.server`) puts in front of it:

- :class:`Assembler` reassembles chunks in order, refusing any header that
  announces more than :data:`MAX_MESSAGE_BYTES` before anything is allocated;
- :func:`check_call` lets through only the RPC methods the page uses
  (:data:`ALLOWED_METHODS`), with arguments of the expected shape and finite
  numbers;
- :class:`StateWrites` lets one tab's ``trame.state.update`` write only the
  state keys its page defines, holding at most :data:`MAX_SESSION_STATE_BYTES`
  in them together;
- :class:`ReplyFilter` rewrites the app's error replies to a short message
  (the traceback goes to the server log, never to the browser).

A refused message raises :class:`ProtocolError` (the connection is closed) or
gets a short wslink error reply (:func:`error_reply`).
"""

from __future__ import annotations

import logging
import math
import secrets
import struct

import msgpack

log = logging.getLogger(__name__)

#: the largest message (all its chunks together) a browser may send, in bytes: 4 MiB
MAX_MESSAGE_BYTES = 4 * 1024 * 1024
#: the chunk header: message id, offset of this chunk, total size of the message
HEADER = struct.Struct("<III")
#: the largest WebSocket frame: one chunk of a message at the limit
MAX_FRAME_BYTES = MAX_MESSAGE_BYTES + HEADER.size
#: the largest hello (one chunk): the secret and a few fields
MAX_HELLO_BYTES = 1024

#: wslink's error codes (JSON-RPC 2.0, section 5.1)
METHOD_NOT_FOUND = -32601
INVALID_PARAMS = -32602
AUTHENTICATION_ERROR = -32000
EXCEPTION_ERROR = -32001
#: the id of the hello and of its reply
HELLO_ID = "system:c0:0"


class ProtocolError(Exception):
    """A message that breaks the protocol's limits; the connection is closed."""


# ---------------------------------------------------------------------------
# chunks


def chunk(payload: bytes) -> bytes:
    """``payload`` as one chunk: a header with a fresh random id, offset 0, the full size."""
    return HEADER.pack(secrets.randbits(32), 0, len(payload)) + payload


class Assembler:
    """Reassemble a connection's chunked messages, bounded by ``limit`` bytes.

    Chunks of one message must arrive in order (offset = bytes received so
    far), which is how wslink's clients send them; several messages may be
    in flight at once, but the sizes their headers announce may not add up
    to more than ``limit``. Memory grows with the bytes actually received,
    never with a size a header only announces.
    """

    def __init__(self, limit: int = MAX_MESSAGE_BYTES):
        self.limit = limit
        self._pending: dict[int, tuple[int, bytearray]] = {}

    def feed(self, frame: bytes) -> bytes | None:
        """The whole message (msgpack bytes) once ``frame`` completes one, else None.

        Raises
        ------
        ProtocolError
            A frame shorter than the header, a size over the limit, a chunk
            out of order or past the announced size.
        """
        if len(frame) < HEADER.size:
            raise ProtocolError(f"chunk of {len(frame)} bytes, shorter than the {HEADER.size}-byte header")
        message_id, offset, size = HEADER.unpack_from(frame)
        content = memoryview(frame)[HEADER.size:]
        pending = self._pending.get(message_id)
        if pending is None:
            # a new message: refuse an oversized announcement before allocating anything
            announced = size + sum(total for total, _ in self._pending.values())
            if size > self.limit or announced > self.limit:
                raise ProtocolError(f"message of {size} bytes announced, the limit is {self.limit}")
            if offset != 0:
                raise ProtocolError(f"message {message_id} starts at offset {offset}, not 0")
            pending = (size, bytearray())
        elif size != pending[0]:
            raise ProtocolError(f"message {message_id} announced {pending[0]} bytes, then {size}")
        total, received = pending
        if offset != len(received):
            raise ProtocolError(f"message {message_id}: chunk at offset {offset}, expected {len(received)}")
        if len(received) + len(content) > total:
            raise ProtocolError(f"message {message_id}: more than the {total} bytes announced")
        if len(received) + len(content) == total:
            self._pending.pop(message_id, None)
            return bytes(received) + bytes(content) if received else bytes(content)
        received += content
        self._pending[message_id] = (total, received)
        return None


def unpack(message: bytes):
    """The msgpack ``message`` decoded, as a dict with a string ``method``.

    Raises
    ------
    ProtocolError
        When it is not msgpack or not a wslink call.
    """
    try:
        rpc = msgpack.unpackb(message, strict_map_key=False)
    except Exception as exc:  # msgpack raises several kinds
        raise ProtocolError(f"message is not msgpack: {type(exc).__name__}") from None
    if not isinstance(rpc, dict) or not isinstance(rpc.get("method"), str):
        raise ProtocolError("message is not a wslink call (a map with a method)")
    return rpc


# ---------------------------------------------------------------------------
# hello


def hello_secret(frame: bytes) -> tuple[str, object]:
    """The secret and the id of a hello, the connection's first frame.

    Raises
    ------
    ProtocolError
        When the frame is not a single-chunk hello of at most :data:`MAX_HELLO_BYTES`.
    """
    if len(frame) > MAX_HELLO_BYTES:
        raise ProtocolError(f"hello of {len(frame)} bytes, the limit is {MAX_HELLO_BYTES}")
    message = Assembler(MAX_HELLO_BYTES).feed(frame)
    if message is None:
        raise ProtocolError("hello cut into several chunks")
    rpc = unpack(message)
    args = rpc.get("args")
    if rpc["method"] != "wslink.hello" or not isinstance(args, list) or not args or not isinstance(args[0], dict):
        raise ProtocolError(f"first message must be wslink.hello, got {rpc['method'][:60]!r}")
    secret = args[0].get("secret")
    return (secret if isinstance(secret, str) else ""), rpc.get("id")


def hello(secret: str) -> bytes:
    """A hello carrying ``secret``, as one chunk."""
    rpc = {"wslink": "1.0", "id": HELLO_ID, "method": "wslink.hello", "args": [{"secret": secret}], "kwargs": {}}
    return chunk(msgpack.packb(rpc))


def error_reply(rpc_id, code: int, message: str) -> bytes:
    """A wslink error reply to the call ``rpc_id``, as one chunk."""
    wrapper = {"wslink": "1.0", "id": rpc_id, "error": {"code": code, "message": message}}
    return chunk(msgpack.packb(wrapper))


# ---------------------------------------------------------------------------
# replies


class ReplyFilter:
    """Rewrite the app's error replies to a short message before they reach the browser.

    wslink answers a failed call with ``{"error": {"code", "message", "data":
    {"exception", "trace"}}}``: a Python traceback with the server's paths.
    :meth:`clean` replaces such a reply by its code and a short message and
    logs the details; every other chunk passes unchanged, after a look at its
    first bytes only.
    """

    #: how far into a message the ``"error"`` key of wslink's reply map can be
    HEAD_BYTES = 256
    _ERROR_KEY = msgpack.packb("error")

    def __init__(self, name: str = ""):
        self.name = name
        self._dropping: set[int] = set()

    def clean(self, frame: bytes) -> bytes | None:
        """``frame`` as the browser should get it; None to drop it (rest of a rewritten reply)."""
        if len(frame) < HEADER.size:
            return frame
        message_id, offset, size = HEADER.unpack_from(frame)
        if offset != 0:
            if message_id in self._dropping:
                if offset + len(frame) - HEADER.size >= size:
                    self._dropping.discard(message_id)
                return None
            return frame
        head = frame[HEADER.size:HEADER.size + self.HEAD_BYTES]
        if self._ERROR_KEY not in head:
            return frame
        error = _error_of(frame[HEADER.size:])
        if error is None:
            return frame
        rpc_id, code, message, data = error
        if data:
            log.error("session %s: call %s failed: %s", self.name, rpc_id, _describe(data))
        if len(frame) - HEADER.size < size:
            self._dropping.add(message_id)
        return error_reply(rpc_id, code, message)


def _error_of(payload: bytes):
    """``(id, code, message, data)`` when ``payload`` starts a wslink error reply, else None."""
    unpacker = msgpack.Unpacker(strict_map_key=False)
    unpacker.feed(payload)
    try:
        entries = unpacker.read_map_header()
        fields = {}
        for _ in range(entries):
            key = unpacker.unpack()
            if key == "error":
                try:
                    fields["error"] = unpacker.unpack()
                except msgpack.OutOfData:  # a long traceback, cut by the chunking
                    fields["error"] = {}
                break
            fields[key] = unpacker.unpack()
    except (msgpack.OutOfData, msgpack.UnpackValueError, msgpack.ExtraData, ValueError, TypeError):
        return None
    if "error" not in fields or "result" in fields:
        return None
    error = fields["error"] if isinstance(fields["error"], dict) else {}
    code = error.get("code") if isinstance(error.get("code"), int) else EXCEPTION_ERROR
    message = error.get("message") if isinstance(error.get("message"), str) else "Exception raised"
    return fields.get("id"), code, message[:200], error.get("data")


def _describe(data) -> str:
    if isinstance(data, dict):
        return "\n".join(str(data.get(key, "")) for key in ("method", "exception", "trace") if data.get(key))
    return str(data)[:2000]


# ---------------------------------------------------------------------------
# calls

#: the deepest nesting of lists and maps a call's arguments may have
MAX_DEPTH = 16
#: the most state changes one ``trame.state.update`` may carry
MAX_CHANGES = 200
#: the longest name (state key, trigger, array hash) a call may give
MAX_NAME = 200
#: the trame client's life-cycle events
LIFE_CYCLE = frozenset({"client_connected", "client_exited", "client_unmounted"})


def _names_a_state_key(change) -> bool:
    key = change.get("key") if isinstance(change, dict) else None
    # trame__* keys hold the page's templates and routes: the server's to set
    return isinstance(key, str) and 0 < len(key) <= MAX_NAME and not key.startswith("trame__")


def _state_update(args, kwargs) -> str | None:
    if kwargs or len(args) != 1 or not isinstance(args[0], list):
        return "expects one list of {key, value} changes"
    if len(args[0]) > MAX_CHANGES:
        return f"at most {MAX_CHANGES} changes at once, got {len(args[0])}"
    if not all(_names_a_state_key(change) for change in args[0]):
        return "each change must be {key, value} with a state key (not trame__*)"
    return None


def _state_get(args, kwargs) -> str | None:
    return "takes no arguments" if args or kwargs else None


def _life_cycle(args, kwargs) -> str | None:
    if kwargs or len(args) != 1 or args[0] not in LIFE_CYCLE:
        return f"expects one of {sorted(LIFE_CYCLE)}"
    return None


def _trigger(args, kwargs) -> str | None:
    if (kwargs or len(args) != 3 or not isinstance(args[0], str) or not 0 < len(args[0]) <= MAX_NAME
            or not isinstance(args[1], list) or not isinstance(args[2], dict)):
        return "expects (name, [args], {kwargs})"
    return None


def _array_get(args, kwargs) -> str | None:
    if kwargs or not 1 <= len(args) <= 2 or not isinstance(args[0], str) or not 0 < len(args[0]) <= MAX_NAME:
        return "expects (array hash, binary)"
    if len(args) == 2 and not isinstance(args[1], bool):
        return "expects (array hash, binary)"
    return None


#: the RPC methods the page calls (logged from real sessions: every lesson,
#: sliders, picking, turning and zooming the view, export, the accuracy
#: lesson), each with the check of its arguments
ALLOWED_METHODS = {
    "trame.state.get": _state_get,
    "trame.state.update": _state_update,
    "trame.lifecycle.update": _life_cycle,
    "trame.trigger": _trigger,
    "viewport.geometry.array.get": _array_get,
}


def check_call(rpc: dict):
    """None when the call ``rpc`` may reach the app, else ``(code, short message)`` for the error reply.

    A call must name a method of :data:`ALLOWED_METHODS`, pass arguments of
    the shape that method takes, and carry only finite numbers, strings,
    booleans, None and binary data, nested at most :data:`MAX_DEPTH` deep
    (a state change whose value is one number is the exception: the app's
    controls check that number). The id must be ``rpc:...`` (``system:...`` ids are wslink's own).
    """
    method = rpc["method"]
    check = ALLOWED_METHODS.get(method)
    if check is None:
        return METHOD_NOT_FOUND, f"method not available: {method[:80]}"
    rpc_id = rpc.get("id")
    if not isinstance(rpc_id, str) or not rpc_id.startswith("rpc:") or len(rpc_id) > MAX_NAME:
        return INVALID_PARAMS, f"{method}: the call id must be rpc:..."
    args = rpc.get("args", [])
    kwargs = rpc.get("kwargs", {})
    if not isinstance(args, list) or not isinstance(kwargs, dict):
        return INVALID_PARAMS, f"{method}: args must be a list and kwargs a map"
    problem = check(args, kwargs) or _plain_values(_checked_values(method, args, kwargs))
    if problem is not None:
        return INVALID_PARAMS, f"{method}: {problem}"
    return None


def _checked_values(method: str, args: list, kwargs: dict):
    """What :func:`_plain_values` checks in a call's arguments.

    A state change's own value is left to the app when it is a single number:
    the lesson's controls refuse a non-finite slider value with a notice on
    the page and set the slider back, which a refusal here could not do.
    """
    if method == "trame.state.update":
        return [[change.get("value") for change in args[0] if not isinstance(change.get("value"), float)],
                [{k: v for k, v in change.items() if k != "value"} for change in args[0]]]
    return [args, kwargs]


# ---------------------------------------------------------------------------
# what one tab may write into its state

#: the most bytes (msgpack) of values one tab may hold in its state keys together: the largest
#: value the page writes is a pasted student file of at most 64 KiB, so this leaves 16 times that
MAX_SESSION_STATE_BYTES = 1024 * 1024


class StateWrites:
    """Which state keys one tab may write, and how much it may keep in them.

    trame's ``trame.state.update`` stores whatever key the browser names: a
    client could add keys of megabytes each until the server runs out of
    memory. Only keys the page itself defines (the server set them first:
    the page's initial state, its controls, its panels) may be written, and
    the values this tab wrote are counted: together at most ``limit`` bytes
    (each value's msgpack size, the latest per key).

    Parameters
    ----------
    defined : callable
        ``defined(key) -> bool``: whether the tab's state holds ``key``
        (the app's ``state.has``).
    limit : int
        The most bytes the tab's written values may hold together.
    """

    def __init__(self, defined, limit: int = MAX_SESSION_STATE_BYTES):
        self.defined = defined
        self.limit = limit
        self._held: dict[str, int] = {}

    @property
    def held(self) -> int:
        """Bytes this tab's written values hold now."""
        return sum(self._held.values())

    def refusal(self, rpc: dict):
        """None when ``rpc`` (a call :func:`check_call` passed) may reach the app, else ``(code, short message)``.

        A refused update changes nothing (none of its keys is written).
        """
        if rpc["method"] != "trame.state.update":
            return None
        changes = rpc["args"][0]
        for change in changes:
            if not self.defined(change["key"]):
                return INVALID_PARAMS, (f"trame.state.update: {change['key'][:60]!r} is not a state key "
                                        "of this page")
        sizes = {change["key"]: len(msgpack.packb(change.get("value"))) for change in changes}
        total = sum({**self._held, **sizes}.values())
        if total > self.limit:
            return INVALID_PARAMS, (f"trame.state.update: this tab's values would hold {total:,} bytes, "
                                    f"at most {self.limit:,} allowed")
        self._held.update(sizes)
        return None


def _plain_values(value, depth: int = 0) -> str | None:
    """Why ``value`` is not plain data (finite numbers, text, lists, string-keyed maps), or None."""
    if depth > MAX_DEPTH:
        return f"arguments nested deeper than {MAX_DEPTH}"
    if isinstance(value, float):
        return None if math.isfinite(value) else f"numbers must be finite, got {value}"
    if value is None or isinstance(value, (bool, int, str, bytes)):
        return None
    if isinstance(value, list):
        for item in value:
            problem = _plain_values(item, depth + 1)
            if problem is not None:
                return problem
        return None
    if isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                return "map keys must be strings"
            problem = _plain_values(item, depth + 1)
            if problem is not None:
                return problem
        return None
    return f"unexpected value of type {type(value).__name__}"
