"""Matplotlib plots of the model: the specular lobe, Lambert's cosine, the plane of incidence.

Each ``*_plot`` function returns a matplotlib ``Figure`` (Agg backend) of the
requested pixel size; :func:`phonglab.render.figure` saves it as PNG,
SVG or PDF. Directions point *away from the surface point*.
"""

from __future__ import annotations

import math
from collections import ChainMap

import matplotlib

matplotlib.use("Agg", force=False)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Arc  # noqa: E402

from phonglab import core  # noqa: E402
from phonglab.core import furnace, microfacet  # noqa: E402
from phonglab.render.errors import FigureError  # noqa: E402
from phonglab.render.layout import canvas  # noqa: E402
from phonglab.render.objects import scene_mesh  # noqa: E402
from phonglab.render.shadows import at_probe  # noqa: E402
from phonglab.render.probe import directed_light_index, locate_probe, probe_vectors  # noqa: E402
from phonglab.render.text import fit_width, keep_inside  # noqa: E402
from phonglab.scene import trace  # noqa: E402

#: shininess values drawn by the lobe plot (the scene's own is added)
LOBE_EXPONENTS = (1, 4, 16, 64, 256)
#: roughness values drawn by the Cook–Torrance lobe plot (the scene's own is added)
LOBE_ROUGHNESS = (0.1, 0.25, 0.5, 0.75, 1.0)
#: vector colours on white paper (darker than the on-screen arrows)
PAPER_COLORS = {
    "N": "#0072b2",
    "L": "#c99a00",
    "R": "#d5401a",
    "V": "#009e73",
    "H": "#b0609a",
}


def make_plot(kind: str, scene, size):
    """The plot named ``kind`` ("lobe", "lambert" or "incidence") for ``scene``."""
    makers = {"lobe": lobe_plot, "lambert": lambert_plot, "incidence": incidence_plot, "furnace": furnace_plot}
    return makers[kind](scene, size)


def _font(size) -> float:
    """A base font size in points that suits a figure of ``size`` pixels."""
    return max(7.0, min(size) / 52)


def half_width(shininess: float) -> float:
    """The angle φ (degrees) at which :math:`\\cos^\\alpha\\phi` falls to one half."""
    return math.degrees(math.acos(0.5 ** (1.0 / shininess)))


def lobe_plot(scene, size):
    """The specular lobe :math:`\\max(0, \\cos\\phi)^\\alpha` for several α: polar and cartesian.

    φ is the angle between R and V (Phong) or N and H (Blinn-Phong); the
    scene's own shininess is drawn thick. Under Cook–Torrance the lobe is
    the GGX distribution instead (:func:`ggx_lobe_plot`).
    """
    if scene.model == "cook-torrance":
        return ggx_lobe_plot(scene, size)
    alpha_scene = float(scene.material.shininess)
    exponents = sorted(set(LOBE_EXPONENTS) | {alpha_scene})

    def lobe(alpha, phi):
        cos = np.cos(phi)
        return core.specular_lobe(np.ones_like(cos), cos, alpha)  # a lit point: the n·l gate open

    def label(alpha):
        return rf"$\alpha$ = {alpha:g}" + ("  (this scene)" if alpha == alpha_scene else "") + \
            f"   half at {half_width(alpha):.1f}°"

    around = "N" if scene.model == "blinn-phong" else "R"
    angle = r"$\angle(N, H)$" if scene.model == "blinn-phong" else r"$\angle(R, V)$"
    return _lobe_figure(size, exponents, alpha_scene, LOBE_EXPONENTS, lobe, label,
                        xlabel=f"φ = {angle} in degrees", ylabel=r"$\max(0, \cos\varphi)^{\alpha}$",
                        subtitle="larger α: a smaller, sharper highlight",
                        title=r"Specular lobe  $\max(0,\cos\varphi)^{\alpha}$", polar=f"lobe around {around} (polar)")


