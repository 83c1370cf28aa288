"""Scene errors: what is wrong, where, and how it is shown.

A :class:`SceneError` names the field path, the bad value and what is
allowed; the file loader adds the file name and line. The message reads
``FILE:LINE: field.path: problem, got VALUE; hint``, with the unknown parts
left out. Values are shown as they would be written in TOML
(:func:`show_value`). This module is the bottom of the scene layer: it
imports nothing from phonglab.
"""

from __future__ import annotations

import difflib
import math
import unicodedata
from typing import Any

#: Unicode categories a message shows escaped: control characters (NUL, ESC, DEL ...), format
#: characters (right-to-left overrides, zero-width marks), line and paragraph separators, lone surrogates
_HIDDEN = frozenset({"Cc", "Cf", "Cs", "Zl", "Zp"})


def printable(text: str) -> str:
    """``text`` with every character that would act on the terminal or page instead of showing, escaped.

    A NUL, an escape sequence or a right-to-left override from a file or a
    browser would otherwise cut, recolour or reverse the rest of the message
    it is echoed in; each is shown as Python writes it (``\\x00``, ``\\u202e``).

    >>> printable("abc\\u202etxt.toml\\x00")
    'abc\\\\u202etxt.toml\\\\x00'
    """
    text = str(text)
    if text.isprintable():
        return text
    out = []
    for ch in text:
        if unicodedata.category(ch) not in _HIDDEN:
            out.append(ch)
        elif ord(ch) < 0x100:
            out.append(f"\\x{ord(ch):02x}")
        elif ord(ch) < 0x10000:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(f"\\U{ord(ch):08x}")
    return "".join(out)


class SceneError(ValueError):
    """A scene or lesson field is wrong.

    The message reads ``FILE:LINE: field.path: problem, got VALUE; hint``;
    the parts that are unknown are left out.

    Parameters
    ----------
    problem : str
        What is wrong, phrased as what is allowed ("must be a finite number >= 0").
    field : str, optional
        The field path ("material.shininess", "lights[1].position").
    value : object, optional
        The bad value; shown TOML-style after "got".
    hint : str, optional
        A suggestion ("did you mean \"shininess\"?").
    file : str, optional
        The file the value came from.
    line : int, optional
        The 1-based line of the value in that file.
    """

    _NO_VALUE = object()

    def __init__(self, problem, *, field=None, value=_NO_VALUE, hint=None, file=None, line=None):
        self.problem = problem
        self.field = field
        self.value = value
        self.hint = hint
        self.file = file
        self.line = line
        super().__init__(self._text())

    @property
    def has_value(self) -> bool:
        """Whether the error carries a bad value."""
        return self.value is not SceneError._NO_VALUE

    def _text(self) -> str:
        where = ""
        if self.file:
            where = f"{self.file}:{self.line}: " if self.line else f"{self.file}: "
        text = where + (f"{self.field}: " if self.field else "") + self.problem
        if self.has_value:
            text += f", got {show_value(self.value)}"
        if self.hint:
            text += f"; {self.hint}"
        return printable(text)

    def located(self, *, file=None, line=None, field=None) -> "SceneError":
        """A copy with the file, line or a field prefix filled in.

        Parameters
        ----------
        file, line : optional
            Used only where this error has none yet.
        field : str, optional
            A field path prepended to this error's own ("lights[1]" + "position").
        """
        path = self.field
        if field:
            path = join_path(field, self.field) if self.field else field
        return SceneError(
            self.problem,
            field=path,
            value=self.value,
            hint=self.hint,
            file=self.file or file,
            line=self.line or line,
        )


