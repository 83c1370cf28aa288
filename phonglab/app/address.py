"""The page's address carries the lesson: ``?lesson=04-specular``.

The server puts the query of the open lesson in the state key
:data:`QUERY_KEY`; ``www/phonglab.js`` writes it into the address bar with
``history.replaceState``, so a reload, a bookmark or a pasted link opens the
same lesson. When the page loads, it sends its own query back in
:data:`REQUEST_KEY`; :func:`lesson_index` checks it like any client value.
"""

from __future__ import annotations

from urllib.parse import parse_qs, urlencode

#: state key: the query of the view the page shows (set by the server)
QUERY_KEY = "url_query"
#: state key: the query the page was opened with (set by the browser, once)
REQUEST_KEY = "url_request"


def lesson_key(entry) -> str:
    """How the address names a lesson: its file's stem (``04-specular``)."""
    return entry.path.stem


def query_for(entry) -> str:
    """``?lesson=04-specular`` for a catalogue entry."""
    return "?" + urlencode({"lesson": lesson_key(entry)})


def lesson_index(query, entries):
    """The index of the lesson a query names: ``(index, None)`` or ``(None, problem)``.

    No query, or a missing or empty ``lesson``, gives ``(None, None)`` (nothing asked).
    Anything else that does not name a lesson gives a problem to show.
    """
    if query is None:
        return None, None
    if not isinstance(query, str) or len(query) > 2000:
        return None, "address: not a query string"
    values = parse_qs(query.lstrip("?")).get("lesson", [])
    if not values or not values[0]:
        return None, None
    name = values[0]
    for i, entry in enumerate(entries):
        if lesson_key(entry) == name:
            return i, None
    known = ", ".join(lesson_key(e) for e in entries)
    return None, f"address: no lesson {name!r}; the lessons are {known}"