def ggx_half_width(roughness: float) -> float:
    """The angle φ (degrees) at which the GGX distribution falls to half its peak."""
    alpha2 = microfacet.ggx_alpha(roughness) ** 2
    # D(φ)/D(0) = α⁴ / (cos²φ (α² − 1) + 1)² = 1/2  ⇔  cos²φ = (1 − √2 α²) / (1 − α²)
    cos2 = (1 - math.sqrt(2) * alpha2) / (1 - alpha2) if alpha2 < 1 else 0.0
    return math.degrees(math.acos(math.sqrt(max(cos2, 0.0)))) if alpha2 < 1 / math.sqrt(2) else 90.0


def ggx_lobe_plot(scene, size):
    """Cook–Torrance's lobe: the GGX distribution :math:`D(\\phi)/D(0)` for several roughnesses.

    φ is the angle between N and H; the scene's own roughness is drawn thick.
    """
    rough_scene = float(scene.material.roughness)
    values = sorted(set(LOBE_ROUGHNESS) | {rough_scene})

    def lobe(roughness, phi):
        alpha = microfacet.ggx_alpha(roughness)
        # D(φ) scaled so that its peak is 1: D(0) = 1/(π α²)
        return microfacet.ggx_distribution(1 - np.cos(phi), alpha) * (math.pi * alpha * alpha)

    def label(roughness):
        return f"roughness {roughness:g}" + ("  (this scene)" if roughness == rough_scene else "") + \
            f"   half at {ggx_half_width(roughness):.1f}°"

    return _lobe_figure(size, values, rough_scene, LOBE_ROUGHNESS, lobe, label,
                        xlabel=r"φ = $\angle(N, H)$ in degrees", ylabel=r"$D(\varphi)\,/\,D(0)$",
                        subtitle="rougher: a wider lobe (each scaled to its peak)",
                        title=r"GGX lobe  $D = \alpha^2 / \pi((n\cdot h)^2(\alpha^2-1)+1)^2$",
                        polar="lobe around N (polar)")


def _lobe_figure(size, values, own, usual, lobe, label, *, xlabel, ylabel, subtitle, title, polar):
    """A lobe for each of ``values`` (``lobe(value, φ)``, peak 1), cartesian and polar; ``own`` drawn thick.

    Values in ``usual`` are solid, the scene's own thick and black, others dashed.
    """
    fs = _font(size)
    fig = canvas(size)
    polar_cell, flat_cell = _two_cells(fig, size, polar_first=True)
    flat = fig.add_subplot(flat_cell)
    curves = []
    phi = np.linspace(-math.pi / 2, math.pi / 2, 721)
    colors = plt.cm.viridis(np.linspace(0.05, 0.85, len(values)))
    for value, color in zip(values, colors):
        y = lobe(value, phi)
        mine = value == own
        style = dict(color="black" if mine else color, lw=3.2 if mine else 1.6,
                     ls="-" if mine or value in usual else "--")
        curves.append((y, style))
        flat.plot(np.degrees(phi), y, label=label(value), **style)
    flat.set_xlim(-90, 90)
    flat.set_ylim(0, 1.05)
    flat.set_xticks(range(-90, 91, 30))
    flat.set_xlabel(xlabel, fontsize=fs)
    flat.set_ylabel(ylabel, fontsize=fs)
    flat.tick_params(labelsize=fs * 0.85)
    flat.grid(alpha=0.3)
    flat.set_title(subtitle, fontsize=fs * 1.1)
    fit_width(flat.title, fig.canvas.get_renderer(), _cell_width(fig, flat_cell))
    suptitle = fig.suptitle(title, fontsize=fs * 1.35, weight="bold", va="top", y=1 - _pad(size) / size[1])
    legend = _bottom_legend(fig, *flat.get_legend_handles_labels(), fontsize=fs * 0.85)
    _tight(fig, suptitle, legend)
    keep_inside(flat.title, fig, _pad(size))
    # polar: the lobe's axis straight up, the surface along the horizontal, in the free left cell
    axes = _half_polar(fig, polar_cell, flat, fs, polar)
    for y, style in curves:
        axes.plot(phi, y, **style)
    axes.set_rticks([0.25, 0.5, 0.75, 1.0])
    return fig


