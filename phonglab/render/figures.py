"""Figures for slides and handouts: single renders, per-term views, sweeps, plots.

:func:`figure` is the one entry point (``phonglab.figure``); ``phonglab
export`` is a thin layer over it. Every output is written to a temporary
file in the target folder and renamed into place, so a failure never leaves
a partial file behind.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from phonglab.render import _files
from phonglab.render.annotate import downsample
from phonglab.render.view import BACKGROUND, SceneView

#: output formats, by file extension
FORMATS = (".png", ".svg", ".pdf")
#: what ``plot=`` accepts
PLOTS = ("lobe", "lambert", "incidence")
#: the figure's default size in pixels (width, height)
DEFAULT_SIZE = (1200, 900)
#: smallest width or height accepted, in pixels
MIN_SIZE = 16
#: largest width or height accepted, in pixels
MAX_SIZE = 8192
#: the ``vectors`` default: N, L, R, V, H on a single render, none in grids
AUTO = "auto"

#: how sweep labels name the common fields
FIELD_SYMBOLS = {
    "material.ka": "$k_a$",
    "material.kd": "$k_d$",
    "material.ks": "$k_s$",
    "material.emission": "$k_e$",
    "material.shininess": r"$\alpha$",
    "material.opacity": "opacity",
    "geometry.resolution": "resolution",
}
#: fields whose values are names: the label shows the value alone
NAMED_FIELDS = ("interpolation", "model", "geometry.kind", "geometry.name")


class FigureError(ValueError):
    """A figure cannot be made from the given options; the message is one line."""


# ---------------------------------------------------------------------------
# checking the inputs


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
    if not all(MIN_SIZE <= s <= MAX_SIZE for s in size):
        raise FigureError(f"size: width and height must be from {MIN_SIZE} to {MAX_SIZE} pixels, got {size[0]}x{size[1]}")
    return size


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
    """
    from phonglab.scene import parse_path, parse_value

    if "=" not in text:
        raise FigureError(f'sweep: must be PATH=VALUE,VALUE,..., e.g. material.ks=0.1,0.5,0.9, got "{text}"')
    path, _, raw = text.partition("=")
    path = path.strip()
    parse_path(path)
    pieces = split_values(raw)
    if not raw.strip() or any(not p for p in pieces):
        raise FigureError(f'sweep: {path}: needs comma-separated values, e.g. {path}=1,2,3, got "{raw}"')
    return path, [parse_value(p) for p in pieces]


def resolve_scene(scene_or_path):
    """A Scene from a Scene, a Lesson (its scene) or a scene/lesson file path."""
    from phonglab.scene import Lesson, Scene, load

    if isinstance(scene_or_path, Scene):
        return scene_or_path
    if isinstance(scene_or_path, Lesson):
        return scene_or_path.scene
    if isinstance(scene_or_path, (str, os.PathLike)):
        loaded = load(scene_or_path)
        return loaded.scene if isinstance(loaded, Lesson) else loaded
    raise FigureError(f"scene: must be a Scene, a Lesson or a file path, got {type(scene_or_path).__name__}")


def apply_settings(scene, settings):
    """The scene with ``settings`` applied in order.

    ``settings`` holds ``(path, value)`` pairs or ``"path=value"`` strings
    (values as in TOML), or is a dict.
    """
    from phonglab.scene import parse_setting

    items = settings.items() if isinstance(settings, dict) else settings
    for item in items or ():
        path, value = parse_setting(item) if isinstance(item, str) else item
        scene = scene.replace(path, value)
    return scene


def normalize_sweeps(sweep, scene) -> list[tuple[str, list]]:
    """Sweeps as ``(path, values)`` pairs; every value is tried on ``scene`` first.

    Returns
    -------
    list of (path, values)
        At most two; each value already known to be valid at its path.
    """
    if not sweep:
        return []
    if isinstance(sweep, dict):
        sweep = list(sweep.items())
    elif isinstance(sweep, str):
        sweep = [sweep]
    elif isinstance(sweep, tuple) and len(sweep) == 2 and isinstance(sweep[0], str) and not isinstance(sweep[1], str):
        sweep = [sweep]  # a single (path, values) pair
    out = []
    for item in sweep:
        path, values = parse_sweep(item) if isinstance(item, str) else (item[0], list(item[1]))
        if not values:
            raise FigureError(f"sweep: {path}: needs at least one value")
        for value in values:
            scene.replace(path, value)  # raises SceneError naming the path and value
        out.append((path, values))
    if len(out) > 2:
        raise FigureError(f"sweep: at most two sweeps (rows, columns), got {len(out)}")
    return out


