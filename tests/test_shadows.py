"""Shadows: the kernels' visibility, the shadow rays cast with Embree, the planner's pairs, and the pictures.

The Done-when statements: the ball over the floor casts a shadow on the
floor in flat, Gouraud and per-pixel mode; with ``shadows = false`` the same
pixels are brighter and no pixel is brighter with shadows on; the planned
shadows equal the fully traced ones exactly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.scene import load_scene, plan

ROOT = Path(__file__).resolve().parent.parent
BALL = load_scene(ROOT / "assets" / "scenes" / "ball-over-floor.toml")
MODES = ("flat", "gouraud", "pixel")

MAT = pl.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=40)
LIGHTS = [pl.AmbientLight(intensity=0.3), pl.PointLight(position=(2, 2.5, 3), attenuation=(1, 0.1, 0)),
          pl.DirectionalLight(direction=(0, 0.3, 1)),
          pl.SpotLight(position=(2, 2, 3), direction=(-2, -2, -3), cutoff=40, exponent=2)]


def random_points(n, dtype, seed=0):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(n, 3)).astype(dtype), rng.normal(size=(n, 3)).astype(dtype)


# ---------------------------------------------------------------------------
# the core: visibility per light


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_a_light_seen_everywhere_shades_bit_for_bit_as_without_visibility(dtype):
    points, normals = random_points(70_000, dtype)  # more than one block of the fast kernel
    before = pl.shade(points, normals, eye=(0, 0, 4), material=MAT, lights=LIGHTS)
    seen = {1: np.ones(len(points), bool), 2: np.ones(len(points)), 3: True}
    after = pl.shade(points, normals, eye=(0, 0, 4), material=MAT, lights=LIGHTS, visibility=seen)
    for term in ("ambient", "diffuse", "specular", "color"):
        assert np.array_equal(getattr(before, term), getattr(after, term)), term


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_a_blocked_light_adds_nothing_and_the_kernels_agree(dtype):
    points, normals = random_points(5_000, dtype, seed=1)
    rng = np.random.default_rng(2)
    seen = {1: rng.random(len(points)) < 0.5, 3: rng.random(len(points)) < 0.5}
    fast = pl.shade(points, normals, eye=(0, 0, 4), material=MAT, lights=LIGHTS, visibility=seen)
    ref, record = pl.shade_reference(points, normals, eye=(0, 0, 4), material=MAT, lights=LIGHTS,
                                     visibility=seen, trace=True)
    tol = 1e-4 if dtype == np.float32 else 1e-10
    assert np.abs(fast.color - ref.color).max() < tol
    # where light 1 is blocked, the scene shades as if it were off (light 3 is blocked as given too)
    dark = [LIGHTS[0], pl.PointLight(position=(2, 2.5, 3), intensity=0, attenuation=(1, 0.1, 0))] + LIGHTS[2:]
    off = pl.shade(points, normals, eye=(0, 0, 4), material=MAT, lights=dark, visibility={3: seen[3]})
    blocked = ~seen[1]
    assert np.array_equal(fast.color[blocked], off.color[blocked])
    light = record.light(1)
    assert np.array_equal(light["lit"], seen[1])
    assert light.terms["diffuse"][:2] == ("if", ("lit",)) and "lit" not in record.light(2).values
    assert np.all(light["diffuse"][blocked] == 0) and np.all(light["specular"][blocked] == 0)


@pytest.mark.parametrize("visibility, message", [
    ({0: [1.0]}, "ambient light is not blocked"),
    ({9: [1.0]}, "must be the index of a light, 0 to 3"),
    ({1: [0.5]}, r"visibility\[1\]: must hold only 0 and 1"),
    ({1: np.ones(3)}, r"visibility\[1\]: must broadcast to the points' shape \(2,\)"),
    ([1], "must map light indices to arrays"),
])
def test_a_bad_visibility_is_refused_naming_it(visibility, message):
    points, normals = random_points(2, np.float64)
    for kernel in (pl.shade, pl.shade_reference):
        with pytest.raises(ValueError, match=message):
            kernel(points, normals, eye=(0, 0, 4), material=MAT, lights=LIGHTS, visibility=visibility)


def test_a_shadow_ray_starts_bias_along_l_and_stops_at_the_light():
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    origins, directions, lengths = pl.shadow_rays(points, pl.PointLight(position=(0, 0, 2)), bias=0.5)
    assert np.allclose(origins[0], [0, 0, 0.5]) and np.allclose(directions[0], [0, 0, 1])
    assert np.isclose(lengths[0], 1.5) and np.isclose(lengths[1], np.sqrt(5) - 0.5)
    _, directions, lengths = pl.shadow_rays(points, pl.DirectionalLight(direction=(0, 0, 3)), bias=0.0)
    assert np.allclose(directions, [0, 0, 1]) and np.all(lengths >= 1e29)
    _, _, lengths = pl.shadow_rays(points[:1], pl.PointLight(position=(0, 0, 0.1)), bias=0.5)
    assert lengths[0] == 0  # the light within the bias: nothing can block it


# ---------------------------------------------------------------------------
# the pictures: the Done-when statements


@pytest.fixture(scope="module")
def view():
    from phonglab.render import SceneView

    v = SceneView(BALL, size=(320, 240), vectors="", labels=False, vtk_text=False, markers=False)
    yield v
    v.close()


def picture(view, scene):
    view.update(scene)
    return view.screenshot(annotate=False).astype(int), view.gbuffer()


@pytest.mark.parametrize("mode", MODES)
def test_the_ball_casts_a_shadow_on_the_floor_and_no_pixel_gets_brighter(view, mode):
    on, gbuffer = picture(view, BALL.replace_many([("interpolation", mode), ("shadows", True)]))
    off, _ = picture(view, BALL.replace_many([("interpolation", mode), ("shadows", False)]))
    brighter = (on > off).any(axis=-1)
    assert not brighter.any(), (mode, np.argwhere(brighter)[:5], on[brighter][:5], off[brighter][:5])
    floor = gbuffer.objects == 1
    darker = floor & ((off - on).max(axis=-1) >= 40)  # the lamp's light taken away: far below rounding
    assert darker.sum() > 0.05 * floor.sum(), (mode, darker.sum(), floor.sum())
    # the darker pixels are the floor points whose line to the lamp crosses the ball (the exact sphere)
    # (per face and per vertex the shadow's edge is a floor triangle wide: most, not all, lie inside)
    inside = exact_shadow(gbuffer.positions[darker])
    assert inside.mean() > (0.97 if mode == "pixel" else 0.9), (mode, inside.mean())


def exact_shadow(points) -> np.ndarray:
    """Whether the segment from each point to the lamp crosses the exact sphere the ball's mesh stands for."""
    lamp = np.asarray(BALL.lights[1].position, dtype=np.float64)
    centre, radius = np.asarray(BALL.geometry.center), BALL.geometry.scale
    d = lamp - points
    length = np.linalg.norm(d, axis=1)
    d = d / length[:, None]
    t = np.clip(np.einsum("ij,ij->i", centre - points, d), 0, length)  # the segment's point nearest the centre
    nearest = points + t[:, None] * d
    return np.linalg.norm(nearest - centre, axis=1) < radius


