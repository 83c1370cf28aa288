"""Figures for slides and handouts: single renders, per-term views, sweeps, plots.

:func:`figure` is the one entry point (``phonglab.figure``); ``phonglab
export`` is a thin layer over it. Its options are checked first
(:mod:`phonglab.render.options`), then the renders are laid out on a grid
(:mod:`phonglab.render.layout`), labelled (:mod:`phonglab.render.captions`)
and saved (:mod:`phonglab.render.saving`): every output is written to a
temporary file in the target folder and renamed into place, so a failure
never leaves a partial file behind.

A figure can show a lesson's *common mistake* (``mistake=``, a name from
:data:`phonglab.teaching.MISTAKES`): every render is then shaded with that
deliberately wrong variant, and a band at the top says so in red, with the
wrong line of code next to the right one. ``compare=True`` puts the correct
render and the mistaken one side by side.
"""

from __future__ import annotations

import sys

import numpy as np

from phonglab.render import shading
from phonglab.render.annotate import downsample
from phonglab.render.captions import (
    COMPARED_MODELS,
    LABEL_BOX,
    RIGHT_COLOR,
    RIGHT_LABEL_BOX,
    WRONG_COLOR,
    WRONG_LABEL_BOX,
    ambient_value,
    mistake_banner,
    model_label,
    plain,
    sweep_label,
    wrong_term_labels,
)
from phonglab.render.errors import FigureError
from phonglab.render.figure_request import FigureRequest, check_request
from phonglab.render.glyphs import parse_vectors
from phonglab.render.layout import (
    MIN_CONTRAST,
    canvas,
    cell_labels,
    fill,
    frame,
    grid_layout,
    grid_titles,
    place,
    subject_contrast,
    unit,
)
from phonglab.render.options import AUTO, DEFAULT_SIZE
from phonglab.render.saving import save_figure, save_image
from phonglab.render.view import BACKGROUND, SceneView


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
        Which of N, L, R, V, H to draw; with none, the light and eye markers
        are left out too.
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
        # no vectors asked for: a clean picture, without the light and eye markers over the surface
        view = SceneView(scene, size=big, vectors=vectors, term=term, background=background, vtk_text=False,
                         mistake=mistake, markers=bool(parse_vectors(vectors)))
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
    models: bool = False,
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
    plot : {"lobe", "lambert", "incidence", "furnace"}, optional
        A matplotlib plot instead of a render: the specular lobe
        :math:`\\max(0, \\cos\\phi)^\\alpha` (the GGX distribution under
        Cook–Torrance), the Lambert cosine, the plane of incidence at the
        scene's probe point, or the white furnace (the light each model sends
        back, :mod:`phonglab.core.furnace`).
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
    models : bool
        The scene under Phong and under Cook–Torrance side by side (stacked
        in a tall figure): the same mesh, lights, eye and probe, each shaded
        by the core with its own model, labelled with the model and its lobe
        parameters (α; roughness and metallic).

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
    request = check_request(scene_or_path, out_path, size=size, settings=settings, vectors=vectors, terms=terms,
                            sweep=sweep, plot=plot, supersample=supersample, mistake=mistake, compare=compare,
                            models=models)
    return render_request(request, progress=progress, background=background)


def render_request(request: FigureRequest, *, progress=None, background=BACKGROUND) -> Path:
    """Render a figure :func:`~phonglab.render.figure_request.check_request` has checked; the file written.

    ``progress`` and ``background`` are those of :func:`figure`.
    """
    path, ext, size, supersample, scene = request.path, request.ext, request.size, request.supersample, request.scene
    letters, plot, terms, sweeps, mistake = request.letters, request.plot, request.terms, request.sweeps, request.mistake
    compare, models = request.compare, request.models
    if progress is True:
        progress = stderr_progress

    if plot is not None:
        from phonglab.render import plots

        fig = plots.make_plot(plot, scene, size)
        save_figure(fig, path, ext)
    elif compare:
        fig = _compare_figure(scene, mistake, size, letters, supersample, background, progress)
        save_figure(fig, path, ext)
    elif models:
        fig = models_figure(scene, size, letters=letters, supersample=supersample, background=background,
                            progress=progress)
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