#: the furnace plot's curves: (model, lobe width, label); roughness for Cook–Torrance, α for Phong
FURNACE_CURVES = (
    ("phong", 0.5, "Phong, α = 0.5"),
    ("phong", 1.0, "Phong, α = 1"),
    ("phong", 10.0, "Phong, α = 10"),
    ("phong-normalised", 10.0, "normalised Phong, α = 10"),
    ("cook-torrance", 0.1, "Cook–Torrance, roughness 0.1"),
    ("cook-torrance", 0.5, "Cook–Torrance, roughness 0.5"),
    ("cook-torrance", 1.0, "Cook–Torrance, roughness 1"),
)
#: view angles of the furnace plot, degrees from the normal
FURNACE_ANGLES = tuple(range(0, 90, 5)) + (88.0,)


def furnace_plot(scene, size):
    """The white furnace: the light each model sends back, as a fraction of the light arriving.

    For each view angle, :func:`phonglab.core.furnace.directional_albedo` of a
    white surface: plain Phong (``k_s = 1``) at several α, energy-normalised
    Phong and a white Cook–Torrance metal at several roughnesses. Above the
    line at 1 a model makes light; below it, it loses some. The scene's own
    model and lobe width are drawn thick.
    """
    mine = ("cook-torrance", float(scene.material.roughness)) if scene.model == "cook-torrance" else \
        ("phong", float(scene.material.shininess))
    curves = list(FURNACE_CURVES)
    if all((m, w) != mine for m, w, _ in curves):
        width = mine[1]
        curves.append((mine[0], width, f"Cook–Torrance, roughness {width:g}" if mine[0] == "cook-torrance"
                       else f"Phong, α = {width:g}"))
    fs = _font(size)
    fig = canvas(size)
    ax = fig.add_subplot(1, 1, 1)
    colors = {"phong": "#d5401a", "phong-normalised": "#0072b2", "cook-torrance": "#009e73"}
    dashes = ["-", "--", ":", "-."]
    seen = {}
    for model, width, label in curves:
        kw = {"roughness": width} if model == "cook-torrance" else {"shininess": width}
        albedo = [furnace.directional_albedo(model, a, n_xi=128, n_phi=128, **kw) for a in FURNACE_ANGLES]
        thick = (model, width) == mine
        style = seen.setdefault((model, width), dashes[sum(m == model for m, _ in seen) % len(dashes)])
        ax.plot(FURNACE_ANGLES, albedo, color="black" if thick else colors[model], lw=3.2 if thick else 1.8,
                ls=style, label=label + ("  (this scene)" if thick else ""))
    ax.axhline(1.0, color="#555555", lw=1.0)
    ax.text(1, 1.0, "  all the light that arrives", va="bottom", ha="left", fontsize=fs * 0.85, color="#555555")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, max(1.7, ax.get_ylim()[1]))
    ax.set_xticks(range(0, 91, 15))
    ax.set_xlabel("view angle from the normal, degrees", fontsize=fs)
    ax.set_ylabel("light sent back / light arriving", fontsize=fs)
    ax.tick_params(labelsize=fs * 0.85)
    ax.grid(alpha=0.3)
    title = fig.suptitle("White furnace: which models make or lose light", fontsize=fs * 1.35, weight="bold",
                         va="top", y=1 - _pad(size) / size[1])
    legend = _bottom_legend(fig, *ax.get_legend_handles_labels(), fontsize=fs * 0.85)
    _tight(fig, title, legend)
    return fig


