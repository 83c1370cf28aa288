"""Matplotlib plots of the model: the specular lobe, Lambert's cosine, the plane of incidence.

Each ``*_plot`` function returns a matplotlib ``Figure`` (Agg backend) of the
requested pixel size; :func:`phonglab.render.figures.figure` saves it as PNG,
SVG or PDF. Directions point *away from the surface point*.
"""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg", force=False)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Arc  # noqa: E402

from phonglab import core  # noqa: E402

#: shininess values drawn by the lobe plot (the scene's own is added)
LOBE_EXPONENTS = (1, 4, 16, 64, 256)
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
    makers = {"lobe": lobe_plot, "lambert": lambert_plot, "incidence": incidence_plot}
    return makers[kind](scene, size)


def _figure(size, **kwargs):
    return plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100, facecolor="white", **kwargs)


def _font(size) -> float:
    """A base font size in points that suits a figure of ``size`` pixels."""
    return max(7.0, min(size) / 52)


def half_width(shininess: float) -> float:
    """The angle φ (degrees) at which :math:`\\cos^\\alpha\\phi` falls to one half."""
    return math.degrees(math.acos(0.5 ** (1.0 / shininess)))


def lobe_plot(scene, size):
    """The specular lobe :math:`\\max(0, \\cos\\phi)^\\alpha` for several α: polar and cartesian.

    φ is the angle between R and V (Phong) or N and H (Blinn-Phong); the
    scene's own shininess is drawn thick.
    """
    alpha_scene = float(scene.material.shininess)
    exponents = sorted(set(LOBE_EXPONENTS) | {alpha_scene})
    angle_name = r"$\angle(N, H)$" if scene.model == "blinn-phong" else r"$\angle(R, V)$"
    fs = _font(size)
    fig = _figure(size)
    polar = fig.add_subplot(1, 2, 1, projection="polar")
    flat = fig.add_subplot(1, 2, 2)
    phi = np.linspace(-math.pi / 2, math.pi / 2, 721)
    colors = plt.cm.viridis(np.linspace(0.05, 0.85, len(exponents)))
    for alpha, color in zip(exponents, colors):
        lobe = np.maximum(0.0, np.cos(phi)) ** alpha
        mine = alpha == alpha_scene
        label = rf"$\alpha$ = {alpha:g}" + ("  (this scene)" if mine else "") + f"   half at {half_width(alpha):.1f}°"
        width = 3.2 if mine else 1.6
        style = "-" if mine or alpha in LOBE_EXPONENTS else "--"
        polar.plot(phi, lobe, color="black" if mine else color, lw=width, ls=style)
        flat.plot(np.degrees(phi), lobe, color="black" if mine else color, lw=width, ls=style, label=label)
    # polar: R (or H) straight up, the surface along the horizontal
    polar.set_theta_zero_location("N")
    polar.set_theta_direction(-1)
    polar.set_thetamin(-90)
    polar.set_thetamax(90)
    polar.set_rticks([0.25, 0.5, 0.75, 1.0])
    polar.tick_params(labelsize=fs * 0.8)
    polar.set_title(f"lobe around {'N' if scene.model == 'blinn-phong' else 'R'} (polar)", fontsize=fs * 1.1)
    flat.set_xlim(-90, 90)
    flat.set_ylim(0, 1.05)
    flat.set_xticks(range(-90, 91, 30))
    flat.set_xlabel(f"φ = {angle_name} in degrees", fontsize=fs)
    flat.set_ylabel(r"$\max(0, \cos\varphi)^{\alpha}$", fontsize=fs)
    flat.tick_params(labelsize=fs * 0.85)
    flat.grid(alpha=0.3)
    flat.set_title("larger α: a smaller, sharper highlight", fontsize=fs * 1.1)
    handles, labels = flat.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=fs * 0.85, frameon=False)
    fig.suptitle(r"Specular lobe  $\max(0,\cos\varphi)^{\alpha}$", fontsize=fs * 1.35, weight="bold")
    fig.tight_layout(rect=(0, 0.12, 1, 0.94))
    return fig


