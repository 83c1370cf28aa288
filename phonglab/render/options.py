"""A figure's options, checked at the boundary before anything is rendered.

:func:`phonglab.render.figure` accepts Python values and, as ``phonglab
export`` passes them, their text forms: a size ``"1200x900"``, a setting
``"path=value"`` and a sweep ``"path=v1,v2,..."`` (values as in TOML). Each
check here raises :class:`~phonglab.render.FigureError` (or the scene's
:class:`~phonglab.scene.SceneError` for a scene field) with one line naming
the option, the value and what is allowed.
"""

from __future__ import annotations

import difflib
import numbers
import os
from pathlib import Path

from phonglab.render.errors import FigureError
from phonglab.scene import Lesson, Scene, SceneError, load, parse_path, parse_setting, parse_value
from phonglab.teaching import MISTAKES

#: output formats, by file extension
FORMATS = (".png", ".svg", ".pdf")
#: what ``plot=`` accepts
PLOTS = ("lobe", "lambert", "incidence", "furnace")
#: the figure's default size in pixels (width, height)
DEFAULT_SIZE = (1200, 900)
#: smallest width or height accepted, in pixels
MIN_SIZE = 16
#: largest width or height accepted, in pixels
MAX_SIZE = 8192
#: most pixels rendered for one figure: width × height × supersample² (the default
#: 1200x900 at supersample 2 renders 4,320,000; per-pixel shading needs about 200 bytes a pixel)
MAX_RENDER_PIXELS = 2**23
#: supersample factors accepted
SUPERSAMPLE_RANGE = (1, 4)
#: most cells in a sweep's grid (rows × columns)
MAX_SWEEP_CELLS = 64
#: the ``vectors`` default: N, L, R, V, H on a single render, none in grids
AUTO = "auto"
#: ``mistake=`` value that means "the lesson's own mistake"
LESSON_MISTAKE = "lesson"


