"""State keys: scene field paths spelled so trame accepts them.

The page's state keys are the scene's field paths (``material.ks``,
``lights[1].position``), but a trame state key cannot contain ``.`` or
``[``. The mapping is:

=========================  ===========================
field path                 state key
=========================  ===========================
``model``                  ``model``
``material.ks``            ``material__ks``
``lights[1].position``     ``lights_1__position``
``lights[1].position[2]``  ``lights_1__position_2``
=========================  ===========================

``.`` becomes ``__`` and ``[i]`` becomes ``_i``. No scene field name ends in
``_<digits>``, so the mapping can be undone. The app also has a few
view-only fields, named like fields (``view.term``, ``lights[1].azimuth``);
they follow the same spelling.
"""

from __future__ import annotations

import functools
import re

_SEGMENT = re.compile(r"([A-Za-z][A-Za-z0-9_]*?)((?:_\d+)*)")
_PATH_SEGMENT = re.compile(r"([A-Za-z][A-Za-z0-9_]*)((?:\[\d+\])*)")


@functools.lru_cache(maxsize=4096)
def state_key(path: str) -> str:
    """The trame state key of a field path: ``lights[1].position`` -> ``lights_1__position``.

    Raises
    ------
    ValueError
        When ``path`` is not a field path (names joined by dots, each with optional ``[i]``).
    """
    parts = []
    for segment in path.split("."):
        match = _PATH_SEGMENT.fullmatch(segment)
        if not match or "__" in match.group(1) or re.search(r"_\d+$", match.group(1)):
            raise ValueError(f"not a field path: {path!r}")
        indices = "".join(f"_{i}" for i in re.findall(r"\[(\d+)\]", match.group(2)))
        parts.append(match.group(1) + indices)
    return "__".join(parts)


@functools.lru_cache(maxsize=4096)
def field_path(key: str) -> str:
    """The field path of a state key: ``lights_1__position`` -> ``lights[1].position``.

    Raises
    ------
    ValueError
        When ``key`` is not the spelling of a field path.
    """
    segments = []
    for segment in key.split("__"):
        match = _SEGMENT.fullmatch(segment)
        if not match:
            raise ValueError(f"not a field state key: {key!r}")
        indices = "".join(f"[{i}]" for i in re.findall(r"_(\d+)", match.group(2)))
        segments.append(match.group(1) + indices)
    return ".".join(segments)
