"""``phonglab bench planner``: planned scenes against the full evaluation.

On 1M vertices (points on a unit sphere with their normals), in one run, the
baseline is the *full* evaluation of a point light with a local viewer: every
term of the Phong sum, per-point ``L`` and ``V``, attenuation even though it
is ``(1, 0, 0)``. Each case below is shaded with its plan
(:func:`phonglab.scene.shade`) and printed as a ratio to that baseline, next
to the ratio of the case's own full evaluation:

- ambient only (an ambient light, no other light): no per-light work;
- diffuse only (``k_s = 0``, a point light): no specular;
- directional light + infinite viewer: constant ``L`` and ``V`` (Phong still
  reflects per point, as ``r`` depends on ``n``); the same with Blinn-Phong,
  where ``H`` is constant too (for information: the baseline is Phong);
- point light, local viewer: what planning alone saves on the baseline scene;
- spotlight with attenuation: the cone and ``1/(a + b d + c d²)`` per point.

Every time is the median of several runs, the scenes timed in turn. Targets (ratio to the baseline):
ambient only <= 0.10, diffuse only <= 0.6, directional + infinite viewer <= 0.5.

Then the shadow figures (:mod:`phonglab.bench.shadows`): one convex object
with shadows on against off (target <= 1.05), the ball over the floor with
the planned shadow rays against those of every pair, and the re-shade with
shadows on per vertex and per pixel.
"""

from __future__ import annotations

import json
import statistics
import sys
import time

import numpy as np

from phonglab.bench import shadows
from phonglab.bench.scenes import red_sphere
from phonglab.scene import Scene, plan, shade

HELP = "planned scenes against the full evaluation"

#: case -> largest allowed ratio to the baseline
TARGETS = {"ambient only": 0.10, "diffuse only": 0.6, "directional + infinite viewer": 0.5}


def add_arguments(parser):
    parser.add_argument("--points", type=int, default=1_000_000, metavar="N", help="vertices (default 1000000)")
    parser.add_argument("--repeats", type=int, default=7, metavar="K", help="runs per median (default 7)")
    parser.add_argument("--dtype", choices=("float32", "float64"), default="float32", help="vertex dtype (default float32)")
    parser.add_argument("--quick", action="store_true", help="100000 vertices, 3 runs: a smoke test")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    parser.add_argument("--shadow-vertices", type=int, default=100_000, metavar="N",
                        help="vertices of the shadow scenes (default 100000)")
    parser.add_argument("--shadow-picture", default="960x720", metavar="WxH",
                        help="size of the per-pixel view the shadows are timed in (default 960x720, the page's)")


def interleaved_medians(functions: dict, repeats: int) -> dict:
    """Median wall time of each function, timed round-robin after one warm-up each.

    Taking turns spreads any slowdown of a shared machine over every function
    alike, so the ratios between them hold better than the absolute times.
    """
    for fn in functions.values():
        fn()
    samples = {name: [] for name in functions}
    for _ in range(repeats):
        for name, fn in functions.items():
            start = time.perf_counter()
            fn()
            samples[name].append(time.perf_counter() - start)
    return {name: statistics.median(times) for name, times in samples.items()}