def lambert_plot(scene, size):
    """Lambert's cosine law: :math:`\\max(0, \\cos\\theta)` against the angle of incidence θ.

    The scene's probe angle (between N and L) is marked when the scene has a
    directed light.
    """
    fs = _font(size)
    fig = canvas(size)
    flat_cell, polar_cell = _two_cells(fig, size, polar_first=False)
    flat = fig.add_subplot(flat_cell)
    theta = np.linspace(0, 180, 721)
    cos = np.cos(np.radians(theta))
    flat.plot(theta, cos, color="0.6", ls="--", lw=1.4, label=r"$\cos\theta$")
    flat.plot(theta, core.lambert(cos), color=PAPER_COLORS["L"], lw=3, label=r"$\max(0, \cos\theta)$")
    flat.axvspan(90, 180, color="0.9")
    flat.text(135, 0.55, "light behind\nthe surface:\nno diffuse light", ha="center", va="center", fontsize=fs * 0.85)
    flat.axhline(0, color="black", lw=0.8)
    probe = _probe_vectors(scene)
    if probe is not None:
        _, _, vec, used = probe
        angle = math.degrees(math.acos(max(-1.0, min(1.0, vec.nl))))
        weight = float(used["diffuse weight"])  # max(0, n·l), as the model computed it
        flat.axvline(angle, color=PAPER_COLORS["N"], lw=1.2)
        flat.plot([angle], [weight], "o", color=PAPER_COLORS["N"])
        # the numbers on a white patch, on the side of the line with more room
        left = angle > 120
        flat.annotate(
            f"probe: θ = {angle:.1f}°\nn·l = {vec.nl:.3f}",
            (angle, weight),
            xytext=(-10 if left else 10, -40),
            textcoords="offset points",
            ha="right" if left else "left",
            va="top",
            fontsize=fs * 0.85,
            color=PAPER_COLORS["N"],
            bbox=dict(boxstyle="round,pad=0.25", facecolor="white", edgecolor="none", alpha=0.85),
        )
    flat.set_xlim(0, 180)
    flat.set_ylim(-1.05, 1.1)
    flat.set_xticks(range(0, 181, 30))
    flat.set_xlabel(r"angle of incidence $\theta = \angle(N, L)$ in degrees", fontsize=fs)
    flat.set_ylabel("diffuse factor", fontsize=fs)
    flat.tick_params(labelsize=fs * 0.85)
    flat.grid(alpha=0.3)
    flat.legend(fontsize=fs * 0.85, loc="lower left")
    flat.set_title("the same light spread over a larger area", fontsize=fs * 1.05)
    fit_width(flat.title, fig.canvas.get_renderer(), _cell_width(fig, flat_cell))
    title = fig.suptitle(r"Lambert's cosine law  $I_d = k_d\, I_l \max(0, n\cdot l)$", fontsize=fs * 1.35,
                         weight="bold", va="top", y=1 - _pad(size) / size[1])
    _tight(fig, title)
    keep_inside(flat.title, fig, _pad(size))
    # polar: the light's direction against the normal, radius = brightness
    polar = _half_polar(fig, polar_cell, flat, fs, "brightness for light arriving\n" r"at $\theta$ from N (polar)")
    phi = np.linspace(-math.pi / 2, math.pi / 2, 361)
    polar.plot(phi, np.cos(phi), color=PAPER_COLORS["L"], lw=3)
    polar.fill(phi, np.cos(phi), color=PAPER_COLORS["L"], alpha=0.15)
    polar.set_rticks([0.5, 1.0])
    return fig


def _two_cells(fig, size, *, polar_first: bool):
    """Two grid cells for a polar half disc and a cartesian plot: side by side, or stacked in a tall figure.

    Side by side, the polar cell is a little wider (a half disc is twice as
    wide as tall); stacked, the polar cell is on top and lower.
    """
    if size[0] >= 1.2 * size[1]:
        ratios = (1.15, 1) if polar_first else (1, 1.15)
        grid = fig.add_gridspec(1, 2, width_ratios=ratios)
        return grid[0, 0], grid[0, 1]
    grid = fig.add_gridspec(2, 1, height_ratios=(0.75, 1))
    return (grid[0, 0], grid[1, 0]) if polar_first else (grid[1, 0], grid[0, 0])


def _cell_width(fig, cell) -> float:
    """About the width in pixels a grid cell's column gets in a tight layout: its share of the figure."""
    width = fig.get_size_inches()[0] * fig.dpi
    grid = cell.get_gridspec()
    ratios = grid.get_width_ratios() or [1.0] * grid.ncols
    return 0.95 * width * ratios[cell.colspan.start] / sum(ratios)


def _pad(size) -> float:
    """The free border of a plot, in pixels."""
    return 0.025 * min(size)


def _points_to_px(points: float) -> float:
    return points * 100.0 / 72.0


