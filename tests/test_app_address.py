"""The page's address names the lesson; a query from the browser is checked like any client value."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from phonglab.app import address

ENTRIES = [SimpleNamespace(path=Path("lessons") / name) for name in ("01-light.md", "04-specular.md")]


def test_query_round_trips_to_the_same_lesson():
    for i, entry in enumerate(ENTRIES):
        query = address.query_for(entry)
        assert address.lesson_index(query, ENTRIES) == (i, None), query


@pytest.mark.parametrize("query", [None, "", "?", "?other=1", "?lesson="])
def test_nothing_asked_opens_nothing(query):
    assert address.lesson_index(query, ENTRIES) == (None, None), query


@pytest.mark.parametrize("query, words", [
    ("?lesson=99-nope", "no lesson '99-nope'"),
    ("?lesson=../../etc/passwd", "no lesson"),
    (42, "not a query string"),
    ("?lesson=" + "x" * 3000, "not a query string"),
])
def test_a_bad_address_is_refused_with_a_problem(query, words):
    index, problem = address.lesson_index(query, ENTRIES)
    assert index is None and words in problem, (str(query)[:40], problem)