def test_with_shadows_off_the_floor_under_the_ball_is_as_bright_as_without_the_ball(view):
    from phonglab.scene import scene_to_dict

    lone = BALL.replace("objects", scene_to_dict(BALL)["objects"][1:])  # the floor alone
    off, gbuffer = picture(view, BALL.replace("shadows", False))
    alone, _ = picture(view, lone.replace("shadows", False))
    floor = gbuffer.objects == 1
    assert np.abs(off[floor] - alone[floor]).max() <= 1  # without shadows the ball takes no light from the floor


# ---------------------------------------------------------------------------
# the planner: a skipped pair casts nothing


def scenes_to_plan():
    low = BALL.replace("lights[1].position", [0.5, 0.2, -2.0])  # the lamp under the floor
    spot_away = BALL.replace("lights[1]", {"type": "spot", "position": [3, 0, 1], "direction": [1, 0, 0],
                                           "cutoff": 20})  # aimed away from both
    spot_floor = BALL.replace("lights[1]", {"type": "spot", "position": [0, 0, 3], "direction": [0, 0, -1],
                                            "cutoff": 40, "exponent": 1})
    sun = BALL.replace("lights[1]", {"type": "directional", "direction": [0.4, -0.3, 1]})
    torus = BALL.replace_many([("objects[0].geometry.kind", "torus"), ("objects[0].geometry.center", [0, 0, 0.5])])
    two_lamps = BALL.replace("lights", [{"type": "ambient", "intensity": 0.2},
                                        {"type": "point", "position": [2, -1.5, 5]},
                                        {"type": "point", "position": [-3, 1, 0.5]}])
    return {"ball": BALL, "lamp below": low, "spot away": spot_away, "spot on floor": spot_floor, "sun": sun,
            "torus": torus, "two lamps": two_lamps}


