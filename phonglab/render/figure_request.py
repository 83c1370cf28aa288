"""What a figure asks for, checked before anything is rendered, without loading VTK or PyVista.

:func:`check_request` reads the scene or lesson, applies the settings and checks
every option, size and bound of a :func:`~phonglab.render.figures.figure`; it
returns a :class:`FigureRequest` that :func:`~phonglab.render.figures.render_request`
renders. ``phonglab export`` calls it first, so a bad file, flag or value is
refused in the time it takes to start Python and read it (about a second here),
before the renderer loads (``tests/test_export_cli.py`` checks that neither
VTK, PyVista nor the render modules were imported).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from phonglab.render._files import clean_stale_temporaries
from phonglab.render.errors import FigureError
from phonglab.render.layout import grid_layout, grid_size
from phonglab.render.options import (
    AUTO,
    DEFAULT_SIZE,
    MAX_RENDER_PIXELS,
    PLOTS,
    apply_settings,
    check_output,
    check_render_work,
    normalize_sweeps,
    parse_size,
    parse_vectors,
    resolve_mistake,
    resolve_source,
)
from phonglab.scene.limits import check_picture_work

__all__ = ["FigureRequest", "check_request"]


@dataclass(frozen=True)
class FigureRequest:
    """A figure that passed every check: what :func:`~phonglab.render.figures.render_request` draws."""

    path: Path
    ext: str
    size: tuple[int, int]
    supersample: int
    scene: object
    letters: object
    plot: str | None
    terms: bool
    sweeps: list
    mistake: str | None
    compare: bool
    models: bool


def check_request(scene_or_path, out_path, *, size=DEFAULT_SIZE, settings=(), vectors=AUTO, terms: bool = False,
                  sweep=None, plot: str | None = None, supersample: int = 2, mistake: str | None = None,
                  compare: bool = False, models: bool = False) -> FigureRequest:
    """Check a figure's arguments (those of :func:`~phonglab.render.figures.figure`) before the first render.

    Raises
    ------
    FigureError
        Bad options or an unwritable output.
    phonglab.scene.SceneError
        A bad scene file, setting path or value.
    """
    path, ext = check_output(out_path)
    clean_stale_temporaries(path.resolve().parent)  # what a killed export left behind
    fitted = size is None or size == AUTO  # a sweep's grid then picks the size; anything else 1200x900
    size = DEFAULT_SIZE if fitted else parse_size(size)
    if plot is None:
        supersample = check_render_work(size, supersample)
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
    if models and (terms or sweep or plot is not None or compare or mistake is not None):
        raise FigureError("models: Phong beside Cook–Torrance cannot be combined with terms, sweeps, plots or "
                          "a mistake")
    base, lesson = resolve_source(scene_or_path)
    source = os.fspath(scene_or_path) if isinstance(scene_or_path, (str, os.PathLike)) else ""
    mistake = resolve_mistake(mistake, lesson, source)
    scene = apply_settings(base, settings)
    if plot is None:  # a per-pixel area light's rays follow the picture's pixels
        check_picture_work(scene, size[0] * size[1] * supersample**2)
    sweeps = normalize_sweeps(sweep, scene)
    if sweeps:
        # the grid must have room for its cells before n × m scenes are built
        rows, cols = (len(sweeps[0][1]), len(sweeps[1][1])) if len(sweeps) == 2 else (1, len(sweeps[0][1]))
        shape = {"title": bool(scene.title), "row_labels": len(sweeps) == 2, "col_labels": True}
        if fitted:
            # cells as large as the render's pixel limit allows at this supersampling (checked above)
            size = parse_size(grid_size(rows, cols, **shape, max_pixels=MAX_RENDER_PIXELS // supersample**2))
            supersample = check_render_work(size, supersample)
            check_picture_work(scene, size[0] * size[1] * supersample**2)
        grid_layout(size, rows, cols, **shape)
    grid = bool(terms or sweeps or compare or models)
    letters = (None if grid else "NLRVH") if vectors == AUTO else vectors
    try:
        letters = parse_vectors(letters)
    except ValueError as exc:
        raise FigureError(str(exc)) from None
    return FigureRequest(path, ext, size, supersample, scene, letters, plot, bool(terms), sweeps, mistake,
                         bool(compare), bool(models))
