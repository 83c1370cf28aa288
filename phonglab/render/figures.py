"""Figures for slides and handouts: single renders, per-term views, sweeps, plots.

:func:`figure` is the one entry point (``phonglab.figure``); ``phonglab
export`` is a thin layer over it. Every output is written to a temporary
file in the target folder and renamed into place, so a failure never leaves
a partial file behind.

A figure can show a lesson's *common mistake* (``mistake=``, a name from
:data:`phonglab.teaching.MISTAKES`): every render is then shaded with that
deliberately wrong variant, and a band at the top says so in red, with the
wrong line of code next to the right one. ``compare=True`` puts the correct
render and the mistaken one side by side.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from phonglab.render import _files, shading
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
#: ``mistake=`` value that means "the lesson's own mistake"
LESSON_MISTAKE = "lesson"
#: colours of the mistake labels: wrong (red), right (green), notes (grey)
WRONG_COLOR = "#b71c1c"
RIGHT_COLOR = "#1b5e20"
NOTE_COLOR = "#424242"


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
    return resolve_source(scene_or_path)[0]


def resolve_source(scene_or_path):
    """``(scene, lesson)`` from a Scene, a Lesson or a file path; ``lesson`` is None for a scene."""
    from phonglab.scene import Lesson, Scene, load

    if isinstance(scene_or_path, Scene):
        return scene_or_path, None
    if isinstance(scene_or_path, Lesson):
        return scene_or_path.scene, scene_or_path
    if isinstance(scene_or_path, (str, os.PathLike)):
        loaded = load(scene_or_path)
        return (loaded.scene, loaded) if isinstance(loaded, Lesson) else (loaded, None)
    raise FigureError(f"scene: must be a Scene, a Lesson or a file path, got {type(scene_or_path).__name__}")


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
    import difflib

    from phonglab.render.shading import mistake_names

    if mistake is None:
        return None
    names = mistake_names()
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
           legend: bool = True, view: SceneView | None = None, mistake: str | None = None) -> np.ndarray:
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
    mistake : str or None
        Shade with this common mistake (a name from
        :data:`phonglab.teaching.MISTAKES`) instead of the correct model.
        The image carries no label: :func:`figure` adds one.
    """
    ss = max(1, int(supersample))
    big = (size[0] * ss, size[1] * ss)
    own = view is None
    if own:
        view = SceneView(scene, size=big, vectors=vectors, term=term, background=background, vtk_text=False,
                         mistake=mistake)
    else:
        view.set_size(big)
        view.update(scene)
        view.set_term(term)
        view.set_mistake(mistake)
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
    mistake: str | None = None,
    compare: bool = False,
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
    mistake : str, optional
        Show a common mistake: a name from :data:`phonglab.teaching.MISTAKES`,
        or ``"lesson"`` for the lesson's own ``mistake`` key. Every render
        (single, per-term, sweep) is shaded with the deliberately wrong
        variant, per face, per vertex or per pixel as the scene says, and a
        red band at the top labels the figure as wrong, with the wrong and
        the right line of code. A mistake that shows only per pixel
        (``needs_raw_normals``) in a flat or Gouraud scene is rendered as
        asked, and the band says that the picture is therefore the correct one.
    compare : bool
        With ``mistake``: the correct render and the mistaken one side by
        side (one above the other in a tall figure), labelled "correct" and
        "common mistake: ...".

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
    >>> pl.figure("lessons/03-diffuse.md", "mistake.png", mistake="lesson",
    ...           compare=True)                                 # doctest: +SKIP
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
    if compare and mistake is None:
        raise FigureError('compare: needs a mistake to compare with, e.g. mistake="lesson"')
    if compare and (terms or sweep or plot is not None):
        raise FigureError("compare: the side-by-side comparison cannot be combined with terms, sweeps or plots")
    if mistake is not None and plot is not None:
        raise FigureError("mistake: plots show the correct model only; a mistake cannot be combined with plot")
    base, lesson = resolve_source(scene_or_path)
    source = os.fspath(scene_or_path) if isinstance(scene_or_path, (str, os.PathLike)) else ""
    mistake = resolve_mistake(mistake, lesson, source)
    scene = apply_settings(base, settings)
    sweeps = normalize_sweeps(sweep, scene)
    grid = bool(terms or sweeps or compare)
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
    elif compare:
        fig = _compare_figure(scene, mistake, size, letters, supersample, background, progress)
        save_figure(fig, path, ext)
    elif sweeps:
        fig = _sweep_figure(scene, sweeps, size, letters, supersample, background, progress, mistake=mistake)
        save_figure(fig, path, ext)
    elif terms:
        fig = _terms_figure(scene, size, letters, supersample, background, progress, mistake=mistake)
        save_figure(fig, path, ext)
    elif mistake is not None:
        fig = _mistake_render_figure(scene, mistake, size, letters, supersample, background)
        save_figure(fig, path, ext)
    else:
        image = render(scene, size, vectors=letters, supersample=supersample, background=background)
        save_image(image, path, ext)
    return path


