"""``phonglab bench core``: the shading core against plain NumPy and the memory floor.

On 1M vertices, one point light, Phong, RGB coefficients, float32, in one run:

- phonglab's ``shade`` against a straightforward NumPy implementation written
  here (``np.linalg.norm`` to normalise, form R, ``np.clip``, power);
- against the machine's memory floor: ``np.copyto`` of the same bytes that
  shading reads (points, normals) and writes (diffuse, specular, colour);
- scaling from 10k to 4M points and from 1 to 8 lights, as time per
  point-light relative to the 1M-point, one-light case.

Every figure is a median of several runs and is printed as a ratio.
"""

from __future__ import annotations

import json

import numpy as np

from phonglab import core
from phonglab.bench.timing import median_time, progress, table, verdict

HELP = "the shading core against plain NumPy and the memory-copy floor"

TARGET_VS_NAIVE = 0.4
TARGET_VS_COPY = 8.0


def add_arguments(parser):
    parser.add_argument("--points", type=int, default=1_000_000, metavar="N",
                        help="points for the main comparison (default 1000000)")
    parser.add_argument("--repeats", type=int, default=7, metavar="K", help="runs per median (default 7)")
    parser.add_argument("--quick", action="store_true", help="fewer points and repeats, no 4M case")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")


def naive_phong(points, normals, eye, light_position, ka_ia, kd_id, ks_is, shininess):
    """Phong as a textbook would write it in NumPy: the baseline to beat."""
    n = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    l = light_position - points
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    v = eye - points
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    nl = np.sum(n * l, axis=1)
    r = 2 * nl[:, None] * n - l
    rv = np.clip(np.sum(r * v, axis=1), 0, 1)
    spec = np.where(nl > 0, rv**shininess, 0)
    diffuse = kd_id * np.clip(nl, 0, None)[:, None]
    specular = ks_is * spec[:, None]
    return diffuse, specular, ka_ia + diffuse + specular


def make_inputs(n_points: int, seed: int = 0):
    """Points on a unit sphere with their normals, float32."""
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(n_points, 3)).astype(np.float32)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return normals.copy(), normals


MATERIAL = core.Material(ka=(0.1, 0.1, 0.12), kd=(0.8, 0.3, 0.2), ks=(0.6, 0.6, 0.5), shininess=40.0)
EYE = (0.0, 0.0, 4.0)


def lights(count: int):
    """``count`` point lights around the object."""
    out = []
    for i in range(count):
        angle = 2 * np.pi * i / max(count, 1)
        out.append(core.PointLight(position=(3 * np.cos(angle), 2.5, 3 * np.sin(angle) + 1)))
    return out


def run(args) -> int:
    n = 200_000 if args.quick and args.points == 1_000_000 else args.points
    repeats = 3 if args.quick else args.repeats
    if n < 1 or repeats < 1:
        from phonglab.bench.usage import UsageError

        raise UsageError(f"--points and --repeats must be >= 1, got {n} and {repeats}")
    points, normals = make_inputs(n)
    light = lights(1)
    results: dict = {"points": n, "repeats": repeats}

    progress(f"core: {n:,} points, one point light, Phong, float32")
    t_phonglab = median_time(lambda: core.shade(points, normals, eye=EYE, material=MATERIAL, lights=light),
                             repeats=repeats)
    pos = np.asarray(light[0].position, np.float32)
    kd_id = np.asarray(MATERIAL.kd, np.float32)
    ks_is = np.asarray(MATERIAL.ks, np.float32)
    ka_ia = np.zeros(3, np.float32)
    eye = np.asarray(EYE, np.float32)
    t_naive = median_time(lambda: naive_phong(points, normals, eye, pos, ka_ia, kd_id, ks_is,
                                              np.float32(MATERIAL.shininess)), repeats=repeats)
    # memory floor: copy what shading reads (points, normals) and writes (diffuse, specular, colour)
    sources = [points, normals, points.copy(), normals.copy(), points.copy()]
    targets = [np.empty_like(a) for a in sources]

    def copy_all():
        for dst, src in zip(targets, sources):
            np.copyto(dst, src)

    t_copy = median_time(copy_all, repeats=repeats)

    # agreement, so speed is not bought with wrong answers
    ours = core.shade(points[:10000], normals[:10000], eye=EYE, material=MATERIAL, lights=light).color
    ref = naive_phong(points[:10000].astype(np.float64), normals[:10000].astype(np.float64),
                      np.asarray(EYE), np.asarray(light[0].position), 0, np.asarray(MATERIAL.kd),
                      np.asarray(MATERIAL.ks), MATERIAL.shininess)[2]
    max_diff = float(np.abs(ours - ref).max())

    vs_naive, vs_copy = t_phonglab / t_naive, t_phonglab / t_copy
    results.update(phonglab_s=t_phonglab, naive_s=t_naive, copy_s=t_copy, vs_naive=vs_naive,
                   vs_copy=vs_copy, max_abs_diff_vs_float64=max_diff)
    rows = [
        ["phonglab / plain NumPy", f"{vs_naive:.2f}x", f"<= {TARGET_VS_NAIVE}x", verdict(vs_naive, TARGET_VS_NAIVE)],
        ["phonglab / memory copy", f"{vs_copy:.2f}x", f"<= {TARGET_VS_COPY:g}x", verdict(vs_copy, TARGET_VS_COPY)],
    ]

    # scaling: time per point-light, relative to the main case
    per_unit = t_phonglab / n
    sizes = [10_000, 100_000, 1_000_000] + ([] if args.quick else [4_000_000])
    scaling = []
    for size in sizes:
        progress(f"core: scaling, {size:,} points x 1 light")
        p, nn = make_inputs(size, seed=1)
        t = median_time(lambda: core.shade(p, nn, eye=EYE, material=MATERIAL, lights=light),
                        repeats=max(3, repeats if size <= 1_000_000 else 3))
        scaling.append({"points": size, "lights": 1, "per_point_light": t / size / per_unit})
    p, nn = make_inputs(min(n, 250_000), seed=2)
    for count in (1, 2, 4, 8):
        progress(f"core: scaling, {len(p):,} points x {count} lights")
        ls = lights(count)
        t = median_time(lambda: core.shade(p, nn, eye=EYE, material=MATERIAL, lights=ls), repeats=repeats)
        scaling.append({"points": len(p), "lights": count, "per_point_light": t / (len(p) * count) / per_unit})
    results["scaling"] = scaling

    if args.json:
        print(json.dumps(results, indent=2))
        return 0
    print(f"phonglab bench core: {n:,} points, 1 point light, Phong, RGB, float32; medians of {repeats}")
    print(f"(phonglab {t_phonglab * 1e3:.1f} ms, plain NumPy {t_naive * 1e3:.1f} ms, "
          f"memory copy {t_copy * 1e3:.1f} ms; max |phonglab - float64 NumPy| = {max_diff:.2e})")
    print()
    print(table(rows, ["comparison", "ratio", "target", "verdict"]))
    print()
    print("time per point-light, relative to the main case (flat = linear cost):")
    print(table([[f"{s['points']:,}", s["lights"], f"{s['per_point_light']:.2f}"] for s in scaling],
                ["points", "lights", "relative time per point-light"]))
    return 0