def _bottom_legend(fig, handles, labels, fontsize):
    """A frameless legend at the bottom centre, in as many columns (3, 2 or 1) as fit the width."""
    width = fig.get_size_inches()[0] * fig.dpi
    renderer = fig.canvas.get_renderer()
    legend = None
    for columns in (3, 2, 1):
        if legend is not None:
            legend.remove()
        legend = fig.legend(handles, labels, loc="lower center", ncol=columns, fontsize=fontsize, frameon=False,
                            bbox_to_anchor=(0.5, 0.0))
        if legend.get_window_extent(renderer).width <= width * 0.96:
            break
    return legend


def _tight(fig, title, legend=None) -> None:
    """Tight layout of the axes between the title (shrunk to the width if needed) and a bottom legend."""
    width, height = fig.get_size_inches() * fig.dpi
    renderer = fig.canvas.get_renderer()
    fit_width(title, renderer, width * 0.96)
    top = title.get_window_extent(renderer).y0 - 0.01 * height
    bottom = legend.get_window_extent(renderer).y1 if legend is not None else 0.0
    fig.tight_layout(rect=(0, bottom / height, 1, top / height), w_pad=3.0)


def _half_polar(fig, cell, neighbour, fs, title: str):
    """A polar axes for θ in [-90°, 90°] (θ = 0 straight up), as large as fits in a grid cell.

    The half disc is centred in ``cell`` horizontally. Beside the
    ``neighbour`` axes it is centred in the neighbour's height and its
    ``title`` is level with the neighbour's; above the neighbour it fills
    the cell down to the neighbour's title. A polar axes is square with the half disc in its
    middle, so the square overhangs the half disc by a quarter above and
    below, where nothing is drawn.
    """
    width, height = fig.get_size_inches() * fig.dpi
    renderer = fig.canvas.get_renderer()
    box = cell.get_position(fig)
    x0, x1 = box.x0 * width, box.x1 * width
    beside = box.y0 < neighbour.get_position().y1 and neighbour.get_position().y0 < box.y1
    if beside:
        # level with the neighbour: its height, and the title on the line of its title
        span = neighbour.get_window_extent(renderer)
        bottom, title_y = span.y0, neighbour.title.get_window_extent(renderer).y0
    else:
        # above the neighbour: the cell's height, down to the top of the neighbour's title
        bottom = neighbour.title.get_window_extent(renderer).y1 + _points_to_px(fs)
        title_y = box.y1 * height - _points_to_px(fs * 1.6)
    label = fig.text((x0 + x1) / 2 / width, title_y / height, title, ha="center", va="bottom",
                     fontsize=neighbour.title.get_fontsize(), linespacing=1.3)
    fit_width(label, renderer, x1 - x0)
    top = label.get_window_extent(renderer).y0 - _points_to_px(fs * 0.5)
    if beside:
        top = min(top, span.y1)
    # room for the angle labels around the rim and the radius labels under the base
    side = _points_to_px(fs * 0.8 * 3.2)
    above, below = _points_to_px(fs * 0.8 * 1.8), _points_to_px(fs * 0.8 * 2.0)
    room_h = top - bottom - above - below
    radius = max(10.0, min((x1 - x0) / 2 - side, room_h))
    base = bottom + below + (room_h - radius) / 2
    centre_x = (x0 + x1) / 2
    polar = fig.add_axes(((centre_x - radius) / width, (base - radius / 2) / height, 2 * radius / width,
                          2 * radius / height), projection="polar")
    polar.set_theta_zero_location("N")
    polar.set_theta_direction(-1)
    polar.set_thetamin(-90)
    polar.set_thetamax(90)
    polar.tick_params(labelsize=fs * 0.8)
    # the angle labels stand off the rim, so "−90°" and "90°" keep clear of the radius labels under the base
    polar.tick_params(axis="x", pad=fs * 1.2)  # points: more than a label height
    return polar