def _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                 *, row_titles=None, col_titles=None, title="", band=None, labels=None):
    """Render ``cells`` into a labelled grid figure.

    Parameters
    ----------
    cells : list of (scene, term, label, mistake)
        Row-major; ``mistake`` is None for a correct render, else the
        common mistake the cell is shaded with.
    band : callable, optional
        ``band(fig) -> pixels``: draws a band at the top of the figure and
        returns its height; the grid goes below it.
    labels : list of (text, box colour), optional
        A label per cell, drawn in a strip at the cell's top with the render
        below it (never over it). The cells then share one background that
        keeps every panel readable: ``background`` when each panel's subject
        has a contrast of at least :data:`~phonglab.render.layout.MIN_CONTRAST`
        against it, else :data:`PAPER` when that does better.

    Returns
    -------
    fig, boxes, u
        The figure, the cells' pixel boxes (x, y_from_top, w, h) by row, and the layout unit.
    """
    fig = canvas(size, facecolor="white")
    try:
        top_offset = band(fig) if band is not None else 0
        boxes, u = grid_layout(size, rows, cols, title=bool(title), row_labels=bool(row_titles),
                               col_labels=bool(col_titles), top_offset=top_offset)
        image_boxes = [b for row in boxes for b in row][:len(cells)]
        if labels is not None:
            # the labels first, then the renders in the room left below them
            placed = cell_labels(fig, boxes, cols, labels, u, size)
            strip = max(round(y1 - y) for (_, _, _, y1), (_, y, _, _) in zip(placed, image_boxes)) + round(0.2 * u)
            image_boxes = [(x, y + strip, w, h - strip) for x, y, w, h in image_boxes]
            if min(b[3] for b in image_boxes) < 8:
                raise FigureError(f"size: {size[0]}x{size[1]} is too small for the labels and the renders")
        images = _render_cells(cells, image_boxes, letters, supersample, background, progress)
        if labels is not None:
            background, images = _readable(cells, image_boxes, letters, supersample, background, images)
            for box in image_boxes:
                fill(fig, (box[0], box[1] - strip, box[2], box[3] + strip), size, background)
        for image, box in zip(images, image_boxes):
            place(fig, image, box, size)
    except BaseException:
        import matplotlib.pyplot as plt

        plt.close(fig)
        raise
    grid_titles(fig, boxes, size, u, title=title, top_offset=top_offset, row_titles=row_titles,
                col_titles=col_titles)
    return fig, boxes, u


#: the light background a panel falls back to when the dark one would hide its subject
PAPER = (0.92, 0.92, 0.92)


def _render_cells(cells, boxes, letters, supersample, background, progress):
    """One image per cell at its box's size, from one reused view."""
    view = None
    images = []
    try:
        for i, ((cell_scene, term, label, mistake), box) in enumerate(zip(cells, boxes)):
            cell_size = (box[2], box[3])
            if view is None:
                ss = max(1, int(supersample))
                view = SceneView(cell_scene, size=(cell_size[0] * ss, cell_size[1] * ss), vectors=letters,
                                 term=term, background=background, vtk_text=False, mistake=mistake,
                                 markers=bool(parse_vectors(letters)))
            images.append(render(cell_scene, cell_size, vectors=letters, term=term, supersample=supersample,
                                 background=background, legend=False, view=view, mistake=mistake))
            if progress:
                progress(i + 1, len(cells), label)
    finally:
        if view is not None:
            view.close()
    return images


