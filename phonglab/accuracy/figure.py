"""The accuracy figure: error against time, log–log, one panel per question.

Six panels: interpolation (RMSE, and RMSE inside the highlight), precision,
Phong against Blinn-Phong, and the finite-size light (error against time, and
error against the sample count N with the fitted slopes). A reference whose
error is zero by definition is drawn as a vertical line at its time.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from phonglab.render._files import write_atomically

#: file extensions the figure can be written as
FORMATS = ("png", "svg", "pdf")

_COLOURS = {"flat": "#1b9e77", "gouraud": "#d95f02", "pixel": "#7570b3",
            "float32": "#e7298a", "float64": "#1f78b4",
            "uniform": "#d95f02", "stratified": "#1b9e77", "point": "#666666"}


def _reference_line(ax, seconds, label):
    ax.axvline(seconds, color="0.55", linestyle="--", linewidth=1)
    ax.annotate(label, (seconds, 0.02), xycoords=("data", "axes fraction"), rotation=90,
                fontsize=8, color="0.35", ha="right", va="bottom")


def _interpolation(ax, study, key, ylabel):
    for method in ("flat", "gouraud", "pixel"):
        rows = [r for r in study["rows"] if r["method"] == method and r[key] > 0]
        t = [r["time"] * 1e3 for r in rows]
        ax.plot(t, [r[key] for r in rows], "o-", color=_COLOURS[method], label=method, markersize=4)
        if rows:  # label the coarsest and finest mesh
            for r in (rows[0], rows[-1]):
                ax.annotate(str(r["resolution"]), (r["time"] * 1e3, r[key]), fontsize=7,
                            xytext=(3, 3), textcoords="offset points")
    _reference_line(ax, study["reference_time"] * 1e3, "exact sphere")
    ax.set_xlabel("shading time (ms)")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8, title="mesh resolution labelled", title_fontsize=8)


def _precision(ax, study):
    cases = list(dict.fromkeys(r["case"] for r in study["rows"]))
    markers = ("o", "s", "^", "D", "v")
    for i, case in enumerate(cases):
        pts = [r for r in study["rows"] if r["case"] == case and r["precision"] in ("float32", "float64")]
        ax.plot([r["time_per_million"] for r in pts], [max(r["max_rel_error"], 1e-17) for r in pts],
                "-", color="0.75", linewidth=0.8, zorder=1)
        for r in pts:
            ax.scatter(r["time_per_million"], max(r["max_rel_error"], 1e-17), marker=markers[i % len(markers)],
                       color=_COLOURS[r["precision"]], zorder=2, s=22,
                       label=f"{r['precision']}" if i == 0 else None)
        ax.scatter([], [], marker=markers[i % len(markers)], color="0.4", label=case, s=18)
    mp = [r["time_per_million"] for r in study["rows"] if r["precision"].startswith("mpmath")]
    if mp:
        _reference_line(ax, float(np.median(mp)), "mpmath 50 digits")
    ax.set_xlabel("time per million points (s)")
    ax.set_ylabel("max relative error")
    ax.legend(fontsize=8)


def _models(ax, study):
    from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

    alphas = sorted({r["alpha"] for r in study["rows"]})
    shown = ", ".join(f"{a:g}" for a in alphas)
    for setup, fill in (("local viewer, point light", True), ("infinite viewer, directional light", False)):
        for exponent, colour in (("a", "#1f78b4"), ("4a", "#e7298a")):
            rows = [r for r in study["rows"] if r["setup"] == setup and r["blinn_exponent"] == exponent]
            if not rows:
                continue
            # the worst case over the shininesses tried
            worst = max(rows, key=lambda r: r["max_diff"])
            ax.plot(worst["time_per_million"], worst["max_diff"], "o", markersize=7,
                    markerfacecolor=colour if fill else "white", markeredgecolor=colour,
                    label=f"blinn-phong {exponent.replace('a', 'α')}, {setup.split(',')[0]}")
        phong = [t["time_per_million"] for t in study["timing"] if t["model"] == "phong" and t["setup"] == setup]
        if phong:
            _reference_line(ax, phong[0], f"phong, {setup.split(',')[0]}")
    ax.set_xlabel("time per million points (s)")
    ax.set_ylabel(f"max |specular − phong's|, worst of α = {shown}")
    ax.legend(fontsize=8)
    # the times span less than a decade: label a few plain ticks, not every minor one
    ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.xaxis.set_major_formatter(FormatStrFormatter("%.3g"))


def _area_time(ax, study):
    for method in ("uniform", "stratified"):
        rows = [r for r in study["rows"] if r["method"] == method]
        ax.plot([r["time"] * 1e3 for r in rows], [r["error"] for r in rows], "o-", color=_COLOURS[method],
                label=f"Monte Carlo, {method}", markersize=4)
    point = [r for r in study["rows"] if r["method"] == "point"]
    if point:
        ax.plot(point[0]["time"] * 1e3, point[0]["error"], "*", color=_COLOURS["point"], markersize=10,
                label="point light at the centre")
    _reference_line(ax, study["reference_time"] * 1e3, "exact (Lambert)")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("relative RMS error")
    ax.legend(fontsize=8)


def _area_samples(ax, study):
    for method in ("uniform", "stratified"):
        rows = [r for r in study["rows"] if r["method"] == method]
        n = np.array([r["samples"] for r in rows], float)
        e = np.array([r["error"] for r in rows])
        slope = study["slopes"][method]
        ax.plot(n, e, "o", color=_COLOURS[method], markersize=4)
        # the fitted power law through the points' geometric centre
        fit = np.exp(np.mean(np.log(e)) + slope * (np.log(n) - np.mean(np.log(n))))
        ax.plot(n, fit, "-", color=_COLOURS[method], label=f"{method}: slope {slope:+.2f}")
    rows = [r for r in study["rows"] if r["method"] == "uniform"]
    if rows:
        n = np.array([r["samples"] for r in rows], float)
        guide = rows[0]["error"] * 1.6 * n ** -0.5
        ax.plot(n, guide, ":", color="0.4", label="1/√N")
    ax.set_xlabel("samples per point N")
    ax.set_ylabel("relative RMS error")
    ax.legend(fontsize=8)


def draw(results: dict):
    """A matplotlib Figure of the studies (Agg backend, not shown)."""
    from matplotlib.figure import Figure

    studies = {s["name"]: s for s in results["studies"]}
    fig = Figure(figsize=(15, 9), layout="constrained")
    axes = fig.subplots(2, 3)
    panels = [
        ("interpolation", lambda ax, s: _interpolation(ax, s, "rmse", "RMSE of the colour"),
         "1. Interpolation: error of the image"),
        ("interpolation", lambda ax, s: _interpolation(ax, s, "highlight_rmse", "RMSE inside the highlight"),
         "1. Interpolation: error in the highlight"),
        ("precision", _precision, "2. Precision against 50 digits"),
        ("models", _models, "3. Blinn-Phong against Phong (α vs 4α)"),
        ("area_light", _area_time, "4. Finite light: error against time"),
        ("area_light", _area_samples, "4. Finite light: error against samples"),
    ]
    for ax, (name, plot, title) in zip(axes.ravel(), panels):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
        ax.set_title(title, fontsize=10)
        if name in studies:
            plot(ax, studies[name])
    fig.suptitle("phonglab: what accuracy costs in time" + (" (quick run)" if results.get("quick") else ""))
    return fig


def write_figure(results: dict, path) -> str:
    """Write the figure to ``path``; the format follows the extension (.png, .svg, .pdf).

    The file is written to a temporary name in the same folder and renamed, so
    a reader never sees half a file.

    Raises
    ------
    ValueError
        If the extension is not one of :data:`FORMATS`.
    OSError
        If the file cannot be written (nothing is left behind).
    """
    path = Path(path)
    ext = path.suffix.lower().lstrip(".")
    if ext not in FORMATS:
        raise ValueError(f"figure path: must end in .png, .svg or .pdf, got {str(path)!r}")
    fig = draw(results)
    write_atomically(path, lambda tmp: fig.savefig(tmp, format=ext, dpi=110))
    return str(path)