class SceneErrors(SceneError):
    """Several :class:`SceneError` at once, one per line of the message.

    Parameters
    ----------
    errors : list of SceneError
        At least one error; the first one's parts fill this error's attributes.
    """

    def __init__(self, errors):
        self.errors = list(errors)
        if not self.errors:
            raise ValueError("SceneErrors needs at least one error")
        first = self.errors[0]
        ValueError.__init__(self, "\n".join(str(e) for e in self.errors))
        self.problem, self.field, self.value = first.problem, first.field, first.value
        self.hint, self.file, self.line = first.hint, first.file, first.line

    def __iter__(self):
        return iter(self.errors)

    def __len__(self):
        return len(self.errors)

    def located(self, *, file=None, line=None, field=None) -> "SceneErrors":
        return SceneErrors([e.located(file=file, line=line, field=field) for e in self.errors])


#: longest value shown in a message, in characters; longer ones are cut with "…"
SHOWN_VALUE_CHARS = 80


def show_value(value: Any, limit: int = SHOWN_VALUE_CHARS) -> str:
    """Render a value as it would be written in TOML (``true``, ``"text"``, ``[1, 2]``).

    At most about ``limit`` characters: a longer rendering is cut and ends
    in ``… (N characters)`` so that a huge input cannot flood a message; a
    long string keeps its last third (``"/home/…/broken.ply" (83 characters)``). Lists
    and tables are rendered item by item only as far as the limit needs.
    """
    text = _show(value, limit + 1)
    if len(text) <= limit:
        return text
    total = _shown_length(value)
    if total:
        # a long string keeps its end too: a path's file name, the last words of a text
        tail = _show(value[-(limit // 3):], limit)[1:]
        return text[: limit - len(tail)] + "…" + tail + f" ({total:,} characters)"
    return text[:limit] + "…"


def _shown_length(value: Any) -> int | None:
    """The length of the full rendering when cheap (strings), else None."""
    return len(value) + 2 if isinstance(value, str) else None


def _show(value: Any, budget: int, depth: int = 0) -> str:
    """``show_value`` without the cut, stopping once ``budget`` characters are produced."""
    if depth > 8 and isinstance(value, (list, tuple, dict)):
        return "[…]" if not isinstance(value, dict) else "{…}"  # nesting past any scene value
    if isinstance(value, str) and len(value) > budget:
        value = value[:budget]
    if isinstance(value, (list, tuple, dict)) or (hasattr(value, "tolist") and getattr(value, "ndim", 0)):
        if hasattr(value, "tolist") and not isinstance(value, (list, tuple, dict)):
            value = value.ravel()[:budget].tolist() if value.size > budget else value.tolist()
        dict_items = isinstance(value, dict)
        items = value.items() if dict_items else value
        out, used = [], 0
        for item in items:
            piece = (f"{item[0]} = {_show(item[1], budget - used, depth + 1)}" if dict_items
                     else _show(item, budget - used, depth + 1))
            out.append(piece)
            used += len(piece) + 2
            if used > budget:
                break
        inner = ", ".join(out)
        return "{" + inner + "}" if dict_items else "[" + inner + "]"
    return _show_scalar(value)


def _show_scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "nothing"
    if isinstance(value, str):
        return '"' + printable(value.replace("\\", "\\\\").replace('"', '\\"')) + '"'
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e16:
        return str(int(value)) if value != 0 or math.copysign(1, value) > 0 else "-0"
    if hasattr(value, "tolist"):  # NumPy scalars
        return _show_scalar(value.tolist())
    return str(value)


def join_path(parent: str, child: str) -> str:
    """Join two field paths: ``join_path("lights[1]", "position")`` is ``lights[1].position``."""
    if not parent:
        return child
    if not child:
        return parent
    return parent + child if child.startswith("[") else f"{parent}.{child}"


def did_you_mean(word: str, allowed) -> str | None:
    """A ``did you mean "x"?`` hint for a near miss among ``allowed``, else None."""
    close = difflib.get_close_matches(str(word), [str(a) for a in allowed], n=1, cutoff=0.6)
    return f'did you mean "{close[0]}"?' if close else None


__all__ = ["SceneError", "SceneErrors", "show_value", "printable", "join_path", "did_you_mean"]