@pytest.mark.parametrize("name", list(scenes_to_plan()))
def test_planned_shadows_equal_the_fully_traced_ones_exactly(name):
    from phonglab.render import shadows
    from phonglab.render.objects import cell_objects, point_objects, scene_mesh
    from phonglab.render.shading import _faces

    from phonglab.scene import shade

    scene = scenes_to_plan()[name]
    mesh = scene_mesh(scene)
    centroids, face_normals = _faces(mesh)
    normals = np.asarray(mesh.point_data["Normals"])
    for points, n, ids in ((np.asarray(mesh.points), normals, point_objects(mesh)),
                           (centroids, face_normals, cell_objects(mesh))):
        planned = shadows.visibility(scene, points, ids)
        full = shadows.visibility(scene, points, ids, full=True)
        a = shade(scene, points, n, objects=ids, visibility=planned)
        b = shade(scene, points, n, objects=ids, visibility=full)
        assert np.array_equal(a.color, b.color), (name, int((a.color != b.color).any(axis=-1).sum()))
        assert full is not None or name == "spot away", name  # the full trace does trace something


def test_the_planner_skips_what_cannot_cast_and_says_why():
    pairs = {(p.light, p.occluder): p for p in plan(BALL).shadows}
    assert pairs[(1, 0)].traced and pairs[(1, 0)].receivers == (1,)  # the ball on the floor
    assert not pairs[(1, 1)].traced  # the floor, under both, casts nothing towards the lamp above
    reasons = dict(pairs[(1, 1)].reasons)
    assert "a plane separates them" in reasons[0] and "cannot shadow itself" in reasons[1]
    lone = plan(load_scene(ROOT / "assets" / "scenes" / "sphere.toml").replace("shadows", True))
    assert lone.shadows and not lone.traced  # one convex object: nothing to trace
    torus = plan(scenes_to_plan()["torus"])
    assert any(p.occluder == 0 and 0 in p.receivers for p in torus.traced)  # a torus may shadow itself
    away = plan(scenes_to_plan()["spot away"])
    assert not away.traced and any("outside the spot's cone" in why for p in away.shadows for _, why in p.reasons)


def test_a_convex_object_shadows_nothing_its_n_dot_l_gate_does_not_darken():
    # flat shading: the facets' own normals, the polytope's own rays; its own triangles cast exactly the gate
    from phonglab.render.objects import object_triangles
    from phonglab.render.shading import _faces
    from phonglab.render.shadows import Caster
    from phonglab.render.objects import scene_mesh

    sphere = load_scene(ROOT / "assets" / "scenes" / "sphere.toml")
    mesh = scene_mesh(sphere)
    centroids, normals = _faces(mesh)
    caster = Caster(mesh)
    for light in (pl.PointLight(position=(2, 2.5, 3)), pl.DirectionalLight(direction=(-1, 0.2, 0.4))):
        origins, directions, lengths = pl.shadow_rays(centroids, light, bias=1e-4)
        blocked = caster.occluded(0, origins, directions, lengths)
        nl = np.einsum("ij,ij->i", normals.astype(np.float64), directions.astype(np.float64))
        facing = nl > 1e-3
        assert not blocked[facing].any(), (light, int(blocked[facing].sum()))
        assert blocked[nl < -1e-3].all(), light  # and it does block every ray into the solid
    assert len(object_triangles(mesh, 0)) == mesh.n_cells


# ---------------------------------------------------------------------------
# the bias: acne below, leaking above


def test_no_bias_shows_acne_on_a_surface_that_shadows_itself_and_a_small_one_does_not(view):
    torus = BALL.replace_many([("objects[0].geometry.kind", "torus"), ("objects[0].geometry.center", [0, 0, 0.6]),
                               ("interpolation", "pixel")])
    from phonglab.render import shadows

    view.update(torus)
    gbuffer = view.gbuffer()
    on_torus = gbuffer.objects == 0
    points, ids = gbuffer.positions[on_torus], gbuffer.objects[on_torus]
    lamp = np.asarray(torus.lights[1].position)
    to_lamp = (lamp - points) / np.linalg.norm(lamp - points, axis=1, keepdims=True)
    facing = np.einsum("ij,ij->i", gbuffer.normals[on_torus], to_lamp) > 0.5  # well lit, never self-shadowed
    fraction = {}
    for bias in (0.0, 1e-3):
        seen = shadows.visibility(torus.replace("shadow_bias", bias), points, ids)[1]
        fraction[bias] = float((~seen[facing]).mean())
    assert fraction[0.0] > 0.2 and fraction[1e-3] < 0.005, fraction


def test_a_bias_larger_than_the_gap_lets_light_leak_under_a_thin_card():
    from phonglab.render import shadows

    card = BALL.replace_many([("objects[0].geometry.kind", "plane"), ("objects[0].geometry.center", [0, 0, 0.3]),
                              ("objects[0].geometry.scale", 0.5)])
    under = np.array([[-0.2, 0.15, 0.0]])  # on the floor, in the card's shadow
    seen = {bias: bool(shadows.visibility(card.replace("shadow_bias", bias), under, [1])[1][0])
            for bias in (0.001, 0.1, 0.5)}
    assert seen == {0.001: False, 0.1: False, 0.5: True}, seen


