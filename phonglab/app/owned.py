"""State keys the server owns, and notices that stay short.

The browser can write any state key, not only the controls' (a tab's
``trame.state.set('mistake', 'abc')``). Keys the server writes for the page
to show are never read back from the state: the server keeps its own copy
and, when the browser overwrites one, writes its copy back
(:func:`keep_server_value`). Notices show the reason of a failure in one
short line (:func:`reason`), never an exception class or a huge value.
"""

from __future__ import annotations

from phonglab.scene.errors import printable

#: longest notice text, in characters
NOTICE_CHARS = 300


def short(text: str, limit: int = NOTICE_CHARS) -> str:
    """``text`` on one line, cut to ``limit`` characters with "…", characters that would act escaped (``\\u202e``)."""
    text = printable(" ".join(str(text).split()))
    return text if len(text) <= limit else text[: limit - 1] + "…"


def reason(exc: BaseException) -> str:
    """What went wrong, for a notice: the error's first line, short; no class name, no traceback."""
    lines = [line for line in str(exc).splitlines() if line.strip()]
    return short(lines[0]) if lines else "an internal error (details are in the server log)"


def keep_server_value(state, key: str, current):
    """A change handler that puts the server's value (``current()``) back when the browser writes ``key``."""

    def on_change(**_):
        ours = current()
        if state[key] != ours:
            state[key] = ours

    return on_change
