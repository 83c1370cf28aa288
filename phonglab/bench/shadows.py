"""``phonglab bench planner``'s shadow figures: what shadows cost, and what the planner saves.

Three figures, each a ratio of times measured in the same run (medians,
timed in turn so that a change of load hits both alike):

a. **a single convex object** (the red sphere, about 100k vertices):
   re-shading its vertices with shadows on against the same with shadows
   off. A convex object cannot shadow itself, so the planner traces
   nothing; what is left is planning. Target: at most 1.05.
b. **the ball over the floor** (``assets/scenes/ball-over-floor.toml`` at
   about 100k vertices): the shadow rays of the planned pairs against those
   of every pair (``plan(scene, full_shadows=True)``), each with the
   re-shade (and the casting alone: each time less the re-shade without
   shadows); the colours are the same.
c. **re-shading with shadows on**, after the lamp moved (no shadow kept):
   the ball over the floor per vertex (about 100k vertices), and the
   per-pixel view (960 × 720, as the page shades it), each against its own
   re-shade with shadows off; with the milliseconds and the shadow rays per
   second.

Times are the median CPU time of the thread that shades (Embree answers in
that thread too), of at least 16 runs (48 for the convex object), the cases timed in turn, each first
in half of the rounds. The view's
camera does not change a shadow, so a turn of the view re-shades
with the shadows kept from the last lamp position; these figures are for a
change that moves them.
"""

from __future__ import annotations

import os
import statistics
import time
from pathlib import Path

import numpy as np

from phonglab.bench.scenes import red_sphere

#: case -> largest allowed ratio
TARGETS = {"convex object: shadows on / off": 1.05}
#: the ball-over-floor scene
BALL_OVER_FLOOR = Path(__file__).resolve().parents[2] / "assets" / "scenes" / "ball-over-floor.toml"


def _medians(functions: dict, repeats: int) -> dict:
    """Median CPU time of each function (this thread's), timed in turn, the order reversed each round.

    Each function runs once first, as a warm-up.

    CPU time, not wall time: on a shared machine another process's work lands
    on the wall clock of whichever function runs then, and with figures a few
    per cent apart that noise is larger than the difference measured.
    """
    for fn in functions.values():
        fn()
    samples = {name: [] for name in functions}
    order = list(functions.items())
    for _ in range(repeats):
        for name, fn in order:
            start = time.thread_time()
            fn()
            samples[name].append(time.thread_time() - start)
        order.reverse()  # whichever runs first in a round pays for the caches: each goes first as often
    return {name: statistics.median(times) for name, times in samples.items()}


def ball_over_floor(vertices: int):
    """The ball over the floor with about ``vertices`` vertices, half on the ball and half on the floor."""
    from phonglab.scene import load_scene

    ball = max(8, int(round(np.sqrt(vertices))))  # n (n/2 + 1) ≈ n²/2 vertices
    floor = max(4, int(round(np.sqrt(vertices / 2))) - 1)  # (n + 1)² vertices
    return load_scene(BALL_OVER_FLOOR).replace_many([("objects[0].geometry.resolution", ball),
                                                     ("objects[1].geometry.resolution", floor)])


def _vertex_job(scene, scene_plan):
    """Re-shade ``scene``'s vertices as the view does, its shadows cast again (as after the lamp moved).

    ``scene_plan`` is a plan, or a function making one for each re-shade.
    """
    from phonglab.render import shadows
    from phonglab.render.objects import point_objects, scene_mesh
    from phonglab.render.shading import display_rgb8, shade

    mesh = scene_mesh(scene)
    points, normals = np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"])
    ids = point_objects(mesh)

    def job():
        shadows.forget()
        made = scene_plan() if callable(scene_plan) else scene_plan
        display_rgb8(scene, shade(scene, points, normals, scene_plan=made, objects=ids).color)

    return job, len(points)