def _probe_vectors(scene):
    """(point, normal, ProbeVectors, used) at the scene's probe for its first directed light, or None.

    ``used`` maps a name to what the model used there (:func:`phonglab.scene.trace`):
    the light's values (its weights, ``n·l``), then the point's (``n·v``).
    """
    index = directed_light_index(scene.lights)
    if index is None:
        return None
    point, normal = locate_probe(scene_mesh(scene), scene)
    vec, _ = probe_vectors(scene, point, normal, index)
    obj, seen, _ = at_probe(scene, point)  # the object the probe is on, and the lights that reach it
    _, record = trace(scene, np.asarray([point], float), np.asarray([normal], float), obj=obj, visibility=seen)
    record = record.at(0)
    return point, normal, vec, ChainMap(dict(record.light(index).values), dict(record.values))


def _free_spot(spot, placed, distance: float) -> np.ndarray:
    """``spot``, or the nearest point sideways of it that is ``distance`` clear of ``placed``."""
    spot = np.asarray(spot, dtype=float)
    if all(np.linalg.norm(spot - q) >= distance for q in placed):
        return spot
    radius = np.linalg.norm(spot)
    angle = math.atan2(spot[1], spot[0])
    for step in range(1, 40):
        for sign in (-1, 1):
            a = angle + sign * step * 0.03
            trial = radius * np.array([math.cos(a), math.sin(a)])
            if all(np.linalg.norm(trial - q) >= distance for q in placed):
                return trial
    return spot


def _angle(a, b) -> float:
    return math.degrees(math.acos(max(-1.0, min(1.0, float(np.dot(a, b))))))


