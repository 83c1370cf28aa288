"""SceneView: in-place updates, vectors at the probe, markers, picking, pixel-mode compositing."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

vtk = pytest.importorskip("vtk")

import phonglab as pl  # noqa: E402
from phonglab.render.view import BACKGROUND, SceneView  # noqa: E402
from phonglab.bench import scenes  # noqa: E402
from phonglab.scene import Camera, Geometry, Scene  # noqa: E402

SIZE = (200, 150)


def red_sphere(**changes) -> Scene:
    # the shared red sphere, with the default camera
    scene = scenes.red_sphere(24, camera=Camera(), probe=(0.35, 0.45, 0.82))
    for path, value in changes.items():
        scene = scene.replace(path.replace("__", "."), value)
    return scene


@pytest.fixture
def view():
    v = SceneView(red_sphere(), size=SIZE)
    yield v
    v.close()


def props(view):
    collection = view.renderer.GetViewProps()
    return [collection.GetItemAsObject(i) for i in range(collection.GetNumberOfItems())]


def test_slider_moves_change_colours_in_place_without_new_actors(view):
    before = props(view)
    array = view.mesh.GetPointData().GetArray("rgb")
    colours = np.array(view.mesh.point_data["rgb"])
    for scene in (red_sphere(material__ks=0.1), red_sphere(material__shininess=5),
                  red_sphere(**{"lights[1].position": [-2, 1, 3]}), red_sphere(model="blinn-phong")):
        view.update(scene)
    after = props(view)
    assert [id(p) for p in after] == [id(p) for p in before], f"{len(before)} props became {len(after)}"
    assert view.mesh.GetPointData().GetArray("rgb") is array, "the colour array was replaced, not updated"
    assert not np.array_equal(colours, np.asarray(view.mesh.point_data["rgb"])), "colours did not change"


def test_every_actor_has_lighting_off_and_colours_from_arrays(view):
    view.update(red_sphere(**{"lights[1]": {"type": "spot", "position": [2, 2, 3], "direction": [-2, -2, -3],
                                             "cutoff": 25}}))
    actors = [p for p in props(view) if isinstance(p, vtk.vtkActor)]
    assert len(actors) >= 7, f"only {len(actors)} actors"
    for actor in actors:
        assert not actor.GetProperty().GetLighting(), f"{actor} has VTK lighting on"
        data = actor.GetMapper().GetInput()
        if data.GetNumberOfPoints():
            scalars = data.GetPointData().GetScalars() or data.GetCellData().GetScalars()
            assert scalars is not None and scalars.GetNumberOfComponents() == 3, f"{actor}: no RGB scalars"
            assert scalars.GetDataTypeAsString() == "unsigned char", scalars.GetDataTypeAsString()


def test_vectors_at_probe_are_the_core_vectors(view):
    vec = view.probe_vectors
    point, normal = view.probe
    expected = pl.vectors(point, normal, eye=(0, 0, 4), light=view.scene.lights[1])
    for name in "nlrvh":
        assert np.allclose(getattr(vec, name), getattr(expected, name)), f"{name}: {getattr(vec, name)}"
    # each arrow starts at the probe and points along its vector
    for letter, (data, actor) in view.glyph_actors.arrows.items():
        assert actor.GetVisibility()
        pts = np.asarray(data.GetPoints().GetData())
        d = getattr(vec, letter.lower())
        along = (pts - point) @ d
        assert along.min() > -0.01 and abs(along.max() - view.arrow_length) < 0.01, f"{letter}: {along.min()}"


def test_set_probe_moves_the_arrows_to_the_nearest_surface_point(view):
    view.set_probe((-3.0, 0.0, 0.0))
    point, normal = view.probe
    assert point[0] < -0.99 and normal[0] < -0.99, f"probe {point}, normal {normal}"
    pts = np.asarray(view.glyph_actors.arrows["N"].data.GetPoints().GetData())
    assert pts[:, 0].min() < -1 - 0.9 * view.arrow_length, f"the N arrow did not move: x from {pts[:, 0].min()}"
    view.set_probe(None)  # default: where the eye's line of sight hits
    assert view.probe[0][2] > 0.99, f"default probe {view.probe[0]}"


def test_choosing_vectors_hides_the_others(view):
    view.set_vectors("N,V")
    shown = {letter for letter, (_, actor) in view.glyph_actors.arrows.items() if actor.GetVisibility()}
    assert shown == {"N", "V"}, shown
    assert [e[0] for e in view.legend()] == ["N", "V"]
    with pytest.raises(ValueError, match="Q"):
        view.set_vectors("NQ")


def test_light_markers_match_light_kinds(view):
    # a spot the view takes in whole (one farther out is left out of the picture: the test below)
    position = np.array([1.3, 0.8, 1.2])
    view.update(red_sphere(**{"lights[1]": {"type": "spot", "position": position.tolist(),
                                             "direction": (-position).tolist(), "cutoff": 25}}))
    data, actor = view.glyph_actors.light_markers[1]
    assert actor.GetVisibility()
    pts = np.asarray(data.GetPoints().GetData())
    # a cone: the apex at the light, opening along the axis (away from the light)
    axis = -position / np.linalg.norm(position)
    along = (pts - position) @ axis
    assert along.max() > 0.2 and along.min() > -0.05, f"cone spans {along.min()}..{along.max()} along the axis"
    assert not view.glyph_actors.light_markers[0].actor.GetVisibility(), "the ambient light has a marker"



def test_a_light_marker_the_view_cannot_take_in_whole_is_left_out_not_cut_at_the_edge(tmp_path):
    """The torus's directional light: its arrows stuck into the picture's top edge, half drawn, in every export."""
    from PIL import Image

    from phonglab.render import figure
    from phonglab.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "assets" / "scenes" / "torus.toml")
    out = figure(scene, tmp_path / "torus.png", size=(400, 300))
    with Image.open(out) as img:
        picture = np.asarray(img.convert("RGB")).astype(int)
    background = np.rint(np.asarray(BACKGROUND) * 255)
    edges = {"top": picture[:3], "bottom": picture[-3:], "left": picture[:, :3], "right": picture[:, -3:]}
    drawn = {side: int((np.abs(band - background).max(axis=-1) > 30).sum()) for side, band in edges.items()}
    assert not any(drawn.values()), f"pixels drawn at the picture's edges (not background {background}): {drawn}"
    # and a marker that fits is drawn: the same light from over the eye's shoulder
    view = SceneView(scene.replace("lights[1].direction", [0.4, -1.0, 1.2]), size=(400, 300))
    try:
        assert view.glyph_actors.light_markers[1].actor.GetVisibility(), "the framed marker is hidden"
    finally:
        view.close()

def test_eye_marker_only_when_the_camera_leaves_the_eye(view):
    view.render()
    assert not view.glyph_actors.eye.actor.GetVisibility(), "eye marker shown while the camera sits at the eye"
    view.renderer.GetActiveCamera().Azimuth(60)
    view.render()
    assert view.glyph_actors.eye.actor.GetVisibility(), "eye marker hidden after orbiting"


def test_pick_returns_surface_point_or_none(view):
    view.render()
    hit = view.pick(SIZE[0] / 2, SIZE[1] / 2)
    assert hit is not None and abs(np.linalg.norm(hit) - 1) < 0.02 and hit[2] > 0.9, f"picked {hit}"
    assert view.pick(1, 1) is None, "picked something in the corner"


def test_pixel_mode_draws_arrows_over_the_shaded_mesh():
    scene = red_sphere(interpolation="pixel")
    with_arrows = SceneView(scene, size=SIZE, labels=False)
    without = SceneView(scene, size=SIZE, vectors=None, labels=False)
    try:
        a = with_arrows.screenshot(annotate=False)
        mesh_only = with_arrows.pixel_image()  # the same camera, no glyphs
        b = without.screenshot(annotate=False)
        shaded = without.pixel_image()
    finally:
        with_arrows.close()
        without.close()
    assert np.array_equal(b, shaded), "pixel mode without glyphs is not the per-pixel image"
    changed = np.any(a != mesh_only, axis=-1)
    assert 0.002 * changed.size < changed.sum() < 0.2 * changed.size, f"{changed.sum()} pixels show glyphs"
    # the arrow colours appear (the relief shades them, so look for their hue: bright yellow L)
    yellowish = (a[..., 0] > 150) & (a[..., 1] > 150) & (a[..., 2] < 90)
    assert yellowish.sum() > 5, "the yellow L arrow is not visible in pixel mode"


def test_terms_add_up_to_the_colour():
    # the terms add up in linear light: shown raw (display = "linear") their bytes add up too
    scene = red_sphere(interpolation="gouraud").replace("display", "linear")
    view = SceneView(scene, size=SIZE, vectors=None)
    try:
        parts = {}
        for term in ("ambient", "diffuse", "specular", "color"):
            view.set_term(term)
            parts[term] = np.asarray(view.mesh.point_data["rgb"]).astype(int)
    finally:
        view.close()
    total = parts["ambient"] + parts["diffuse"] + parts["specular"]
    unclipped = parts["color"] < 255
    err = np.abs(total - parts["color"])[unclipped].max()
    assert err <= 2, f"ambient + diffuse + specular differs from the colour by {err}/255 (rounding allows 2)"
    assert parts["specular"].max() > 100 and parts["ambient"].max() < 20, "terms look swapped"


def test_screenshot_writes_png(tmp_path, view):
    from PIL import Image

    path = tmp_path / "shot.png"
    image = view.screenshot(path)
    with Image.open(path) as saved:
        assert saved.size == SIZE and np.array_equal(np.asarray(saved.convert("RGB")), image)
    assert [p.name for p in tmp_path.iterdir()] == ["shot.png"], "a temporary file was left behind"


def test_geometry_change_keeps_the_actor_and_resizes_arrays(view):
    actor_count = len(props(view))
    view.update(red_sphere(geometry__kind="torus"))
    assert len(props(view)) == actor_count
    assert view.mesh.point_data["rgb"].shape == (view.mesh.n_points, 3)
    assert view.mesh_actor.GetMapper().GetInput() is view.mesh


def test_without_vtk_text_only_geometry_actors_remain_and_screenshots_keep_labels():
    scene = red_sphere()
    plain = SceneView(scene, size=SIZE, vtk_text=False)
    texty = SceneView(scene, size=SIZE)
    try:
        kinds = {p.GetClassName() for p in props(plain)}
        assert all(isinstance(p, vtk.vtkActor) for p in props(plain)), f"props without VTK text: {kinds}"
        assert any(isinstance(p, vtk.vtkBillboardTextActor3D) for p in props(texty)), "no VTK letters by default"
        a, b = plain.screenshot(), texty.screenshot()
    finally:
        plain.close()
        texty.close()
    # the letters and legend are drawn on the image either way, identically
    assert np.array_equal(a, b), "VTK text actors leaked into the screenshot"
    assert [e[0] for e in plain.legend()] == list("NLRVH")


ROOT = Path(__file__).resolve().parents[1]
FRAMED = ["assets/scenes/sphere.toml", "lessons/01-light-and-surfaces.md", "lessons/04-specular.md",
          "lessons/07-light-sources.md", "lessons/09-two-sided-and-hard-cases.md"]


@pytest.mark.parametrize("size", [(800, 600), (300, 480)])
@pytest.mark.parametrize("source", FRAMED)
def test_arrow_tips_and_letters_stay_inside_the_window(source, size):
    from phonglab.render.options import resolve_scene

    scene = resolve_scene(ROOT / source)
    view = SceneView(scene, size=size)
    try:
        view.render()
        camera = view.renderer.GetActiveCamera()
        marks = view.vector_marks()
        angle = camera.GetViewAngle()
        eye, focal = np.array(camera.GetPosition()), np.array(camera.GetFocalPoint())
        # each light marker's centre on the image, and its radius in pixels there
        markers = []
        for centre, radius in view._glyphs.marker_balls():
            x, y = view.to_image(centre, size[1])
            right = np.cross(focal - eye, camera.GetViewUp())
            edge = view.to_image(centre + radius * right / np.linalg.norm(right), size[1])
            markers.append((x, y, float(np.hypot(edge[0] - x, edge[1] - y))))
    finally:
        view.close()
    width, height = size
    where = f"{source} at {width}x{height}, view angle {angle:.1f} (scene {scene.camera.view_angle})"
    assert set(marks) == set("NLRVH"), f"{where}: marks for {sorted(marks)}"
    for letter, ((x, y), (left, top, right, bottom)) in marks.items():
        assert 0 <= x <= width and 0 <= y <= height, f"{where}: the {letter} tip at ({x:.0f}, {y:.0f})"
        assert left >= 0 and top >= 0 and right <= width and bottom <= height, (
            f"{where}: the letter {letter} spans x {left:.0f}..{right:.0f}, y {top:.0f}..{bottom:.0f}")
    # the camera keeps the scene's eye and direction; only the view angle may grow
    assert np.allclose(eye, scene.camera.eye) and np.allclose(focal, scene.camera.focal_point), where
    assert angle >= scene.camera.view_angle - 1e-9, where
    if angle > scene.camera.view_angle + 1e-6:
        # widened only as far as needed: some letter or light marker comes close to an edge
        gaps = [min(left, top, width - right, height - bottom) for _, (left, top, right, bottom) in marks.values()]
        gaps += [min(x - r, y - r, width - x - r, height - y - r) for x, y, r in markers]
        assert min(gaps) < 0.1 * min(size), (
            f"{where}: widened although every letter and marker is {min(gaps):.0f} px inside")
    for x, y, r in markers:  # a marker is whole in the window, or wholly outside it
        inside = r <= x <= width - r and r <= y <= height - r
        outside = x < -r or x > width + r or y < -r or y > height + r
        assert inside or outside or r > 0.25 * min(size), f"{where}: a light marker at ({x:.0f}, {y:.0f}), " \
            f"radius {r:.0f} px, is cut by the window's edge"


def test_view_angle_is_the_scenes_without_arrows_and_follows_the_vectors_shown():
    scene = red_sphere(camera={"eye": [0, 0, 3.2]})  # close enough that the arrows leave the scene's frame
    view = SceneView(scene, size=(400, 300), vectors=None)
    try:
        view.render()
        plain = view.renderer.GetActiveCamera().GetViewAngle()
        before = len(props(view))
        view.set_vectors("NLRVH")
        view.render()
        widened = view.renderer.GetActiveCamera().GetViewAngle()
        view.update(scene.replace("material.ks", 0.1))  # a material change never refits
        same = view.renderer.GetActiveCamera().GetViewAngle()
        view.set_vectors(None)
        view.render()
        back = view.renderer.GetActiveCamera().GetViewAngle()
        after = len(props(view))
    finally:
        view.close()
    assert plain == scene.camera.view_angle, f"no arrows, yet the view angle is {plain}"
    assert widened > plain + 1, f"arrows shown close up, yet the view angle stayed {widened}"
    assert same == widened, f"a material change moved the view angle from {widened} to {same}"
    assert back == plain, f"arrows hidden again, yet the view angle is {back}"
    assert after == before, f"{before} props became {after}"


def test_a_camera_set_from_outside_keeps_its_view_angle():
    # the web app copies the browser's camera (position and view angle) in before a pixel-mode image
    scene = red_sphere(camera={"eye": [0, 0, 3.2]})
    view = SceneView(scene, size=(400, 300))
    try:
        camera = view.renderer.GetActiveCamera()
        camera.SetPosition(1.0, 0.5, 3.0)
        camera.SetViewAngle(24.0)
        view.update(scene.replace("lights[1].position", [-2, 2.5, 3]))  # the arrows L, R, H move
        view.screenshot(annotate=False)
        kept = camera.GetViewAngle()
        view.update(scene.replace("camera.eye", [0, 0, 3.0]))  # the scene's own camera again
        view.render()
        refit = camera.GetViewAngle()
        position = camera.GetPosition()
    finally:
        view.close()
    assert kept == 24.0, f"the outside camera's view angle became {kept}"
    assert np.allclose(position, (0, 0, 3.0)) and refit > scene.camera.view_angle, (
        f"back on the scene's camera at {position}, the view angle is {refit}")


def test_colour_array_is_the_array_vtk_draws_from_per_point_or_per_cell(view):
    colours = view.colour_array()
    assert (colours.name, colours.location) == ("rgb", "point")
    assert colours.values.shape == (view.mesh.n_points, 3) and colours.values.dtype == np.uint8
    before = np.array(colours.values)
    view.update(red_sphere(material__ks=0.0))
    assert not np.array_equal(colours.values, before), "the colour array seen before the update did not change"
    flat = red_sphere(interpolation="flat")
    view.update(flat)
    colours = view.colour_array()
    assert colours.location == "cell" and colours.values.shape == (view.mesh.n_cells, 3)
    mapper = view.mesh_actor.GetMapper()
    assert mapper.GetScalarMode() == vtk.VTK_SCALAR_MODE_USE_CELL_DATA
    assert mapper.GetInput().GetCellData().GetArray(colours.name).GetNumberOfTuples() == view.mesh.n_cells


def test_set_camera_moves_the_picture_and_reset_camera_brings_the_scenes_back():
    scene = red_sphere(interpolation="pixel")
    view = SceneView(scene, size=SIZE)
    try:
        start = view.camera_state()
        own = view.pixel_image()
        view.set_camera(eye=(2.0, 1.0, 3.0), focal_point=(0, 0, 0), up=(0, 1, 0), view_angle=25.0)
        moved = view.camera_state()
        turned = view.pixel_image()
        view.reset_camera()
        back = view.camera_state()
        again = view.pixel_image()
    finally:
        view.close()
    assert start.eye == pytest.approx(scene.camera.eye) and start.focal_point == pytest.approx(scene.camera.focal_point)
    assert moved.eye == pytest.approx((2.0, 1.0, 3.0)) and moved.view_angle == 25.0, moved
    assert np.dot(moved.up, np.subtract(moved.focal_point, moved.eye)) == pytest.approx(0.0, abs=1e-9), moved
    assert not np.array_equal(own, turned), "the per-pixel image did not follow the camera"
    assert back == start, f"reset_camera gave {back}, the scene's camera was {start}"
    assert np.array_equal(own, again), "after reset_camera the picture differs from the scene's"


@pytest.mark.parametrize("kwargs, says", [
    ({"eye": (0, 0, float("nan"))}, "eye"),
    ({"eye": (0, 0)}, "eye"),
    ({"focal_point": "origin"}, "focal_point"),
    ({"eye": (0, 0, 0)}, "focal_point"),
    ({"up": (0, 0, 2)}, "up"),
    ({"view_angle": 0}, "view_angle"),
    ({"view_angle": 180}, "view_angle"),
    ({"view_angle": "wide"}, "view_angle"),
])
def test_set_camera_refuses_bad_values_and_keeps_the_camera(view, kwargs, says):
    before = view.camera_state()
    args = {"eye": (0, 0, 5), "focal_point": (0, 0, 0), "up": (0, 1, 0), "view_angle": 30.0, **kwargs}
    with pytest.raises(ValueError, match=says):
        view.set_camera(**args)
    assert view.camera_state() == before, f"{kwargs} moved the camera"


def test_ray_hit_finds_the_first_surface_point_or_none(view):
    point, normal = view.ray_hit((0.0, 0.0, 4.0), (0.2, 0.1, 0.0))
    assert point[2] > 0.9 and abs(np.linalg.norm(point) - 1.0) < 0.02, point
    assert normal @ (point / np.linalg.norm(point)) > 0.99, (point, normal)
    assert view.ray_hit((0.0, 0.0, 4.0), (3.0, 0.0, 4.0)) is None
    with pytest.raises(ValueError, match="origin"):
        view.ray_hit((0.0, float("inf"), 4.0), (0, 0, 0))


def floor_under_a_panel(**changes) -> Scene:
    """A floor lit only by a warm 0.8 × 0.6 ceiling panel at height 1.2, shining down."""
    from phonglab.scene.model import AreaLightSetup

    scene = Scene(
        geometry=Geometry("plane", 8),
        material=pl.Material(ka=0.1, kd=0.8, ks=0.0, shininess=10),
        lights=(pl.AmbientLight(intensity=0.1),),
        camera=Camera(eye=(0.0, -3.0, 0.6), focal_point=(0.0, 0.0, 0.6), up=(0.0, 0.0, 1.0)),
        area_light=AreaLightSetup(pl.AreaLight(position=(0.0, 0.0, 1.2), edge_u=(0.8, 0.0, 0.0),
                                               edge_v=(0.0, -0.6, 0.0), color=(1.0, 0.8, 0.4))),
    )
    for path, value in changes.items():
        scene = scene.replace(path.replace("__", "."), value)
    return scene


def test_an_area_light_is_drawn_as_a_flat_panel_where_it_is():
    scene = floor_under_a_panel()
    view = SceneView(scene, size=SIZE, vectors="")
    try:
        data, actor = view.glyph_actors.area_panel
        assert actor.GetVisibility() and not actor.GetProperty().GetLighting()
        points = np.asarray(data.GetPoints().GetData())
        colours = np.asarray(data.GetPointData().GetArray("rgb"))
        # the emitting face is the light's rectangle, in its colour at full brightness (linear (1, 0.8, 0.4)
        # shown as sRGB); the rest lies behind it
        lit = np.all(colours == (255, 231, 170), axis=1)
        corners = sorted(tuple(np.round(p, 9)) for p in points[lit])
        assert corners == sorted((x, y, 1.2) for x in (-0.4, 0.4) for y in (-0.3, 0.3)), points[lit]
        assert np.all(colours[~lit] == (72, 74, 82)), colours[~lit]
        assert np.all((points[:, 2] >= 1.2 - 1e-9) & (points[:, 2] <= 1.2 + 0.03 * 0.8 + 1e-9)), points
        assert np.ptp(points[:, 2]) == pytest.approx(0.03 * 0.8), "the panel is not as thick as it should be"
        # seen from below the panel's plane, its centre shows the flat light colour
        image = view.screenshot(annotate=False)
        x, y = view.to_image((0.0, 0.0, 1.2))
        assert tuple(image[int(round(y)), int(round(x))]) == (255, 231, 170), (x, y, image[int(round(y)), int(round(x))])
        # moving the light moves the panel, in place; the shading follows
        before_props, before_colours = len(props(view)), np.array(view.colour_array().values)
        view.update(scene.replace("area_light.position", [0.3, 0.0, 1.0]))
        moved = np.asarray(view.glyph_actors.area_panel.data.GetPoints().GetData())
        assert np.allclose(moved.mean(axis=0)[:2], (0.3, 0.0), atol=1e-9) and len(props(view)) == before_props
        assert not np.array_equal(view.colour_array().values, before_colours), "the floor's shading ignored the move"
        # no area light, no panel
        view.update(dataclasses.replace(scene, area_light=None))
        assert not actor.GetVisibility()
    finally:
        view.close()


def test_label_offsets_stack_letters_of_coinciding_arrows_only():
    from phonglab.render.framing import label_offsets

    up, tilted, side = (0, 0, 1), (np.sin(0.05), 0, np.cos(0.05)), (1, 0, 0)  # 0.05 rad ≈ 3°
    dirs = {"N": up, "L": tilted, "R": side, "V": up, "H": up}
    offsets = label_offsets(list("NLRVH"), dirs)
    assert offsets == {"N": 0, "L": 1, "R": 0, "V": 2, "H": 3}, (dirs, offsets)
    assert label_offsets(list("NR"), {"N": up, "R": side}) == {"N": 0, "R": 0}


def test_headlight_over_the_probe_gives_every_letter_its_own_line():
    # light and eye straight above the probe: N, L, R, V and H all point the same way
    probe = np.array([0.0, 0.0, 1.0])
    scene = red_sphere(**{"lights[1].position": [0, 0, 6]}, camera__eye=[0, 0, 4], probe=tuple(probe))
    v = SceneView(scene, size=SIZE, vtk_text=True)
    try:
        shown = [letter for letter, actor in v.glyph_actors.letters.items() if actor.GetVisibility()]
        offsets = [v.glyph_actors.letters[letter].GetDisplayOffset() for letter in shown]
        assert len(shown) == 5 and len(set(offsets)) == 5, (shown, offsets)
    finally:
        v.close()


def test_letters_of_arrows_the_mesh_hides_are_reported_hidden():
    # probe on the near side of the sphere: every tip in sight; turned to look from behind, the sphere hides them
    view = SceneView(red_sphere(), size=SIZE)
    try:
        shown = {letter for letter, _, _ in view.arrow_tips()}
        assert shown and view.hidden_letters() == set(), (shown, view.hidden_letters())
        view.set_camera(eye=(0.0, 0.0, -5.0), focal_point=(0.0, 0.0, 0.0))
        hidden = view.hidden_letters()
        probe = view.probe[0]
    finally:
        view.close()
    assert hidden == shown, f"probe at {probe}, camera at (0, 0, -5): hidden {sorted(hidden)} of {sorted(shown)}"


def test_hidden_letters_are_kept_until_the_camera_or_the_arrows_move(monkeypatch):
    # a slider that changes only colours refreshes the panels: it must not cast the letters' rays again
    from phonglab.render import picking

    casts = []
    real = picking.ray_hit
    monkeypatch.setattr(picking, "ray_hit", lambda *a: casts.append(a) or real(*a))
    view = SceneView(red_sphere(), size=SIZE)
    try:
        first = view.hidden_letters()
        rays = len(casts)
        view.update(red_sphere(**{"material.shininess": 7.0}))
        again = view.hidden_letters()
        assert rays > 0 and len(casts) == rays and again == first, (rays, len(casts), first, again)
        view.set_camera(eye=(0.0, 0.0, -5.0), focal_point=(0.0, 0.0, 0.0))
        behind = view.hidden_letters()
        assert len(casts) == 2 * rays and behind and behind != first, (rays, len(casts), first, behind)
    finally:
        view.close()


def test_faces_turned_away_are_left_out_only_where_no_pixel_changes():
    # a browser drawing WebGL in software draws half the sphere's triangles; the picture must not change
    view = SceneView(red_sphere(), size=SIZE, labels=False, vtk_text=False)
    try:
        prop = view.mesh_actor.GetProperty()
        assert prop.GetBackfaceCulling(), "the opaque sphere seen from outside is drawn with its hidden faces"
        culled = view.screenshot(annotate=False)
        prop.SetBackfaceCulling(False)
        whole = view.screenshot(annotate=False)
        assert np.array_equal(culled, whole), f"{np.count_nonzero((culled != whole).any(axis=2))} pixels changed"
        view.set_camera(eye=(0.2, 0.1, 0.3), focal_point=(0.0, 0.0, -1.0))  # inside the sphere
        assert not prop.GetBackfaceCulling(), "culled with the eye inside the sphere"
        view.reset_camera()
        assert prop.GetBackfaceCulling()
        view.update(red_sphere(**{"material.opacity": 0.5}))
        assert not prop.GetBackfaceCulling(), "culled a translucent sphere (its far side shows)"
    finally:
        view.close()
    plane = SceneView(dataclasses.replace(red_sphere(), geometry=Geometry("plane", 8)), size=SIZE)
    try:
        assert not plane.mesh_actor.GetProperty().GetBackfaceCulling(), "culled an open sheet"
    finally:
        plane.close()
