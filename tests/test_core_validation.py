"""Bad input is refused at the boundary with a message naming field and value."""

import math

import numpy as np
import pytest

import phonglab as pl

NAN, INF = math.nan, math.inf
MAT = pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10)
LIGHT = pl.PointLight(position=(1, 2, 3))


def refused(call, *needles):
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    for needle in needles:
        assert needle in message, (needle, message)
    return info.value


@pytest.mark.parametrize("field,value", [
    ("ka", -0.1), ("kd", (0.5, -0.01, 0.5)), ("ks", NAN), ("kd", (0.1, 0.2)), ("ka", "red"),
    ("emission", INF), ("kd", True),
])
def test_material_coefficients(field, value):
    kw = dict(ka=0.1, kd=0.5, ks=0.5, shininess=10)
    kw[field] = value
    err = refused(lambda: pl.Material(**kw), f"Material.{field}", repr(value))
    assert err.field == f"Material.{field}" and err.value is value


@pytest.mark.parametrize("value", [-1, -1e-300, NAN, INF, "shiny"])
def test_shininess(value):
    refused(lambda: pl.Material(ka=0, kd=0, ks=0, shininess=value), "Material.shininess", ">= 0")


@pytest.mark.parametrize("value", [-0.1, 1.5, NAN])
def test_opacity(value):
    refused(lambda: pl.Material(ka=0, kd=0, ks=0, shininess=1, opacity=value), "Material.opacity", "[0, 1]")


@pytest.mark.parametrize("att", [(0, 0, 0), (1, -1, 0), (0, 0, -1), (1, -3, 1), (-1, 0, 1), (NAN, 0, 0),
                                 (1e-3, -1, 1), (1, 0)])
def test_attenuation_that_can_reach_zero_or_go_negative(att):
    refused(lambda: pl.PointLight(position=(0, 0, 0), attenuation=att), "PointLight.attenuation", "> 0")


@pytest.mark.parametrize("att", [(1, 0, 0), (0, 0, 1), (0, 1, 0), (1, -1, 1), (0.5, 0.1, 0.01)])
def test_attenuation_accepted(att):
    assert pl.PointLight(position=(0, 0, 0), attenuation=att).attenuation == tuple(map(float, att))


@pytest.mark.parametrize("cutoff", [0, -5, 90.5, 179, 181, NAN, INF])
def test_spot_cutoff(cutoff):
    refused(lambda: pl.SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=cutoff),
            "SpotLight.cutoff", "(0, 90]", "180")


@pytest.mark.parametrize("cutoff", [0.001, 45, 90, 180])
def test_spot_cutoff_accepted(cutoff):
    assert pl.SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=cutoff).cutoff == cutoff


@pytest.mark.parametrize("make,needle", [
    (lambda: pl.DirectionalLight(direction=(0, 0, 0)), "DirectionalLight.direction"),
    (lambda: pl.SpotLight(position=(0, 0, 0), direction=(0, 0, 0)), "SpotLight.direction"),
    (lambda: pl.PointLight(position=(0, NAN, 0)), "PointLight.position"),
    (lambda: pl.PointLight(position=(0, 0)), "PointLight.position"),
    (lambda: pl.PointLight(position=(0, 0, 1), intensity=-1), "PointLight.intensity"),
    (lambda: pl.AmbientLight(color=(1, 1, -1)), "AmbientLight.color"),
    (lambda: pl.SpotLight(position=(0, 0, 0), direction=(0, 0, 1), exponent=-2), "SpotLight.exponent"),
    (lambda: pl.light_from_homogeneous((0, 0, 1)), "light.homogeneous"),
    (lambda: pl.light_from_homogeneous((0, 0, 1, -1)), "light.homogeneous"),
])
def test_lights(make, needle):
    refused(make, needle)


@pytest.mark.parametrize("points,normals,needle", [
    ([[0, 0, NAN]], [[0, 0, 1]], "points"),
    ([[0, 0, 0]], [[INF, 0, 1]], "normals"),
    ([[0, 0]], [[0, 0, 1]], "points"),
    ([[0, 0, 0]], [[0, 0, 1, 0]], "normals"),
    (np.zeros((4, 3)), np.zeros((5, 3)), "normals"),
    (5.0, [[0, 0, 1]], "points"),
    ([["a", "b", "c"]], [[0, 0, 1]], "points"),
])
def test_shade_arrays(points, normals, needle):
    refused(lambda: pl.shade(points, normals, eye=(0, 0, 4), material=MAT, lights=[LIGHT]), needle)