def sphere_vertices(n: int, dtype, seed: int = 0):
    """``n`` points on the unit sphere and their normals (the same vectors)."""
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(n, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return normals.astype(dtype), normals.astype(dtype)


def cases() -> dict[str, Scene]:
    """The benchmark scenes; the first is the baseline's scene."""
    base = red_sphere(title="point light, local viewer")
    return {
        "point light, local viewer": base,
        "ambient only": base.replace("lights", [{"type": "ambient", "intensity": 0.2}]),
        "diffuse only": base.replace("material.ks", 0),
        "directional + infinite viewer": base.replace(
            "lights[1]", {"type": "directional", "direction": [2, 2.5, 3]}
        ).replace("camera.infinite_viewer", True),
        "directional + infinite viewer, blinn-phong": base.replace(
            "lights[1]", {"type": "directional", "direction": [2, 2.5, 3]}
        )
        .replace("camera.infinite_viewer", True)
        .replace("model", "blinn-phong"),
        "spotlight with attenuation": base.replace(
            "lights[1]",
            {
                "type": "spot",
                "position": [2, 2.5, 3],
                "direction": [-2, -2.5, -3],
                "cutoff": 30,
                "exponent": 2,
                "attenuation": [1, 0.05, 0.01],
            },
        ),
    }


def measure(n_points: int, repeats: int, dtype) -> dict:
    """Time every case planned and full; ratios to the baseline's full evaluation."""
    points, normals = sphere_vertices(n_points, dtype)
    scenes = cases()
    baseline_name = next(iter(scenes))
    print(f"timing {len(scenes)} scenes on {n_points} vertices ({np.dtype(dtype).name}), "
          f"median of {repeats}", file=sys.stderr, flush=True)
    plans = {name: plan(scene) for name, scene in scenes.items()}
    functions = {}
    for name, scene in scenes.items():
        functions[("full", name)] = lambda scene=scene: shade(scene, points, normals, full=True)
        functions[("planned", name)] = lambda scene=scene, p=plans[name]: shade(scene, points, normals, scene_plan=p)
    times = interleaved_medians(functions, repeats)
    baseline = times[("full", baseline_name)]
    rows = []
    for name in scenes:
        planned, full = times[("planned", name)], times[("full", name)]
        target = TARGETS.get(name)
        ratio = planned / baseline
        rows.append(
            {
                "case": name,
                "planned_vs_baseline": ratio,
                "full_vs_baseline": full / baseline,
                "planned_vs_own_full": planned / full,
                "target": target,
                "verdict": None if target is None else ("PASS" if ratio <= target else "MISS"),
                "skipped": [effect for effect, _ in plans[name].skipped],
            }
        )
    return {
        "points": n_points,
        "dtype": np.dtype(dtype).name,
        "repeats": repeats,
        "baseline": f"{baseline_name}, full evaluation",
        "baseline_seconds": baseline,
        "cases": rows,
    }


def format_report(result: dict) -> str:
    """The figures as an aligned table of ratios."""
    headers = ("case", "planned/base", "full/base", "planned/own full", "target", "")
    cells = [headers]
    for row in result["cases"]:
        cells.append(
            (
                row["case"],
                f"{row['planned_vs_baseline']:.3f}",
                f"{row['full_vs_baseline']:.3f}",
                f"{row['planned_vs_own_full']:.3f}",
                f"<= {row['target']:.2f}" if row["target"] is not None else "",
                row["verdict"] or "",
            )
        )
    widths = [max(len(str(c[i])) for c in cells) for i in range(len(headers))]
    lines = [
        f"phonglab bench planner: {result['points']} vertices, {result['dtype']}, median of {result['repeats']}",
        f"baseline = {result['baseline']} ({result['baseline_seconds'] * 1e3:.1f} ms here; ratios below)",
        "",
    ]
    for i, c in enumerate(cells):
        lines.append("  ".join(str(x).ljust(w) for x, w in zip(c, widths)).rstrip())
        if i == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def run(args) -> int:
    n_points, repeats = args.points, args.repeats
    if args.quick:
        n_points, repeats = 100_000, 3
    if n_points < 1 or repeats < 1:
        from phonglab.bench.usage import UsageError

        raise UsageError(f"--points and --repeats must be >= 1, got {n_points} and {repeats}")
    shadow_vertices = 20_000 if args.quick else args.shadow_vertices
    picture = "320x240" if args.quick else args.shadow_picture
    size = picture.split("x") if isinstance(picture, str) else []
    if shadow_vertices < 100 or len(size) != 2 or not all(x.isdigit() and 16 <= int(x) <= 4096 for x in size):
        from phonglab.bench.usage import UsageError

        raise UsageError(f"--shadow-vertices must be >= 100 and --shadow-picture WxH, each from 16 to 4096, "
                         f"got {shadow_vertices} and {picture!r}")
    result = measure(n_points, repeats, np.dtype(args.dtype))
    print(f"timing the shadow figures on about {shadow_vertices} vertices", file=sys.stderr, flush=True)
    result["shadows"] = shadows.measure(shadow_vertices, repeats, (int(size[0]), int(size[1])))
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        print(format_report(result) + "\n\n" + shadows.format_report(result["shadows"]))
    return 0
