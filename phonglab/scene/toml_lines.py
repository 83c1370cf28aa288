"""Find the line of each key in TOML text, for error messages.

``tomllib`` returns plain dictionaries without positions, so this module
scans the text once and records, for every table header and every key at the
start of a statement, the field path it defines and its 1-based line::

    [[lights]]            -> "lights[1]"           (the second [[lights]] table)
    position = [2, 2, 3]  -> "lights[1].position"

Keys inside inline tables and values spanning several lines map to the line
where their statement starts. :meth:`KeyLines.line` walks up a path
(``lights[1].position[2]`` -> ``lights[1].position`` -> ``lights[1]``) until
it finds a recorded one.
"""

from __future__ import annotations

import re

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def render_key(key: str) -> str:
    """A key as a field-path segment: ``name`` for bare keys, ``["a.b"]`` otherwise."""
    return key if _BARE_KEY.fullmatch(key) else '["' + key.replace('"', '\\"') + '"]'


def join(parent: str, segment: str) -> str:
    """Append a rendered segment to a field path."""
    if not parent:
        return segment.lstrip(".") if not segment.startswith("[") else segment
    return parent + segment if segment.startswith("[") else f"{parent}.{segment}"


def parent_path(path: str) -> str:
    """The path one level up: ``a.b[2]`` -> ``a.b`` -> ``a`` -> ``""``."""
    if path.endswith("]"):
        depth = 0
        for i in range(len(path) - 1, -1, -1):
            if path[i] == "]" and not _inside_quotes(path, i):
                depth += 1
            elif path[i] == "[" and not _inside_quotes(path, i):
                depth -= 1
                if depth == 0:
                    return path[:i]
        return ""
    cut = path.rfind(".")
    return path[:cut] if cut > 0 else ""


def _inside_quotes(text: str, index: int) -> bool:
    return text[:index].count('"') % 2 == 1


def _split_key(text: str) -> list[str] | None:
    """Split a (dotted, maybe quoted) TOML key into its parts; None if malformed."""
    parts, i, n = [], 0, len(text)
    while i < n:
        while i < n and text[i] in " \t":
            i += 1
        if i >= n:
            break
        if text[i] in "\"'":
            quote = text[i]
            end = i + 1
            while end < n and text[end] != quote:
                end += 2 if quote == '"' and text[end] == "\\" else 1
            if end >= n:
                return None
            parts.append(text[i + 1 : end])
            i = end + 1
        else:
            match = _BARE_KEY.match(text, i)
            if not match:
                return None
            parts.append(match.group())
            i = match.end()
        while i < n and text[i] in " \t":
            i += 1
        if i < n:
            if text[i] != ".":
                return None
            i += 1
    return parts or None


class KeyLines:
    """Line numbers of the keys and tables of one TOML text.

    Parameters
    ----------
    text : str
        The TOML text.
    first_line : int
        The file line of the text's first line (lesson front matter starts
        after the opening ``+++``).
    """

    def __init__(self, text: str, first_line: int = 1):
        self.lines: dict[str, int] = {}
        self._scan(text, first_line)

    def line(self, path: str | None) -> int | None:
        """The line that defines ``path`` or its nearest recorded ancestor, else None."""
        while path:
            if path in self.lines:
                return self.lines[path]
            path = parent_path(path)
        return None

    def _record(self, path: str, line: int) -> None:
        self.lines.setdefault(path, line)

    def _scan(self, text: str, first_line: int) -> None:
        table = ""  # rendered path of the current table
        counts: dict[str, int] = {}  # array-of-tables raw name -> tables seen
        open_string = None  # delimiter of a multi-line string still open
        depth = 0  # open brackets and braces of a value spanning lines
        for number, line in enumerate(text.splitlines(), start=first_line):
            i = 0
            if open_string:
                end = line.find(open_string)
                if end < 0:
                    continue
                i, open_string = end + 3, None
            elif depth == 0:
                stripped = line.strip()
                if not stripped or stripped.startswith("#"):
                    continue
                if stripped.startswith("["):
                    table = self._header(stripped, counts, number) or table
                    continue
                eq = self._key_end(line)
                if eq is None:
                    continue
                parts = _split_key(line[:eq])
                if parts:
                    path = table
                    for part in parts:
                        path = join(path, render_key(part))
                        self._record(path, number)
                i = eq + 1
            open_string, depth = self._scan_value(line, i, depth)

    @staticmethod
    def _key_end(line: str) -> int | None:
        """Index of the ``=`` ending the key at the start of ``line``, outside quotes."""
        quote = None
        for i, ch in enumerate(line):
            if quote:
                if ch == quote:
                    quote = None
            elif ch in "\"'":
                quote = ch
            elif ch == "=":
                return i
            elif ch == "#":
                return None
        return None

    def _header(self, stripped: str, counts: dict[str, int], number: int) -> str | None:
        """Record a ``[table]`` or ``[[array]]`` header; return the new table path."""
        array = stripped.startswith("[[")
        close = stripped.find("]]" if array else "]", 2 if array else 1)
        if close < 0:
            return None
        parts = _split_key(stripped[2 if array else 1 : close])
        if not parts:
            return None
        raw, rendered = "", ""
        for j, part in enumerate(parts):
            raw = f"{raw}.{part}" if raw else part
            rendered = join(rendered, render_key(part))
            last = j == len(parts) - 1
            if raw in counts and not (array and last):
                rendered += f"[{counts[raw] - 1}]"
        if array:
            counts[raw] = counts.get(raw, 0) + 1
            # arrays nested in the previous element start again
            for key in [k for k in counts if k.startswith(raw + ".")]:
                del counts[key]
            rendered += f"[{counts[raw] - 1}]"
        self._record(rendered, number)
        return rendered

    @staticmethod
    def _scan_value(line: str, i: int, depth: int) -> tuple[str | None, int]:
        """Track strings and brackets from index ``i``; return (open multi-line string, depth)."""
        n = len(line)
        while i < n:
            ch = line[i]
            if line.startswith('"""', i) or line.startswith("'''", i):
                delim = line[i : i + 3]
                end = line.find(delim, i + 3)
                if end < 0:
                    return delim, depth
                i = end + 3
                continue
            if ch in "\"'":
                i += 1
                while i < n and line[i] != ch:
                    i += 2 if ch == '"' and line[i] == "\\" else 1
            elif ch == "#":
                break
            elif ch in "[{":
                depth += 1
            elif ch in "]}":
                depth = max(0, depth - 1)
            i += 1
        return None, depth