# ---------------------------------------------------------------------------
# grids


def _grid_layout(size, rows, cols, *, title: bool, row_labels: bool, col_labels: bool, top_offset: int = 0):
    """Pixel boxes (x, y_from_top, w, h) of the cells, and the label bands.

    ``top_offset`` pixels at the top are kept free (for a mistake's band).
    """
    width, height = size
    unit = _unit(size)
    top = (round(2.2 * unit) if title else round(0.5 * unit)) + (round(1.8 * unit) if col_labels else 0)
    top += int(top_offset)
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


def _unit(size) -> int:
    """The layout's unit in pixels: about the height of a label's text."""
    return max(10, round(min(size) / 30))


def _place(fig, image, box, size):
    """Put an image at a pixel box (top-left origin), unscaled."""
    x, y, w, h = box
    fig.figimage(image, xo=x, yo=size[1] - y - h, origin="upper")


def _frame(fig, box, size, unit, color):
    """A coloured frame drawn along the edge of a pixel box (top-left origin)."""
    from matplotlib.patches import Rectangle

    x, y, w, h = box
    W, H = size
    fig.add_artist(Rectangle((x / W, 1 - (y + h) / H), w / W, h / H, transform=fig.transFigure, fill=False,
                             edgecolor=color, linewidth=max(1.5, unit * 0.12), zorder=2))


def _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                 *, row_titles=None, col_titles=None, title="", band=None):
    """Render ``cells`` into a labelled grid figure.

    Parameters
    ----------
    cells : list of (scene, term, label, mistake)
        Row-major; ``mistake`` is None for a correct render, else the
        common mistake the cell is shaded with.
    band : callable, optional
        ``band(fig) -> pixels``: draws a band at the top of the figure and
        returns its height; the grid goes below it.

    Returns
    -------
    fig, boxes, unit
        The figure, the cells' pixel boxes (x, y_from_top, w, h) by row, and the layout unit.
    """
    fig = _canvas(size, facecolor="white")
    top_offset = band(fig) if band is not None else 0
    boxes, unit = _grid_layout(size, rows, cols, title=bool(title), row_labels=bool(row_titles),
                               col_labels=bool(col_titles), top_offset=top_offset)
    fs = unit * 0.72  # points at 100 dpi: about unit pixels tall
    view = None
    total = len(cells)
    try:
        for i, (cell_scene, term, label, mistake) in enumerate(cells):
            r, c = divmod(i, cols)
            box = boxes[r][c]
            cell_size = (box[2], box[3])
            if view is None:
                ss = max(1, int(supersample))
                view = SceneView(cell_scene, size=(cell_size[0] * ss, cell_size[1] * ss), vectors=letters,
                                 term=term, background=background, vtk_text=False, mistake=mistake)
            image = render(cell_scene, cell_size, vectors=letters, term=term, supersample=supersample,
                           background=background, legend=False, view=view, mistake=mistake)
            _place(fig, image, box, size)
            if progress:
                progress(i + 1, total, label)
    except BaseException:
        import matplotlib.pyplot as plt

        plt.close(fig)
        raise
    finally:
        if view is not None:
            view.close()
    W, H = size
    if title:
        fig.text(0.5, 1 - (top_offset + 0.3 * unit) / H, title, ha="center", va="top", fontsize=fs * 1.25,
                 weight="bold")
    if col_titles:
        for c, text in enumerate(col_titles):
            x, y, w, _ = boxes[0][c]
            fig.text((x + w / 2) / W, 1 - (y - 0.4 * unit) / H, text, ha="center", va="bottom", fontsize=fs)
    if row_titles:
        for r, text in enumerate(row_titles):
            x, y, _, h = boxes[r][0]
            fig.text((x - 0.4 * unit) / W, 1 - (y + h / 2) / H, text, ha="right", va="center", fontsize=fs)
    return fig, boxes, unit


