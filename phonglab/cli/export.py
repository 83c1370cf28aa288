"""``phonglab export``: render a scene or lesson to a PNG, SVG or PDF figure.

Examples::

    phonglab export assets/scenes/sphere.toml -o sphere.png
    phonglab export lessons/03-specular.md -o matrix.png \\
        --sweep material.ks=0.1,0.5,0.9 --sweep material.shininess=4,32,256
    phonglab export assets/scenes/sphere.toml -o terms.png --terms --set interpolation=pixel
    phonglab export assets/scenes/sphere.toml -o lobe.pdf --plot lobe
    phonglab export lessons/03-diffuse.md -o mistake.png --mistake lesson --compare
    phonglab export assets/scenes/sphere.toml -o models.png --models --set material.roughness=0.3
    phonglab export assets/scenes/sphere.toml -o wrong.png --mistake zero-shininess --terms

Exit status: 0 written, 2 bad input (a one-line error naming the problem;
nothing is written).
"""

from __future__ import annotations

import argparse

from phonglab.cli import UsageError
from phonglab.render.options import AUTO, DEFAULT_SIZE, PLOTS, parse_size


def add_parser(subparsers) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "export",
        help="render a scene or lesson to PNG/SVG/PDF",
        description="Render a scene (.toml) or lesson (.md) to a figure. The output's extension "
        "picks the format: .png, .svg or .pdf.",
    )
    parser.add_argument("scene", metavar="SCENE_OR_LESSON", help="a scene file (.toml) or a lesson (.md)")
    parser.add_argument("-o", "--output", required=True, metavar="FILE", help="the figure to write (.png, .svg, .pdf)")
    parser.add_argument(
        "--set", dest="settings", action="append", default=[], metavar="PATH=VALUE",
        help="change a scene field first, e.g. --set material.shininess=100 (repeatable; values as in TOML)",
    )
    parser.add_argument("--size", default=AUTO, metavar="WxH",
                        help="figure size in pixels (default {}x{}; a sweep's grid: 4:3 cells, "
                             "1800 pixels of them across at most)".format(*DEFAULT_SIZE))
    parser.add_argument(
        "--vectors", default=None, metavar="N,L,R,V,H",
        help="which vectors to draw at the probe, or 'none' (default: all on a single render, none in grids)",
    )
    parser.add_argument("--terms", action="store_true", help="ambient, diffuse, specular and their sum side by side")
    parser.add_argument(
        "--sweep", action="append", default=[], metavar="PATH=V1,V2,...",
        help="a grid with one render per value; give twice for rows x columns",
    )
    parser.add_argument("--plot", choices=PLOTS, help="a plot instead of a render: the specular lobe, "
                        "Lambert's cosine, the plane of incidence at the probe, or the white furnace (the "
                        "light each model sends back)")
    parser.add_argument("--supersample", type=int, default=2, metavar="N",
                        help="antialiasing: render N times larger and average down (default 2)")
    parser.add_argument(
        "--mistake", default=None, metavar="NAME",
        help="show a common mistake: shade with a deliberately wrong variant (" + _mistake_names()
        + "), or 'lesson' for the lesson's own; the figure is labelled as wrong",
    )
    parser.add_argument("--compare", action="store_true",
                        help="with --mistake: the correct picture and the mistaken one side by side")
    parser.add_argument("--models", action="store_true",
                        help="the scene under Phong and under Cook–Torrance side by side (same mesh, lights and eye)")
    return parser


def _mistake_names() -> str:
    """The mistake names for the help text (the teaching package is NumPy-only)."""
    from phonglab.teaching import MISTAKES

    return ", ".join(MISTAKES)


def run(args) -> int:
    from phonglab.render import FigureError
    from phonglab.render.figure_request import check_request
    from phonglab.scene import SceneError

    try:
        size = AUTO if args.size == AUTO else parse_size(args.size)
        if not 1 <= args.supersample <= 4:
            raise FigureError(f"supersample: must be from 1 to 4, got {args.supersample}")
        if args.compare and args.mistake is None:
            raise FigureError("--compare: needs --mistake NAME (or --mistake lesson) to compare with")
        # every file, flag and value is checked before VTK loads: a refusal costs the reading, not the renderer
        request = check_request(args.scene, args.output, size=size, settings=args.settings,
                                vectors=AUTO if args.vectors is None else args.vectors, terms=args.terms,
                                sweep=args.sweep or None, plot=args.plot, supersample=args.supersample,
                                mistake=args.mistake, compare=args.compare, models=args.models)
        from phonglab.render.figures import render_request, stderr_progress

        grid = args.sweep or args.terms or args.compare or args.models
        path = render_request(request, progress=stderr_progress if grid else None)
    except (SceneError, FigureError) as exc:
        raise UsageError(_one_line(exc)) from None
    print(path)
    return 0


def _one_line(exc: Exception) -> str:
    """An error as one line (a file with several problems reports the first and their count)."""
    lines = [line for line in str(exc).splitlines() if line.strip()]
    if len(lines) <= 1:
        return lines[0] if lines else type(exc).__name__
    return f"{lines[0]} (and {len(lines) - 1} more problem{'s' if len(lines) > 2 else ''}; run phonglab check)"