def test_shade_nan_reports_where():
    pts = np.zeros((10, 3))
    pts[7, 1] = NAN
    refused(lambda: pl.shade(pts, pts, eye=(0, 0, 4), material=MAT, lights=[LIGHT]), "points", "(7, 1)", "finite")


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
@pytest.mark.parametrize("where", [0, 5, 70_000])  # first block, a later entry, a later block
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shade_refuses_nonfinite_normals_wherever_they_sit(bad, where, dtype):
    # the finiteness check rides on the normalisation's range test: every block must trip it
    rng = np.random.default_rng(where)
    normals = rng.normal(size=(80_000, 3)).astype(dtype)
    normals[3] = 0  # a zero normal (allowed) in the first block runs the explicit check early
    normals[where, 2] = bad
    for view in (dict(eye=(0, 0, 4)), dict(view_direction=(0, 0, 1))):
        for light in (LIGHT, pl.DirectionalLight(direction=(1, 1, 1))):
            refused(lambda: pl.shade(normals, normals, material=MAT, lights=[light], **view),
                    "normals" if "view_direction" in view and light is not LIGHT else "points",
                    f"({where}, 2)", "finite")


@pytest.mark.parametrize("bad", [NAN, INF])
def test_shade_refuses_nonfinite_points_where_they_are_read(bad):
    pts = np.zeros((50_000, 3), np.float32)
    nrm = np.tile(np.float32([0, 0, 1]), (50_000, 1))
    pts[40_000, 0] = bad
    for kw in (dict(eye=(0, 0, 4), lights=[pl.DirectionalLight(direction=(0, 0, 1))]),  # the local viewer reads them
               dict(view_direction=(0, 0, 1), lights=[LIGHT])):  # the point light reads them
        refused(lambda: pl.shade(pts, nrm, material=MAT, **kw), "points", "(40000, 0)", "finite")


def test_points_are_not_read_by_directional_lights_and_an_infinite_viewer():
    # L and V are the same at every point: the positions never enter the sum (documented in shade)
    pts = np.full((4, 3), NAN)
    nrm = np.tile([0.0, 0.0, 1.0], (4, 1))
    s = pl.shade(pts, nrm, view_direction=(0, 0, 1), material=MAT, lights=[pl.DirectionalLight(direction=(0, 1, 1))])
    ref = pl.shade(np.zeros((4, 3)), nrm, view_direction=(0, 0, 1), material=MAT,
                   lights=[pl.DirectionalLight(direction=(0, 1, 1))])
    np.testing.assert_array_equal(s.color, ref.color)


@pytest.mark.parametrize("kw,needle", [
    (dict(), "eye"),
    (dict(eye=(0, 0, 4), view_direction=(0, 0, 1)), "exactly one"),
    (dict(eye=(0, NAN, 4)), "eye"),
    (dict(view_direction=(0, 0, 0)), "view_direction"),
    (dict(eye=(0, 0, 4), model="ward"), "model"),
    (dict(eye=(0, 0, 4), plan="fast"), "plan"),
])
def test_shade_options(kw, needle):
    refused(lambda: pl.shade([[0, 0, 0]], [[0, 0, 1]], material=MAT, lights=[LIGHT], **kw), needle)


def test_shade_refuses_a_plan_made_for_other_lights():
    plan = pl.plan_effects(MAT, [LIGHT], eye=(0, 0, 4))
    other = [pl.PointLight(position=(5, 5, 5))]
    refused(lambda: pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 4), material=MAT, lights=other, plan=plan),
            "plan")


def test_shade_refuses_non_lights_and_non_materials():
    refused(lambda: pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 4), material=MAT, lights=[(1, 2, 3)]),
            "lights[0]")
    refused(lambda: pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 4), material={"ka": 1}, lights=[]),
            "material")


def test_vectors_refuses_ambient_light():
    refused(lambda: pl.vectors((0, 0, 0), (0, 0, 1), eye=(0, 0, 4), light=pl.AmbientLight()), "ambient")


def test_objects_are_frozen():
    with pytest.raises(AttributeError):
        MAT.ka = (1, 1, 1)  # type: ignore[misc]