def _cell_labels(fig, boxes, cols, labels, unit, size):
    """A label inside each cell's top edge, in a rounded box, shrunk to fit the cell's width.

    ``labels`` holds ``(text, box colour)`` per cell, row-major.
    """
    from phonglab.render.plots import _fit_width

    fs = min(unit * 0.72, boxes[0][0][2] / 13 * 0.72)
    renderer = fig.canvas.get_renderer()
    W, H = size
    for i, (text, facecolor) in enumerate(labels):
        r, c = divmod(i, cols)
        x, y, w, _ = boxes[r][c]
        label = fig.text((x + w / 2) / W, 1 - (y + 0.3 * unit) / H, text, ha="center", va="top",
                         fontsize=fs, color="white", linespacing=1.5,
                         bbox=dict(boxstyle="round,pad=0.3", facecolor=facecolor, edgecolor="none"))
        # the label and its box's padding (0.3 em a side) stay inside the cell, clear of a frame
        _fit_width(label, renderer, w - 0.6 * fs / 0.72 - 0.6 * unit)


#: the label box of a correct panel, and of a panel the mistake changes
LABEL_BOX = (0, 0, 0, 0.45)
WRONG_LABEL_BOX = (0.72, 0.11, 0.11, 0.85)
RIGHT_LABEL_BOX = (0.11, 0.37, 0.13, 0.85)