def _readable(cells, boxes, letters, supersample, background, images):
    """``(background, images)``: the renders again on :data:`PAPER` when that reads better.

    The worst panel decides: its subject's contrast with the background
    (:func:`~phonglab.render.layout.subject_contrast`) must reach
    :data:`~phonglab.render.layout.MIN_CONTRAST`; if it does not and the
    light background gives the worst panel more contrast, every panel is
    rendered on the light one.
    """
    worst = min(subject_contrast(image, background) for image in images)
    if worst >= MIN_CONTRAST or tuple(background) == PAPER:
        return background, images
    paper = _render_cells(cells, boxes, letters, supersample, PAPER, None)
    if min(subject_contrast(image, PAPER) for image in paper) > worst:
        return PAPER, paper
    return background, images


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
        band = mistake_banner(mistake, scene.interpolation, size,
                              f"Common mistake: {title} — these pictures are deliberately wrong")
    labels = []
    for term, name, formula in terms:
        if term in wrong:
            # a panel the mistake changes: the wrong formula in a red label (and a red frame below)
            labels.append((f"{name} (wrong)\n{wrong[term]}", WRONG_LABEL_BOX))
        else:
            labels.append((f"{name}\n{formula}", LABEL_BOX))
    fig, boxes, u = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                                 band=band, labels=labels)
    for i, (term, _, _) in enumerate(terms):
        if term in wrong:
            frame(fig, boxes[i // cols][i % cols], size, u, WRONG_COLOR)
    return fig


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
                parts.append(f"{row_path}={plain(rv)}")
            if col_path is not None:
                cell = cell.replace(col_path, cv)
                parts.append(f"{col_path}={plain(cv)}")
            cells.append((cell, "color", ", ".join(parts), mistake))
    row_titles = [sweep_label(row_path, v) for v in row_values] if row_path is not None else None
    col_titles = [sweep_label(col_path, v) for v in col_values]
    band = None
    if mistake is not None:
        # a sweep over interpolation: the note is needed if any cell cannot show the mistake
        modes = {c[0].interpolation for c in cells}
        mode = next((m for m in sorted(modes) if not shading.mistake_shows(mistake, m)), scene.interpolation)
        band = mistake_banner(mistake, mode, size, f"Common mistake: {shading.get_mistake(mistake).title}"
                              " — these pictures are deliberately wrong")
    fig, boxes, u = _grid_figure(scene, cells, len(row_values), len(col_values), size, letters, supersample,
                                 background, progress, row_titles=row_titles, col_titles=col_titles,
                                 title=scene.title, band=band)
    if mistake is not None:
        for box in (b for row in boxes for b in row):
            frame(fig, box, size, u, WRONG_COLOR)
    return fig


# ---------------------------------------------------------------------------
# Phong beside Cook–Torrance (the models and their labels: captions.py)


def models_figure(scene, size, *, letters=None, supersample: int = 2, background=BACKGROUND, progress=None):
    """The scene under each of :data:`COMPARED_MODELS`, side by side (stacked when tall), labelled.

    Every panel is the same mesh, lights, eye and probe, shaded by the core
    with its own model; the panel of the scene's own model is framed.
    """
    rows, cols = (1, len(COMPARED_MODELS)) if size[0] >= size[1] else (len(COMPARED_MODELS), 1)
    cells = [(scene.replace("model", model), "color", label, None) for model, label in COMPARED_MODELS]
    labels = [(model_label(scene, model), RIGHT_LABEL_BOX) for model, _ in COMPARED_MODELS]
    fig, boxes, u = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                                 title=scene.title or "Phong beside Cook–Torrance", labels=labels)
    own = [m for m, _ in COMPARED_MODELS].index(scene.model) if scene.model in dict(COMPARED_MODELS) else None
    if own is not None:
        flat = [b for row in boxes for b in row]
        frame(fig, flat[own], size, u, RIGHT_COLOR)
    return fig


# ---------------------------------------------------------------------------
# common mistakes


def _compare_figure(scene, mistake, size, letters, supersample, background, progress):
    """The correct render and the mistaken one side by side (stacked in a tall figure), labelled."""
    m = shading.get_mistake(mistake)
    rows, cols = (1, 2) if size[0] >= size[1] else (2, 1)
    cells = [(scene, "color", "correct", None), (scene, "color", "common mistake", mistake)]
    band = mistake_banner(mistake, scene.interpolation, size, f"Correct vs. common mistake: {m.title}",
                          heading_kind="title")
    fig, boxes, u = _grid_figure(scene, cells, rows, cols, size, letters, supersample, background, progress,
                                 band=band)
    frame(fig, boxes[0][0], size, u, RIGHT_COLOR)
    frame(fig, boxes[-1][-1], size, u, WRONG_COLOR)
    cell_labels(fig, boxes, cols, [("correct", RIGHT_LABEL_BOX),
                                   (f"common mistake: {m.title}\ndeliberately wrong", WRONG_LABEL_BOX)],
                u, size)
    return fig


def _mistake_render_figure(scene, mistake, size, letters, supersample, background):
    """One render shaded with ``mistake``, under a red band that says it is wrong."""
    title = shading.get_mistake(mistake).title
    fig = canvas(size, facecolor="white")
    try:
        band = mistake_banner(mistake, scene.interpolation, size,
                              f"Common mistake: {title} — this picture is deliberately wrong")(fig)
        u = unit(size)
        pad = round(0.5 * u)
        box = (pad, band, size[0] - 2 * pad, size[1] - band - pad)
        if box[2] < 8 or box[3] < 8:
            raise FigureError(f"size: {size[0]}x{size[1]} is too small for a render under the mistake's label")
        image = render(scene, box[2:], vectors=letters, supersample=supersample, background=background,
                       mistake=mistake)
        place(fig, image, box, size)
        frame(fig, box, size, u, WRONG_COLOR)
    except BaseException:
        import matplotlib.pyplot as plt

        plt.close(fig)
        raise
    return fig