def sweep_label(path: str, value) -> str:
    """How a sweep value is written on the grid: ``$k_s$ = 0.5``, ``pixel``."""
    from phonglab.scene.model import show_value

    if path in NAMED_FIELDS and isinstance(value, str):
        return value
    text = value if isinstance(value, str) else show_value(value)
    return f"{FIELD_SYMBOLS.get(path, path)} = {text}"


def stderr_progress(done: int, total: int, label: str) -> None:
    """Progress on stderr: one line per finished render (redrawn in place on a terminal)."""
    line = f"phonglab: rendered {done}/{total}" + (f"  {label}" if label else "")
    if sys.stderr.isatty():
        end = "\n" if done == total else ""
        sys.stderr.write("\r\033[K" + line + end)
    else:
        sys.stderr.write(line + "\n")
    sys.stderr.flush()


# ---------------------------------------------------------------------------
# writing


def write_atomically(path: Path, write) -> None:
    """Write ``path`` whole or not at all (see :func:`phonglab.render._files.write_atomically`).

    Raises
    ------
    FigureError
        If the file cannot be written; nothing is left behind.
    """
    try:
        _files.write_atomically(path, write)
    except OSError as exc:
        raise FigureError(f"{path}: cannot write: {exc.strerror or exc}") from None


def save_image(image: np.ndarray, path: Path, ext: str) -> None:
    """Write an RGB image: PNG directly; SVG/PDF as a page holding the image at 100 dpi."""
    if ext == ".png":
        from PIL import Image

        write_atomically(path, lambda tmp: Image.fromarray(image).save(tmp, format="PNG"))
        return
    fig = _canvas((image.shape[1], image.shape[0]))
    fig.figimage(image, 0, 0, origin="upper")
    save_figure(fig, path, ext)


def save_figure(fig, path: Path, ext: str) -> None:
    """Save a matplotlib figure in the format of ``ext``, atomically, and close it."""
    import matplotlib.pyplot as plt

    try:
        write_atomically(path, lambda tmp: fig.savefig(tmp, format=ext[1:], dpi=100, facecolor=fig.get_facecolor()))
    finally:
        plt.close(fig)