def incidence_plot(scene, size):
    """The plane of incidence at the probe: N, L, R, V, H and the angles between them.

    The plane holds N and L (so R too). V and H usually leave it: they are
    drawn as their projections, dashed, and the text gives their true angles.

    Raises
    ------
    phonglab.render.FigureError
        If the scene has no point, directional or spot light.
    """
    probe = _probe_vectors(scene)
    if probe is None:
        raise FigureError("plot: incidence needs a point, directional or spot light in the scene")
    point, _, vec, used = probe
    n, l, r, v, h = vec.n, vec.l, vec.r, vec.v, vec.h
    # in-plane basis: y along N, x along L's tangent part (L drawn on the left)
    tangent = l - vec.nl * n
    if np.linalg.norm(tangent) < 1e-9:
        tangent = v - float(used["n·v"]) * n
    if np.linalg.norm(tangent) < 1e-9:
        tangent = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 1.0, 0.0])
    x_axis = -tangent / np.linalg.norm(tangent)
    z_axis = np.cross(x_axis, n)

    def flat(u):
        return np.array([u @ x_axis, u @ n])

    def out_of_plane(u) -> float:
        return math.degrees(math.asin(max(-1.0, min(1.0, float(u @ z_axis)))))

    # everything is placed in data units first (y along N, x along the surface); the
    # figure's layout then scales the diagram to the room the text leaves
    vectors = {"N": n, "L": l, "R": r, "V": v, "H": h}
    placed = []
    letters = []
    for name, u in vectors.items():
        p = flat(u)
        projected = abs(out_of_plane(u)) > 1.0
        spot = _free_spot(p * 1.1 + np.array([0.0, 0.03]), placed, 0.12)
        placed.append(spot)
        letters.append((name, p, projected, spot))
    # angle arcs, drawn between the in-plane directions, labelled with the true angles
    arcs = []
    for a, b, radius, symbol in [("L", "N", 0.32, r"$\theta_i$"), ("N", "R", 0.38, r"$\theta_r$"),
                                 ("R", "V", 0.55, r"$\varphi$"), ("N", "H", 0.24, r"$\psi$")]:
        pa, pb = flat(vectors[a]), flat(vectors[b])
        ta, tb = math.degrees(math.atan2(pa[1], pa[0])), math.degrees(math.atan2(pb[1], pb[0]))
        lo, hi = sorted((ta, tb))
        if hi - lo > 180:
            lo, hi = hi, lo + 360
        mid = math.radians((lo + hi) / 2)
        direction = np.array([math.cos(mid), math.sin(mid)])
        spot = direction * (radius + 0.09)
        # move outwards along the bisector until clear of the other labels
        while any(np.linalg.norm(spot - q) < 0.1 for q in placed) and np.linalg.norm(spot) < 1.2:
            spot = spot + 0.06 * direction
        placed.append(spot)
        arcs.append((radius, lo, hi, spot, symbol))
    # the drawing's extent: the arrows, their letters and the surface with its hatching
    points = np.array([p for _, p, _, _ in letters] + placed + [(0.0, 0.0)])
    margin = 0.16
    x_lo, x_hi = min(-1.0, points[:, 0].min() - margin), max(1.0, points[:, 0].max() + margin)
    y_lo, y_hi = min(-0.12 - 0.04, points[:, 1].min() - margin), points[:, 1].max() + margin

    # the numbers, in blocks: angles, then dot products and the specular factor
    alpha = float(used["α"])  # the probe's object's shininess, as the model used it
    cos_symbol = r"n\cdot h" if scene.model == "blinn-phong" else r"r\cdot v"
    factor = float(used["specular weight"])  # as the model computed it, gated by n·l > 0
    blocks = [
        "\n".join([
            rf"$\theta_i = \angle(N, L)$ = {_angle(n, l):.1f}°",
            rf"$\theta_r = \angle(N, R)$ = {_angle(n, r):.1f}°",
            rf"$\varphi = \angle(R, V)$ = {_angle(r, v):.1f}°",
            rf"$\psi = \angle(N, H)$ = {_angle(n, h):.1f}°",
        ]),
        "\n".join([
            rf"$n\cdot l$ = {vec.nl:.3f}",
            rf"$r\cdot v$ = {vec.rv:.3f}",
            rf"$n\cdot h$ = {vec.nh:.3f}",
            rf"specular factor $\max(0, {cos_symbol})^{{{alpha:g}}}$ = {factor:.3f}",
        ]),
    ]
    if "lit" in used and not bool(used["lit"]):  # the shadow ray found something between: S = 0
        blocks[1] += ("\n" + rf"in shadow: $S$ = 0, so this light adds" + "\nno diffuse or specular light here")
    if abs(out_of_plane(v)) > 1.0:
        blocks.append(f"V leaves the plane by {abs(out_of_plane(v)):.1f}°,\nH by {abs(out_of_plane(h)):.1f}°:\n"
                      "V′, H′ are their projections")

    fs = _font(size)
    fig = canvas(size)
    px, py, pz = point
    title = fig.suptitle(f"Plane of incidence at the probe ({px:.2f}, {py:.2f}, {pz:.2f})", fontsize=fs * 1.35,
                         weight="bold", va="top", y=1 - 0.02 * min(size) / size[1])
    texts = [fig.text(0, 0, block, fontsize=fs * 0.95, ha="left", va="top", linespacing=1.6,
                      bbox=dict(boxstyle="round,pad=0.6", facecolor="0.965", edgecolor="0.8"))
             for block in blocks]
    rect = _diagram_beside_text(fig, title, texts, (x_hi - x_lo, y_hi - y_lo))
    ax = fig.add_axes(rect)
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(y_lo, y_hi)
    ax.set_aspect("equal")
    ax.axis("off")
    # the surface, hatched below
    ax.plot([x_lo, x_hi], [0, 0], color="black", lw=2)
    ax.fill_between([x_lo, x_hi], [-0.12, -0.12], [0, 0], hatch="///", facecolor="white", edgecolor="0.6", lw=0)
    # arrows as thick as on a full-size figure, thinner when the diagram is drawn small
    thin = min(1.0, rect[2] * size[0] / (x_hi - x_lo) / 300.0)
    for name, p, projected, spot in letters:
        ax.annotate(
            "", xy=tuple(p), xytext=(0, 0),
            arrowprops=dict(arrowstyle="-|>", lw=2.6 * thin, color=PAPER_COLORS[name], mutation_scale=22 * thin,
                            linestyle="--" if projected else "-", shrinkA=0, shrinkB=0),
        )
        ax.text(*spot, name + ("′" if projected else ""), color=PAPER_COLORS[name], fontsize=fs * 1.4,
                weight="bold", ha="center", va="center")
    for radius, lo, hi, spot, symbol in arcs:
        ax.add_patch(Arc((0, 0), 2 * radius, 2 * radius, theta1=lo, theta2=hi, color="0.25", lw=1.2))
        ax.text(*spot, symbol, fontsize=fs * 1.1, ha="center", va="center", color="0.15")
    return fig