def lambert_plot(scene, size):
    """Lambert's cosine law: :math:`\\max(0, \\cos\\theta)` against the angle of incidence θ.

    The scene's probe angle (between N and L) is marked when the scene has a
    directed light.
    """
    fs = _font(size)
    fig = _figure(size)
    flat = fig.add_subplot(1, 2, 1)
    polar = fig.add_subplot(1, 2, 2, projection="polar")
    theta = np.linspace(0, 180, 721)
    cos = np.cos(np.radians(theta))
    flat.plot(theta, cos, color="0.6", ls="--", lw=1.4, label=r"$\cos\theta$")
    flat.plot(theta, np.maximum(0, cos), color=PAPER_COLORS["L"], lw=3, label=r"$\max(0, \cos\theta)$")
    flat.axvspan(90, 180, color="0.9")
    flat.text(135, 0.55, "light behind\nthe surface:\nno diffuse light", ha="center", va="center", fontsize=fs * 0.85)
    flat.axhline(0, color="black", lw=0.8)
    probe = _probe_vectors(scene)
    if probe is not None:
        _, _, vec = probe
        angle = math.degrees(math.acos(max(-1.0, min(1.0, vec.nl))))
        flat.axvline(angle, color=PAPER_COLORS["N"], lw=1.2)
        flat.plot([angle], [max(0.0, vec.nl)], "o", color=PAPER_COLORS["N"])
        flat.annotate(
            f"probe: θ = {angle:.1f}°\nn·l = {vec.nl:.3f}",
            (angle, max(0.0, vec.nl)),
            xytext=(14, -46),
            textcoords="offset points",
            fontsize=fs * 0.85,
            color=PAPER_COLORS["N"],
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
    # polar: the light's direction against the normal, radius = brightness
    phi = np.linspace(-math.pi / 2, math.pi / 2, 361)
    polar.plot(phi, np.cos(phi), color=PAPER_COLORS["L"], lw=3)
    polar.fill(phi, np.cos(phi), color=PAPER_COLORS["L"], alpha=0.15)
    polar.set_theta_zero_location("N")
    polar.set_theta_direction(-1)
    polar.set_thetamin(-90)
    polar.set_thetamax(90)
    polar.set_rticks([0.5, 1.0])
    polar.tick_params(labelsize=fs * 0.8)
    polar.set_title(r"brightness for light arriving at $\theta$ from N (polar)", fontsize=fs * 1.05)
    fig.suptitle(r"Lambert's cosine law  $I_d = k_d\, I_l \max(0, n\cdot l)$", fontsize=fs * 1.35, weight="bold")
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    return fig


def _probe_vectors(scene):
    """(point, normal, ProbeVectors) at the scene's probe for its first directed light, or None."""
    from phonglab.render.mesh import build_mesh, surface_point
    from phonglab.render.view import default_probe

    light = next((x for x in scene.lights if not isinstance(x, core.AmbientLight)), None)
    if light is None:
        return None
    mesh = build_mesh(scene.geometry)
    if scene.probe is None:
        point, normal = default_probe(mesh, scene.camera)
    else:
        point, normal = surface_point(mesh, scene.probe)
    camera = scene.camera
    viewer = {"view_direction": camera.view_direction} if camera.infinite_viewer else {"eye": camera.eye}
    vec = core.vectors(point, normal, light=light, two_sided=scene.two_sided, **viewer)
    return point, normal, vec


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
    phonglab.render.figures.FigureError
        If the scene has no point, directional or spot light.
    """
    from phonglab.render.figures import FigureError

    probe = _probe_vectors(scene)
    if probe is None:
        raise FigureError("plot: incidence needs a point, directional or spot light in the scene")
    point, _, vec = probe
    n, l, r, v, h = vec.n, vec.l, vec.r, vec.v, vec.h
    # in-plane basis: y along N, x along L's tangent part (L drawn on the left)
    tangent = l - (l @ n) * n
    if np.linalg.norm(tangent) < 1e-9:
        tangent = v - (v @ n) * n
    if np.linalg.norm(tangent) < 1e-9:
        tangent = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 1.0, 0.0])
    x_axis = -tangent / np.linalg.norm(tangent)
    z_axis = np.cross(x_axis, n)

    def flat(u):
        return np.array([u @ x_axis, u @ n])

    def out_of_plane(u) -> float:
        return math.degrees(math.asin(max(-1.0, min(1.0, float(u @ z_axis)))))

    fs = _font(size)
    fig = _figure(size)
    ax = fig.add_axes((0.03, 0.08, 0.6, 0.8))
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_xlim(-1.35, 1.35)
    ax.set_ylim(-0.45, 1.3)
    # the surface, hatched below
    ax.plot([-1.3, 1.3], [0, 0], color="black", lw=2)
    ax.fill_between([-1.3, 1.3], [-0.12, -0.12], [0, 0], hatch="///", facecolor="white", edgecolor="0.6", lw=0)
    vectors = {"N": n, "L": l, "R": r, "V": v, "H": h}
    placed = []
    for name, u in vectors.items():
        p = flat(u)
        projected = abs(out_of_plane(u)) > 1.0
        ax.annotate(
            "", xy=tuple(p), xytext=(0, 0),
            arrowprops=dict(arrowstyle="-|>", lw=2.6, color=PAPER_COLORS[name], mutation_scale=22,
                            linestyle="--" if projected else "-", shrinkA=0, shrinkB=0),
        )
        spot = _free_spot(p * 1.1 + np.array([0.0, 0.03]), placed, 0.12)
        placed.append(spot)
        ax.text(*spot, name + ("′" if projected else ""), color=PAPER_COLORS[name], fontsize=fs * 1.4,
                weight="bold", ha="center", va="center")
    # angle arcs, drawn between the in-plane directions, labelled with the true angles
    arcs = [("L", "N", 0.32, _angle(n, l), r"$\theta_i$"), ("N", "R", 0.38, _angle(n, r), r"$\theta_r$"),
            ("R", "V", 0.55, _angle(r, v), r"$\varphi$"), ("N", "H", 0.24, _angle(n, h), r"$\psi$")]
    for a, b, radius, true_angle, symbol in arcs:
        pa, pb = flat(vectors[a]), flat(vectors[b])
        ta, tb = math.degrees(math.atan2(pa[1], pa[0])), math.degrees(math.atan2(pb[1], pb[0]))
        lo, hi = sorted((ta, tb))
        if hi - lo > 180:
            lo, hi = hi, lo + 360
        ax.add_patch(Arc((0, 0), 2 * radius, 2 * radius, theta1=lo, theta2=hi, color="0.25", lw=1.2))
        mid = math.radians((lo + hi) / 2)
        direction = np.array([math.cos(mid), math.sin(mid)])
        spot = direction * (radius + 0.09)
        # move outwards along the bisector until clear of the other labels
        while any(np.linalg.norm(spot - q) < 0.1 for q in placed) and np.linalg.norm(spot) < 1.2:
            spot = spot + 0.06 * direction
        placed.append(spot)
        ax.text(*spot, symbol, fontsize=fs * 1.1, ha="center", va="center", color="0.15")
    # the numbers
    alpha = scene.material.shininess
    specular_cos = vec.nh if scene.model == "blinn-phong" else vec.rv
    cos_symbol = r"n\cdot h" if scene.model == "blinn-phong" else r"r\cdot v"
    lines = [
        rf"$\theta_i = \angle(N, L)$ = {_angle(n, l):.1f}°",
        rf"$\theta_r = \angle(N, R)$ = {_angle(n, r):.1f}°",
        rf"$\varphi = \angle(R, V)$ = {_angle(r, v):.1f}°",
        rf"$\psi = \angle(N, H)$ = {_angle(n, h):.1f}°",
        "",
        rf"$n\cdot l$ = {vec.nl:.3f}",
        rf"$r\cdot v$ = {vec.rv:.3f}",
        rf"$n\cdot h$ = {vec.nh:.3f}",
        rf"specular factor $\max(0, {cos_symbol})^{{{alpha:g}}}$"
        + f" = {max(0.0, specular_cos) ** alpha if vec.nl > 0 else 0.0:.3f}",
    ]
    if abs(out_of_plane(v)) > 1.0:
        lines += ["", f"V leaves the plane by {abs(out_of_plane(v)):.1f}°,", f"H by {abs(out_of_plane(h)):.1f}°:",
                  "V′, H′ are their projections"]
    fig.text(0.64, 0.82, "\n".join(lines), fontsize=fs * 0.95, va="top", ha="left", linespacing=1.6)
    px, py, pz = point
    fig.suptitle(f"Plane of incidence at the probe ({px:.2f}, {py:.2f}, {pz:.2f})", fontsize=fs * 1.35,
                 weight="bold")
    return fig