def measure(vertices: int, repeats: int, pixel_size=(960, 720)) -> dict:
    """Every shadow figure; see the module docstring."""
    repeats = max(repeats, 16)  # even: each case first in half of the rounds
    from phonglab.render import SceneView, shadows
    from phonglab.render.objects import scene_mesh
    from phonglab.render.shading import pixel_colors
    from phonglab.scene import plan

    rows = []

    # a. one convex object: shadows on against off (the planner traces nothing)
    sphere = red_sphere(max(8, int(round(np.sqrt(2 * vertices)))))
    on, off = sphere.replace("shadows", True), sphere
    jobs = {}
    for name, scene in (("on", on), ("off", off)):
        # as the page: it plans every update (for its plan panel) and shades with that plan
        jobs[name] = _vertex_job(scene, lambda scene=scene: plan(scene))[0]
    times = _medians(jobs, 3 * repeats)  # a difference of a few per cent: more runs
    count = scene_mesh(on).n_points
    rows.append(_row("convex object: shadows on / off", times["on"], times["off"], f"{count:,} vertices, "
                     f"{len(plan(on).traced)} pairs traced"))

    # b. the ball over the floor: planned pairs against every pair
    scene = ball_over_floor(vertices)
    planned_plan, full_plan = plan(scene), plan(scene, full_shadows=True)
    planned_job, count = _vertex_job(scene, planned_plan)
    full_job, _ = _vertex_job(scene, full_plan)
    off_job, _ = _vertex_job(scene.replace("shadows", False), None)
    times = _medians({"planned": planned_job, "full": full_job, "off": off_job}, repeats)
    rays = {name: _rays(scene, p) for name, p in (("planned", planned_plan), ("full", full_plan))}
    casting = (times["planned"] - times["off"]) / max(times["full"] - times["off"], 1e-9)
    rows.append(_row("ball over floor: planned / every pair", times["planned"], times["full"],
                     f"{count:,} vertices; {rays['planned']:,} rays against {rays['full']:,}; "
                     f"the casting alone {casting:.2f}"))

    # c. re-shading with shadows on: per vertex (the same scene), per pixel (the page's view)
    rows.append(_row("ball over floor, per vertex: shadows on / off", times["planned"], times["off"],
                     f"{times['planned'] * 1e3:.0f} ms against {times['off'] * 1e3:.0f} ms; "
                     f"{rays['planned'] / max(times['planned'] - times['off'], 1e-9) / 1e6:.2f} M rays/s"))
    pixel = scene.replace("interpolation", "pixel")
    view = SceneView(pixel, size=pixel_size, vectors="", labels=False, vtk_text=False, markers=False)
    try:
        gbuffer = view.gbuffer()
        covered = int(gbuffer.mask.sum())

        def pixels(scene):
            def job():
                shadows.forget()
                pixel_colors(scene, gbuffer, view.background)

            return job

        times = _medians({"on": pixels(pixel), "off": pixels(pixel.replace("shadows", False))}, repeats)
        rows.append(_row("per-pixel view: shadows on / off", times["on"], times["off"],
                         f"{pixel_size[0]}×{pixel_size[1]}, {covered:,} pixels shaded: {times['on'] * 1e3:.0f} ms "
                         f"against {times['off'] * 1e3:.0f} ms"))
    finally:
        view.close()
    return {"vertices": vertices, "repeats": repeats, "load": _load(), "cases": rows, "clock": "CPU time"}


def _rays(scene, scene_plan) -> int:
    """How many shadow rays a re-shade of the scene's vertices casts under ``scene_plan``."""
    from phonglab.render.objects import point_objects, scene_mesh

    ids = point_objects(scene_mesh(scene))
    return int(sum(np.isin(ids, pair.receivers).sum() for pair in scene_plan.traced))


def _row(case: str, time_a: float, time_b: float, note: str) -> dict:
    ratio = time_a / time_b
    target = TARGETS.get(case)
    return {"case": case, "ratio": ratio, "seconds": [time_a, time_b], "note": note, "target": target,
            "verdict": None if target is None else ("PASS" if ratio <= target else "MISS")}


def _load() -> str:
    try:
        return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:  # pragma: no cover - not every system has one
        return "load average unknown"


def format_report(result: dict) -> str:
    """The shadow figures as lines of the planner's report."""
    lines = [f"shadows (median CPU time of {max(result['repeats'], 16)} runs, 3 times as many for the convex object; "
             f"{result['load']} at the end):"]
    width = max(len(row["case"]) for row in result["cases"])
    for row in result["cases"]:
        target = f"  target <= {row['target']:.2f}: {row['verdict']}" if row["target"] is not None else ""
        lines.append(f"  {row['case'].ljust(width)}  {row['ratio']:.3f}{target}  ({row['note']})")
    return "\n".join(lines)