def _diagram_beside_text(fig, title, texts, data_size) -> tuple[float, float, float, float]:
    """Place the text boxes under ``title`` and return the axes rectangle (figure fractions) for a diagram.

    Three arrangements are tried: the diagram left of the boxes (stacked in
    a column), and the diagram above them, the boxes side by side in a row
    or stacked in a column; the one that draws the diagram largest wins.
    The text shrinks while none of them leaves the diagram half the size
    it would have alone. The rectangle has the diagram's aspect (``data_size`` = width,
    height in data units), so an equal-aspect axes fills it exactly.
    """
    width, height = fig.get_size_inches() * fig.dpi
    pad = 0.03 * min(width, height)
    gap = 0.025 * min(width, height)
    dx, dy = data_size
    renderer = fig.canvas.get_renderer()
    fit_width(title, renderer, width - 2 * pad)
    for _ in range(8):
        top = title.get_window_extent(renderer).y0 - gap
        room_w, room_h = width - 2 * pad, top - pad
        # the boxes' sizes and where each text's anchor sits inside its box
        boxes = []
        for t in texts:
            t.set_position((0.5, 0.5))
            t.draw(renderer)
            box = t.get_bbox_patch().get_window_extent(renderer)
            anchor = t.get_transform().transform((0.5, 0.5))
            boxes.append((box.width, box.height, anchor[0] - box.x0, anchor[1] - box.y1))
        column_w = max(b[0] for b in boxes)
        column_h = sum(b[1] for b in boxes) + gap * (len(boxes) - 1)
        row_w = sum(b[0] for b in boxes) + gap * (len(boxes) - 1)
        row_h = max(b[1] for b in boxes)
        # diagram scale (pixels per data unit) for each arrangement; 0 where the text does not fit
        scales = {
            "beside": min((room_w - column_w - gap) / dx, room_h / dy) if column_h <= room_h else 0.0,
            "row below": min(room_w / dx, (room_h - row_h - gap) / dy) if row_w <= room_w else 0.0,
            "column below": min(room_w / dx, (room_h - column_h - gap) / dy) if column_w <= room_w else 0.0,
        }
        arrangement = max(scales, key=scales.get)
        scale = scales[arrangement]
        # good enough when the diagram keeps half the size it would have without any text
        if scale >= 0.5 * min(room_w / dx, room_h / dy) or texts[0].get_fontsize() < 6:
            break
        for t in texts:
            t.set_fontsize(t.get_fontsize() * 0.88)
    scale = max(scale, 1e-3)
    dw, dh = dx * scale, dy * scale
    if arrangement == "beside":
        # the diagram on the left, the boxes in a column on its right, all centred
        x0 = (width - (dw + gap + column_w)) / 2
        y_mid = pad + room_h / 2
        rect = (x0, y_mid - dh / 2, dw, dh)
        x, y = x0 + dw + gap, y_mid + column_h / 2
        steps = [(0.0, -(h + gap)) for _, h, _, _ in boxes]
    else:
        # the diagram on top, the boxes under it (in a row or a column), all centred
        text_w, text_h = (row_w, row_h) if arrangement == "row below" else (column_w, column_h)
        y0 = pad + (room_h - (dh + gap + text_h)) / 2
        rect = ((width - dw) / 2, y0 + text_h + gap, dw, dh)
        x, y = (width - text_w) / 2, y0 + text_h
        if arrangement == "row below":
            steps = [(w + gap, 0.0) for w, _, _, _ in boxes]
        else:
            steps = [(0.0, -(h + gap)) for _, h, _, _ in boxes]
    # each box's top-left corner at (x, y), then on to the next
    for t, (_, _, ax_, ay), (step_x, step_y) in zip(texts, boxes, steps):
        t.set_position(((x + ax_) / width, (y + ay) / height))
        x, y = x + step_x, y + step_y
    return (rect[0] / width, rect[1] / height, rect[2] / width, rect[3] / height)