def _terms_figure(scene, size, letters, supersample, background, progress, mistake=None):
    """Ambient, diffuse, specular and their sum, labelled with their formulas.

    With ``mistake``, every panel is shaded with it; the panels it changes
    carry the wrong formula in a red label, under a band naming the mistake.
    """
    spec = r"\max(0,\,r\cdot v)" if scene.model != "blinn-phong" else r"\max(0,\,n\cdot h)"
    terms = [
        ("ambient", "ambient", rf"$k_a I_a$ = {ambient_value(scene)}"),
        ("diffuse", "diffuse", r"$k_d I_d \max(0,\,n\cdot l)$"),
        ("specular", "specular", rf"$k_s I_s {spec}^{{\alpha}}$"),
        ("color", "sum", "all three + emission" if any(scene.material.emission) else "all three added"),
    ]
    wrong = wrong_term_labels(mistake, spec) if mistake is not None else {}
    rows, cols = (1, 4) if size[0] >= 2 * size[1] else (2, 2)
    cells = [(scene, term, term, mistake) for term, _, _ in terms]
    band = None
    if mistake is not None:
        title = shading.get_mistake(mistake).title
        band = _mistake_banner(mistake, scene.interpolation, size,
                               f"Common mistake: {title} — these pictures are deliberately wrong")
    fig, boxes, unit = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                                    band=band)
    labels = []
    for i, (term, name, formula) in enumerate(terms):
        if term in wrong:
            # a panel the mistake changes: red frame, the wrong formula in a red label
            _frame(fig, boxes[i // cols][i % cols], size, unit, WRONG_COLOR)
            labels.append((f"{name} (wrong)\n{wrong[term]}", WRONG_LABEL_BOX))
        else:
            labels.append((f"{name}\n{formula}", LABEL_BOX))
    _cell_labels(fig, boxes, cols, labels, unit, size)
    return fig


def wrong_term_labels(mistake: str, spec: str = r"\max(0,\,r\cdot v)") -> dict[str, str]:
    """The terms a mistake changes, each with the formula it wrongly computes.

    Parameters
    ----------
    mistake : str
        A name from :data:`phonglab.teaching.MISTAKES`.
    spec : str
        The specular base of the scene's model in LaTeX (``\\max(0, r·v)`` or
        ``\\max(0, n·h)``), without the exponent.

    Returns
    -------
    dict
        term (``"diffuse"``, ``"specular"``, ``"color"``) -> label text; the
        sum is always among them. A mistake not listed here changes the sum only.
    """
    labels = {
        "no-clamp-diffuse": {"diffuse": r"$k_d I_d\,(n\cdot l)$, negative on the dark side"},
        "ungated-specular": {"specular": rf"$k_s I_s {spec}^{{\alpha}}$, no $n\cdot l > 0$ gate"},
        "unnormalised-normals": {"diffuse": r"$k_d I_d \max(0,\,n\cdot l)$, $|n| < 1$",
                                 "specular": rf"$k_s I_s {spec}^{{\alpha}}$, $|n| < 1$"},
        "zero-shininess": {"specular": rf"$k_s I_s {spec}^0$ = $k_s I_s$ where lit"},
    }.get(mistake, {})
    return {**labels, "color": "the sum of the wrong terms" if labels else "the wrong sum"}


def ambient_value(scene) -> str:
    """The scene's constant ambient term :math:`k_a \\circ I_a` as text: ``0.02``, or ``(0.08, 0.03, 0.02)``.

    Taken from the core (one shaded point), so it is the value the ambient
    panel shows; one number when the three channels agree.
    """
    point = np.array([[0.0, 0.0, 1.0]])
    ambient = np.asarray(shading.shade(scene, point, point).ambient, dtype=float).reshape(-1, 3)[0]
    if np.allclose(ambient, ambient[0], rtol=0, atol=5e-4):
        return f"{ambient[0]:.3g}"
    return "(" + ", ".join(f"{c:.3g}" for c in ambient) + ")"


def _sweep_figure(scene, sweeps, size, letters, supersample, background, progress, mistake=None):
    """The classic material matrix: one render per combination of sweep values (with ``mistake``, if given)."""
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
            cells.append((cell, "color", ", ".join(parts), mistake))
    row_titles = [sweep_label(row_path, v) for v in row_values] if row_path is not None else None
    col_titles = [sweep_label(col_path, v) for v in col_values]
    band = None
    if mistake is not None:
        # a sweep over interpolation: the note is needed if any cell cannot show the mistake
        modes = {c[0].interpolation for c in cells}
        mode = next((m for m in sorted(modes) if not shading.mistake_shows(mistake, m)), scene.interpolation)
        band = _mistake_banner(mistake, mode, size, f"Common mistake: {shading.get_mistake(mistake).title}"
                               " — these pictures are deliberately wrong")
    fig, boxes, unit = _grid_figure(scene, cells, len(row_values), len(col_values), size, letters, supersample,
                                    background, progress, row_titles=row_titles, col_titles=col_titles,
                                    title=scene.title, band=band)
    if mistake is not None:
        for box in (b for row in boxes for b in row):
            _frame(fig, box, size, unit, WRONG_COLOR)
    return fig


def _plain(value) -> str:
    from phonglab.scene.model import show_value

    return value if isinstance(value, str) else show_value(value)


# ---------------------------------------------------------------------------
# common mistakes


def _compare_figure(scene, mistake, size, letters, supersample, background, progress):
    """The correct render and the mistaken one side by side (stacked in a tall figure), labelled."""
    m = shading.get_mistake(mistake)
    rows, cols = (1, 2) if size[0] >= size[1] else (2, 1)
    cells = [(scene, "color", "correct", None), (scene, "color", "common mistake", mistake)]
    band = _mistake_banner(mistake, scene.interpolation, size, f"Correct vs. common mistake: {m.title}",
                           heading_kind="title")
    fig, boxes, unit = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                                    band=band)
    _frame(fig, boxes[0][0], size, unit, RIGHT_COLOR)
    _frame(fig, boxes[-1][-1], size, unit, WRONG_COLOR)
    _cell_labels(fig, boxes, cols, [("correct", RIGHT_LABEL_BOX),
                                    (f"common mistake: {m.title}\ndeliberately wrong", WRONG_LABEL_BOX)],
                 unit, size)
    return fig


def _mistake_render_figure(scene, mistake, size, letters, supersample, background):
    """One render shaded with ``mistake``, under a red band that says it is wrong."""
    title = shading.get_mistake(mistake).title
    fig = _canvas(size, facecolor="white")
    try:
        band = _mistake_banner(mistake, scene.interpolation, size,
                               f"Common mistake: {title} — this picture is deliberately wrong")(fig)
        unit = _unit(size)
        pad = round(0.5 * unit)
        box = (pad, band, size[0] - 2 * pad, size[1] - band - pad)
        if box[2] < 8 or box[3] < 8:
            raise FigureError(f"size: {size[0]}x{size[1]} is too small for a render under the mistake's label")
        image = render(scene, box[2:], vectors=letters, supersample=supersample, background=background,
                       mistake=mistake)
        _place(fig, image, box, size)
        _frame(fig, box, size, unit, WRONG_COLOR)
    except BaseException:
        import matplotlib.pyplot as plt

        plt.close(fig)
        raise
    return fig


def mistake_caption(mistake: str, interpolation: str, heading: str,
                    heading_kind: str = "heading") -> list[tuple[str, str]]:
    """The lines of a mistake's band: ``(kind, text)``.

    Kinds: ``heading`` (red) or ``title`` (dark) for the first line, then
    ``wrong``, ``right`` (the two lines of code) and ``note``. The note is
    there only when the mistake cannot show in ``interpolation`` (see
    :func:`phonglab.render.shading.mistake_note`).
    """
    m = shading.get_mistake(mistake)
    lines = [(heading_kind, heading), ("wrong", f"wrong: {m.wrong}"), ("right", f"right: {m.right}")]
    note = shading.mistake_note(mistake, interpolation)
    if note:
        lines.append(("note", note))
    return lines


#: how each kind of band line is drawn: colour, matplotlib font options, size relative to the unit
_BAND_STYLES = {
    "heading": (WRONG_COLOR, {"weight": "bold"}, 1.05),
    "title": ("#212121", {"weight": "bold"}, 1.05),
    "wrong": (WRONG_COLOR, {"family": "monospace"}, 0.8),
    "right": (RIGHT_COLOR, {"family": "monospace"}, 0.8),
    "note": (NOTE_COLOR, {"style": "italic"}, 0.8),
}
#: the most of the figure's height the band may take before its text is made smaller
BAND_MAX_FRACTION = 0.35


def _mistake_banner(mistake, interpolation, size, heading, heading_kind="heading"):
    """A ``band(fig) -> pixels`` drawing the mistake's lines at the top of a figure (see :func:`_band`)."""
    lines = mistake_caption(mistake, interpolation, heading, heading_kind)
    return lambda fig: _band(fig, size, lines)


def _band(fig, size, lines) -> int:
    """Draw ``lines`` centred at the top of ``fig``, each wrapped to the width; return the band's height.

    The text is made smaller (at most four times) while the band would take
    more than :data:`BAND_MAX_FRACTION` of the figure's height.
    """
    from phonglab.render.plots import _fit_width

    W, H = size
    unit = _unit(size)
    pad = 0.4 * unit
    renderer = fig.canvas.get_renderer()
    scale = 1.0
    for attempt in range(5):
        drawn = []
        y = pad
        for kind, text in lines:
            color, style, relative = _BAND_STYLES[kind]
            fs = unit * 0.72 * relative * scale
            for piece in _wrap(fig, renderer, text, W - 2 * pad, fs, style):
                t = fig.text(0.5, 1 - y / H, piece, ha="center", va="top", fontsize=fs, color=color, **style)
                _fit_width(t, renderer, W - 2 * pad)  # a single word wider than the figure
                drawn.append(t)
                y += t.get_window_extent(renderer).height + 0.12 * unit * scale
            y += 0.12 * unit * scale
        if y <= BAND_MAX_FRACTION * H or attempt == 4:
            return int(np.ceil(y))
        for t in drawn:
            t.remove()
        scale *= 0.8
    raise AssertionError("unreachable")


def _wrap(fig, renderer, text: str, width: float, fontsize: float, style) -> list[str]:
    """Split ``text`` into lines at most ``width`` pixels wide.

    A text too wide for one line is broken after a dash ``" — "`` first,
    then at spaces; a single word wider than ``width`` keeps its own line.
    """
    probe = fig.text(0, 0, "", fontsize=fontsize, **style)

    def fits(line: str) -> bool:
        probe.set_text(line)
        return probe.get_window_extent(renderer).width <= width

    try:
        if fits(text):
            return [text]
        parts = text.split(" — ")
        parts = [p + " —" for p in parts[:-1]] + parts[-1:]
        lines = []
        for part in parts:
            current = ""
            for word in part.split():
                candidate = f"{current} {word}" if current else word
                if not current or fits(candidate):
                    current = candidate
                else:
                    lines.append(current)
                    current = word
            lines.append(current)
    finally:
        probe.remove()
    return lines