# ---------------------------------------------------------------------------
# the page: the readout's line per light, the switch and the offset


def test_the_readout_says_per_light_lit_or_in_shadow_and_names_the_blocker(view):
    from phonglab.app.readout import probe_readout

    view.update(BALL)
    point, normal = view.probe
    assert abs(point[2]) < 1e-6, point  # the lesson's probe: on the floor, in the ball's shadow
    out = probe_readout(BALL, point, normal, view.light_index)
    assert out["shadows"] == [{"light": "light 1", "state": "in shadow", "blocker": "ball",
                               "text": out["notes"][0]}], out["shadows"]
    assert "blocked by the ball" in out["notes"][0] and "on the floor" in out["notes"][1]
    terms = {t["name"]: t["value"] for t in out["terms"]}
    assert terms["diffuse"] == terms["specular"] == "(0.000, 0.000, 0.000)", terms
    lit = probe_readout(BALL.replace("shadows", False), point, normal, view.light_index)
    assert lit["shadows"] == [] and float(lit["terms"][1]["value"].strip("()").split(",")[0]) > 0.1, lit["terms"]
    beside = BALL.replace("probe", [2.0, -2.0, 0.0])  # on the floor, in the open
    view.update(beside)
    out = probe_readout(beside, *view.probe, view.light_index)
    assert out["shadows"][0]["state"] == "lit" and out["shadows"][0]["blocker"] is None, out["shadows"]


def test_the_shadow_switch_and_the_offset_are_controls_a_lesson_can_list():
    from phonglab.app.controls import lesson_controls, scene_controls

    controls = {c.path: c for c in scene_controls(BALL)}
    switch, offset = controls["shadows"], controls["shadow_bias"]
    assert switch.kind == "switch" and offset.kind == "slider" and offset.low == 0.0
    assert switch.read(BALL, {}) is True
    off, _ = switch.write(BALL, False, {})
    assert off.shadows is False and off.objects == BALL.objects
    moved, _ = offset.write(BALL, 0.25, {})
    assert moved.shadow_bias == 0.25
    assert [c.path for c in lesson_controls(list(controls.values()), ["shadows", "shadow_bias"])] == [
        "shadows", "shadow_bias"]


def test_the_plan_lists_the_traced_and_the_skipped_pairs():
    lines = plan(BALL).as_dict()
    computed = {line["effect"]: line["reason"] for line in lines["computed"]}
    skipped = {line["effect"]: line["reason"] for line in lines["skipped"]}
    assert "rays from the floor" in computed["shadow of the ball from light 1"], computed
    assert "cannot shadow itself" in skipped["shadow of the floor from light 1"], skipped
    assert "shadows are off" in {e: r for e, r in (
        (x["effect"], x["reason"]) for x in plan(BALL.replace("shadows", False)).as_dict()["skipped"])}["shadows"]


# ---------------------------------------------------------------------------
# exports: phonglab export, in the three modes, and a sweep over the switch


@pytest.mark.parametrize("mode", MODES)
def test_an_export_shows_the_shadow_and_no_pixel_is_brighter_with_it(tmp_path, mode):
    from PIL import Image

    from phonglab.cli import main

    scene = ROOT / "assets" / "scenes" / "ball-over-floor.toml"
    images = {}
    for shadows in ("true", "false"):
        out = tmp_path / f"{mode}-{shadows}.png"
        assert main(["export", str(scene), "-o", str(out), "--size", "200x150", "--supersample", "1", "--vectors", "",
                     "--set", f"interpolation={mode}", "--set", f"shadows={shadows}"]) == 0
        with Image.open(out) as img:
            images[shadows] = np.asarray(img.convert("RGB")).astype(int)
    on, off = images["true"], images["false"]
    assert not (on > off).any(axis=-1).any(), mode
    assert ((off - on).max(axis=-1) >= 40).mean() > 0.02, mode


def test_a_sweep_over_the_switch_and_the_offset_exports(tmp_path):
    from phonglab.cli import main

    out = tmp_path / "sweep.png"
    assert main(["export", str(ROOT / "assets" / "scenes" / "ball-over-floor.toml"), "-o", str(out), "--size",
                 "120x90", "--supersample", "1", "--sweep", "shadows=true,false",
                 "--sweep", "shadow_bias=0.001,0.5"]) == 0
    assert out.stat().st_size > 1000