def check_output(out_path) -> tuple[Path, str]:
    """The output path and its format, checked before anything is rendered.

    Raises
    ------
    FigureError
        For an unknown extension, a missing or unwritable folder, or a path
        that is a folder.
    """
    path = Path(os.fspath(out_path))
    ext = path.suffix.lower()
    if ext not in FORMATS:
        shown = f'"{ext}"' if ext else "no extension"
        raise FigureError(f"{path}: unknown output format {shown}; use one of {', '.join(FORMATS)}")
    folder = path.resolve().parent
    if path.is_dir():
        raise FigureError(f"{path}: is a folder; give a file name ending in {', '.join(FORMATS)}")
    if not folder.exists():
        raise FigureError(f"{path}: cannot write: the folder {folder} does not exist")
    if not folder.is_dir():
        raise FigureError(f"{path}: cannot write: {folder} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise FigureError(f"{path}: cannot write: the folder {folder} is not writable")
    return path, ext


def parse_size(text) -> tuple[int, int]:
    """``"1200x900"`` (or a pair of ints) as (width, height), each from 16 to 8192 pixels.

    Raises
    ------
    FigureError
    """
    if isinstance(text, str):
        parts = text.lower().replace("×", "x").split("x")
        if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
            raise FigureError(f'size: must be WIDTHxHEIGHT in pixels, e.g. 1200x900, got "{text}"')
        size = (int(parts[0]), int(parts[1]))
    else:
        try:
            width, height = text
            size = (int(width), int(height))
        except (TypeError, ValueError):
            raise FigureError(f"size: must be (width, height) in pixels, got {text!r}") from None
    if not all(isinstance(s, int) and MIN_SIZE <= s <= MAX_SIZE for s in size):
        raise FigureError(f"size: width and height must be from {MIN_SIZE} to {MAX_SIZE} pixels, got {size[0]}x{size[1]}")
    return size


def check_render_work(size, supersample) -> int:
    """The supersample factor, after checking it and the pixels it makes render.

    Raises
    ------
    FigureError
        A factor outside :data:`SUPERSAMPLE_RANGE`, or width × height ×
        supersample² past :data:`MAX_RENDER_PIXELS`, naming the limit.
    """
    low, high = SUPERSAMPLE_RANGE
    if isinstance(supersample, bool) or not isinstance(supersample, numbers.Integral) or not low <= supersample <= high:
        raise FigureError(f"supersample: must be a whole number from {low} to {high}, got {supersample!r}")
    pixels = size[0] * size[1] * supersample**2
    if pixels > MAX_RENDER_PIXELS:
        raise FigureError(
            f"size: {size[0]}x{size[1]} at supersample {supersample} renders {pixels:,} pixels, at most "
            f"{MAX_RENDER_PIXELS:,} allowed (width × height × supersample²); use a smaller size or supersample"
        )
    return int(supersample)


def check_sweep_cells(counts) -> None:
    """Refuse sweeps whose grid (the product of their value counts) passes :data:`MAX_SWEEP_CELLS`.

    Raises
    ------
    FigureError
    """
    cells = 1
    for n in counts:
        cells *= n
    if cells > MAX_SWEEP_CELLS:
        shown = " x ".join(str(n) for n in counts)
        raise FigureError(f"sweep: a {shown} grid has {cells:,} cells, at most {MAX_SWEEP_CELLS} allowed")


def split_values(text: str) -> list[str]:
    """Split ``0.1,0.5,0.9`` or ``[1,2,3],[4,5,6]`` at the commas outside brackets."""
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += ch
    parts.append(current)
    return [p.strip() for p in parts]


def parse_sweep(text: str) -> tuple[str, list]:
    """``"material.ks=0.1,0.5,0.9"`` as ``("material.ks", [0.1, 0.5, 0.9])``.

    Raises
    ------
    FigureError
        When there is no ``=`` or a value is empty.
    phonglab.scene.SceneError
        When the path is malformed.
    """
    if "=" not in text:
        raise FigureError(f'sweep: must be PATH=VALUE,VALUE,..., e.g. material.ks=0.1,0.5,0.9, got "{text}"')
    path, _, raw = text.partition("=")
    path = path.strip()
    parse_path(path)
    pieces = split_values(raw)
    if not raw.strip() or any(not p for p in pieces):
        raise FigureError(f'sweep: {path}: needs comma-separated values, e.g. {path}=1,2,3, got "{raw}"')
    try:
        return path, [parse_value(p) for p in pieces]
    except SceneError as exc:
        raise exc.located(field=path) from None


def resolve_source(scene_or_path):
    """``(scene, lesson)`` from a Scene, a Lesson or a file path; ``lesson`` is None for a scene.

    Raises
    ------
    FigureError
        For anything else.
    phonglab.scene.SceneError
        For a file that cannot be loaded.
    """
    if isinstance(scene_or_path, Scene):
        return scene_or_path, None
    if isinstance(scene_or_path, Lesson):
        return scene_or_path.scene, scene_or_path
    if isinstance(scene_or_path, (str, os.PathLike)):
        loaded = load(scene_or_path)
        return (loaded.scene, loaded) if isinstance(loaded, Lesson) else (loaded, None)
    raise FigureError(f"scene: must be a Scene, a Lesson or a file path, got {type(scene_or_path).__name__}")


def resolve_scene(scene_or_path):
    """A Scene from a Scene, a Lesson (its scene) or a scene/lesson file path."""
    return resolve_source(scene_or_path)[0]


def resolve_mistake(mistake, lesson, source="") -> str | None:
    """The mistake's name, checked: a name from :data:`phonglab.teaching.MISTAKES`, ``"lesson"`` or None.

    Parameters
    ----------
    mistake : str or None
        A mistake's name, or ``"lesson"`` for the lesson's own ``mistake`` key.
    lesson : phonglab.scene.Lesson or None
        The lesson being rendered (None for a plain scene).
    source : str
        How to name the input in an error (a file path).

    Raises
    ------
    FigureError
        One line naming the value and the names allowed; for ``"lesson"``
        when the input is not a lesson or the lesson has no mistake.
    """
    if mistake is None:
        return None
    names = tuple(MISTAKES)
    allowed = ", ".join(names) + f', or "{LESSON_MISTAKE}" (the lesson\'s own)'
    where = f"{source}: " if source else ""
    if mistake == LESSON_MISTAKE:
        if lesson is None:
            raise FigureError(f'{where}mistake: "{LESSON_MISTAKE}" needs a lesson (.md), and this is a scene; '
                              f"give a name: {', '.join(names)}")
        if not lesson.mistake:
            raise FigureError(f'{where}mistake: "{LESSON_MISTAKE}": the lesson has no mistake key; '
                              f"give a name: {', '.join(names)}")
        return lesson.mistake
    if not isinstance(mistake, str) or mistake not in names:
        close = difflib.get_close_matches(str(mistake), list(names), n=1)
        hint = f'; did you mean "{close[0]}"?' if close else ""
        raise FigureError(f'mistake: must be one of {allowed}, got "{mistake}"{hint}')
    return mistake


def apply_settings(scene, settings):
    """The scene with ``settings`` applied in order.

    ``settings`` holds ``(path, value)`` pairs or ``"path=value"`` strings
    (values as in TOML), or is a dict.
    """
    items = settings.items() if isinstance(settings, dict) else settings
    for item in items or ():
        path, value = parse_setting(item) if isinstance(item, str) else item
        scene = scene.replace(path, value)
    return scene


def normalize_sweeps(sweep, scene) -> list[tuple[str, list]]:
    """Sweeps as ``(path, values)`` pairs; every value is tried on ``scene`` first.

    ``sweep`` is one sweep or a sequence of them, each ``(path, values)`` or
    ``"path=v1,v2,..."``, or a dict ``{path: values}``.

    Returns
    -------
    list of (path, values)
        At most two; each value already known to be valid at its path.

    Raises
    ------
    FigureError
        For an empty sweep or more than two.
    phonglab.scene.SceneError
        For a value the scene refuses at its path.
    """
    if not sweep:
        return []
    if isinstance(sweep, dict):
        sweep = list(sweep.items())
    elif isinstance(sweep, str):
        sweep = [sweep]
    elif isinstance(sweep, tuple) and len(sweep) == 2 and isinstance(sweep[0], str) and not isinstance(sweep[1], str):
        sweep = [sweep]  # a single (path, values) pair
    parsed = []
    for item in sweep:
        path, values = parse_sweep(item) if isinstance(item, str) else (item[0], list(item[1]))
        if not values:
            raise FigureError(f"sweep: {path}: needs at least one value")
        parsed.append((path, values))
    if len(parsed) > 2:
        raise FigureError(f"sweep: at most two sweeps (rows, columns), got {len(parsed)}")
    # the grid's size before any value is tried on the scene
    check_sweep_cells([len(values) for _, values in parsed])
    for path, values in parsed:
        for value in values:
            scene.replace(path, value)  # raises SceneError naming the path and value
    return parsed


#: the vectors a figure or the view draws at the probe, in drawing order (their colours and legend:
#: :data:`phonglab.render.glyphs.VECTORS`)
VECTOR_LETTERS = "NLRVH"


def parse_vectors(letters) -> str:
    """Normalise a vector selection: ``"NLRVH"``, ``"N,L,R"``, ``["N", "V"]``, ``""`` or None.

    Kept here, with the other options, so that a figure's request is checked
    without loading PyVista (:mod:`~phonglab.render.figure_request`).

    Returns
    -------
    str
        The selected letters in drawing order (may be empty).

    Raises
    ------
    ValueError
        Naming the unknown letters and the allowed ones.
    """
    if letters is None:
        return ""
    if not isinstance(letters, str):
        letters = "".join(str(x) for x in letters)
    text = letters.replace(",", "").replace(" ", "").upper()
    if text in ("NONE", ""):
        return ""
    unknown = sorted(set(text) - set(VECTOR_LETTERS))
    if unknown:
        raise ValueError(
            f"vectors: unknown {', '.join(unknown)} in {letters!r}; allowed letters are N, L, R, V, H (or none)"
        )
    return "".join(v for v in VECTOR_LETTERS if v in text)