def _canvas(size, facecolor="white"):
    """A matplotlib figure of ``size`` = (width, height) pixels at 100 dpi (Agg)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100, facecolor=facecolor)


# ---------------------------------------------------------------------------
# rendering


def render(scene, size, *, vectors="NLRVH", term="color", supersample: int = 2, background=BACKGROUND,
           legend: bool = True, view: SceneView | None = None) -> np.ndarray:
    """One render of ``scene`` as a (height, width, 3) uint8 image.

    Parameters
    ----------
    scene : Scene
    size : (int, int)
        Width and height of the image.
    vectors : str or None
        Which of N, L, R, V, H to draw.
    term : str
        ``"color"`` or one of ``"ambient"``, ``"diffuse"``, ``"specular"``.
    supersample : int
        Render ``supersample`` times larger and average down (antialiasing).
    legend : bool
        Draw the legend box (letters at the arrow tips are always drawn).
    view : SceneView, optional
        A view to reuse (sweeps); it is updated to ``scene``.
    """
    ss = max(1, int(supersample))
    big = (size[0] * ss, size[1] * ss)
    own = view is None
    if own:
        view = SceneView(scene, size=big, vectors=vectors, term=term, background=background, vtk_text=False)
    else:
        view.set_size(big)
        view.update(scene)
        view.set_term(term)
        view.set_vectors(vectors)
    try:
        image = view.annotate(view.screenshot(annotate=False), legend=legend)
    finally:
        if own:
            view.close()
    return downsample(image, ss)


def figure(
    scene_or_path,
    out_path,
    *,
    size=DEFAULT_SIZE,
    settings=(),
    vectors=AUTO,
    terms: bool = False,
    sweep=None,
    plot: str | None = None,
    progress=None,
    supersample: int = 2,
    background=BACKGROUND,
) -> Path:
    """Render a scene or lesson to a PNG (or SVG/PDF) figure.

    Parameters
    ----------
    scene_or_path : Scene, Lesson, str or path-like
        A scene, a lesson (its scene is used) or a ``.toml``/``.md`` file.
    out_path : str or path-like
        The file to write; its extension picks the format (``.png``,
        ``.svg``, ``.pdf``; renders are embedded as images in SVG and PDF).
    size : (int, int) or str
        Width and height of the whole figure in pixels (``"1200x900"`` too).
    settings : sequence of (path, value) or "path=value", or dict
        Scene fields to change first, as with ``phonglab export --set``.
    vectors : str or None
        Which of N, L, R, V, H to draw at the probe (``"NLRVH"``, ``"N,L,V"``,
        None for none). The default draws all five on a single render and
        none in per-term views and sweeps.
    terms : bool
        Ambient, diffuse, specular and their sum side by side (one row
        when the figure is at least twice as wide as tall, else 2 × 2).
    sweep : sequence, optional
        One or two sweeps, each ``(path, values)`` or ``"path=v1,v2,..."``:
        a grid with one render per cell, rows from the first sweep and
        columns from the second.
    plot : {"lobe", "lambert", "incidence"}, optional
        A matplotlib plot instead of a render: the specular lobe
        :math:`\\max(0, \\cos\\phi)^\\alpha`, the Lambert cosine, or the plane
        of incidence at the scene's probe point.
    progress : callable or bool, optional
        ``progress(done, total, label)`` after each render of a grid; True
        prints to stderr.
    supersample : int
        Antialiasing factor for renders (render larger, average down).
    background : 3 floats in [0, 1]
        Background colour of renders.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    FigureError
        Bad options or an unwritable output (nothing is written).
    phonglab.scene.SceneError
        A bad scene file, setting path or value (nothing is written).

    Examples
    --------
    >>> import phonglab as pl                                   # doctest: +SKIP
    >>> pl.figure("lessons/01-diffuse.md", "matrix.png", vectors=None,
    ...           sweep=[("material.ks", [0.1, 0.5, 0.9]),
    ...                  ("material.shininess", [4, 32, 256])])  # doctest: +SKIP
    """
    # check everything before the first render
    path, ext = check_output(out_path)
    size = parse_size(size)
    if plot is not None and plot not in PLOTS:
        raise FigureError(f'plot: must be one of {", ".join(PLOTS)}, got "{plot}"')
    if plot is not None and (terms or sweep):
        raise FigureError("plot: a plot cannot be combined with terms or sweeps")
    if terms and sweep:
        raise FigureError("terms: per-term views cannot be combined with sweeps; choose one")
    scene = apply_settings(resolve_scene(scene_or_path), settings)
    sweeps = normalize_sweeps(sweep, scene)
    grid = bool(terms or sweeps)
    letters = (None if grid else "NLRVH") if vectors == AUTO else vectors
    from phonglab.render.glyphs import parse_vectors

    try:
        letters = parse_vectors(letters)
    except ValueError as exc:
        raise FigureError(str(exc)) from None
    if progress is True:
        progress = stderr_progress

    if plot is not None:
        from phonglab.render import plots

        fig = plots.make_plot(plot, scene, size)
        save_figure(fig, path, ext)
    elif sweeps:
        fig = _sweep_figure(scene, sweeps, size, letters, supersample, background, progress)
        save_figure(fig, path, ext)
    elif terms:
        fig = _terms_figure(scene, size, letters, supersample, background, progress)
        save_figure(fig, path, ext)
    else:
        image = render(scene, size, vectors=letters, supersample=supersample, background=background)
        save_image(image, path, ext)
    return path


# ---------------------------------------------------------------------------
# grids


def _grid_layout(size, rows, cols, *, title: bool, row_labels: bool, col_labels: bool):
    """Pixel boxes (x, y_from_top, w, h) of the cells, and the label bands."""
    width, height = size
    unit = max(10, round(min(width, height) / 30))
    top = (round(2.2 * unit) if title else round(0.5 * unit)) + (round(1.8 * unit) if col_labels else 0)
    left = round(5.5 * unit) if row_labels else round(0.5 * unit)
    gap = max(2, round(0.3 * unit))
    bottom = right = round(0.5 * unit)
    cell_w = (width - left - right - gap * (cols - 1)) // cols
    cell_h = (height - top - bottom - gap * (rows - 1)) // rows
    if cell_w < 8 or cell_h < 8:
        raise FigureError(f"size: {width}x{height} is too small for a {rows} x {cols} grid")
    boxes = [
        [(left + c * (cell_w + gap), top + r * (cell_h + gap), cell_w, cell_h) for c in range(cols)]
        for r in range(rows)
    ]
    return boxes, unit


def _place(fig, image, box, size):
    """Put an image at a pixel box (top-left origin), unscaled."""
    x, y, w, h = box
    fig.figimage(image, xo=x, yo=size[1] - y - h, origin="upper")


def _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                 *, row_titles=None, col_titles=None, title=""):
    """Render ``cells`` (row-major list of (scene, term, label)) into a labelled grid figure."""
    boxes, unit = _grid_layout(size, rows, cols, title=bool(title), row_labels=bool(row_titles),
                               col_labels=bool(col_titles))
    fig = _canvas(size, facecolor="white")
    fs = unit * 0.72  # points at 100 dpi: about unit pixels tall
    view = None
    total = len(cells)
    try:
        for i, (cell_scene, term, label) in enumerate(cells):
            r, c = divmod(i, cols)
            box = boxes[r][c]
            cell_size = (box[2], box[3])
            if view is None:
                ss = max(1, int(supersample))
                view = SceneView(cell_scene, size=(cell_size[0] * ss, cell_size[1] * ss), vectors=letters,
                                 term=term, background=background, vtk_text=False)
            image = render(cell_scene, cell_size, vectors=letters, term=term, supersample=supersample,
                           background=background, legend=False, view=view)
            _place(fig, image, box, size)
            if progress:
                progress(i + 1, total, label)
    finally:
        if view is not None:
            view.close()
    W, H = size
    if title:
        fig.text(0.5, 1 - (0.3 * unit) / H, title, ha="center", va="top", fontsize=fs * 1.25, weight="bold")
    if col_titles:
        for c, text in enumerate(col_titles):
            x, y, w, _ = boxes[0][c]
            fig.text((x + w / 2) / W, 1 - (y - 0.4 * unit) / H, text, ha="center", va="bottom", fontsize=fs)
    if row_titles:
        for r, text in enumerate(row_titles):
            x, y, _, h = boxes[r][0]
            fig.text((x - 0.4 * unit) / W, 1 - (y + h / 2) / H, text, ha="right", va="center", fontsize=fs)
    return fig


def _terms_figure(scene, size, letters, supersample, background, progress):
    """Ambient, diffuse, specular and their sum, labelled with their formulas."""
    spec = r"\max(0,\,n\cdot h)^{\alpha}" if scene.model == "blinn-phong" else r"\max(0,\,r\cdot v)^{\alpha}"
    terms = [
        ("ambient", "ambient", rf"$k_a I_a$ = {ambient_value(scene)}"),
        ("diffuse", "diffuse", r"$k_d I_d \max(0,\,n\cdot l)$"),
        ("specular", "specular", rf"$k_s I_s {spec}$"),
        ("color", "sum", "all three + emission" if any(scene.material.emission) else "all three added"),
    ]
    rows, cols = (1, 4) if size[0] >= 2 * size[1] else (2, 2)
    cells = [(scene, term, term) for term, _, _ in terms]
    boxes, unit = _grid_layout(size, rows, cols, title=False, row_labels=False, col_labels=False)
    fig = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress)
    # a label inside each cell's top edge, small enough to fit the cell's width
    fs = min(unit * 0.72, boxes[0][0][2] / 13 * 0.72)
    W, H = size
    for i, (_, name, formula) in enumerate(terms):
        r, c = divmod(i, cols)
        x, y, w, _ = boxes[r][c]
        fig.text((x + w / 2) / W, 1 - (y + 0.3 * unit) / H, f"{name}\n{formula}", ha="center", va="top",
                 fontsize=fs, color="white", linespacing=1.5,
                 bbox=dict(boxstyle="round,pad=0.3", facecolor=(0, 0, 0, 0.45), edgecolor="none"))
    return fig


def ambient_value(scene) -> str:
    """The scene's constant ambient term :math:`k_a \\circ I_a` as text: ``0.02``, or ``(0.08, 0.03, 0.02)``.

    Taken from the core (one shaded point), so it is the value the ambient
    panel shows; one number when the three channels agree.
    """
    from phonglab.render import shading

    point = np.array([[0.0, 0.0, 1.0]])
    ambient = np.asarray(shading.shade(scene, point, point).ambient, dtype=float).reshape(-1, 3)[0]
    if np.allclose(ambient, ambient[0], rtol=0, atol=5e-4):
        return f"{ambient[0]:.3g}"
    return "(" + ", ".join(f"{c:.3g}" for c in ambient) + ")"


def _sweep_figure(scene, sweeps, size, letters, supersample, background, progress):
    """The classic material matrix: one render per combination of sweep values."""
    (row_path, row_values), *rest = sweeps
    col_path, col_values = rest[0] if rest else (None, [None])
    if not rest:
        # a single sweep reads best as one row
        row_path, row_values, col_path, col_values = None, [None], row_path, row_values
    cells = []
    for rv in row_values:
        for cv in col_values:
            cell = scene
            parts = []
            if row_path is not None:
                cell = cell.replace(row_path, rv)
                parts.append(f"{row_path}={_plain(rv)}")
            if col_path is not None:
                cell = cell.replace(col_path, cv)
                parts.append(f"{col_path}={_plain(cv)}")
            cells.append((cell, "color", ", ".join(parts)))
    row_titles = [sweep_label(row_path, v) for v in row_values] if row_path is not None else None
    col_titles = [sweep_label(col_path, v) for v in col_values]
    return _grid_figure(scene, cells, len(row_values), len(col_values), size, letters, supersample, background,
                        progress, row_titles=row_titles, col_titles=col_titles, title=scene.title)


def _plain(value) -> str:
    from phonglab.scene.model import show_value

    return value if isinstance(value, str) else show_value(value)
