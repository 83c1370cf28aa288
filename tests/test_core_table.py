"""Per-term values against a table worked out by hand, intermediates kept.

Every row is small enough to check on paper: the light and eye sit on 3-4-5
triangles, so n·l, r and r·v are exact decimals.
"""

import math

import numpy as np
import pytest

import phonglab as pl

MAT = pl.Material(ka=0.2, kd=0.5, ks=0.25, shininess=2.0)
AMBIENT = pl.AmbientLight(intensity=0.5)  # k_a·I_a = 0.1

# point, normal, light, eye, n·l, r, r·v, n·h (Blinn), attenuation·spot
ROWS = [
    pytest.param((0, 0, 0), (0, 0, 1), pl.PointLight(position=(0, 3, 4)), (0, -6, 8),
                 0.8, (0, -0.6, 0.8), 1.0, None, 1.0, id="eye-on-mirror-ray"),
    pytest.param((0, 0, 0), (0, 0, 1), pl.PointLight(position=(0, 3, 4)), (0, 0, 5),
                 0.8, (0, -0.6, 0.8), 0.8, 1.8 / math.sqrt(0.36 + 3.24), 1.0, id="eye-overhead"),
    pytest.param((0, 0, 0), (0, 0, 1), pl.PointLight(position=(0, 3, -4)), (0, 0, -5),
                 -0.8, (0, -0.6, -0.8), 0.8, None, 1.0, id="light-behind-but-r.v>0"),
    pytest.param((0, 0, 0), (0, 0, 1), pl.PointLight(position=(0, 3, 4), attenuation=(1, 0.1, 0.01)),
                 (0, 0, 5), 0.8, (0, -0.6, 0.8), 0.8, None, 1 / 1.75, id="attenuation-d=5"),
    pytest.param((1, 0, 0), (0, 0, 1), pl.SpotLight(position=(0, 0, 5), direction=(0, 0, -1),
                                                    cutoff=30, exponent=2),
                 (1, 0, 5), 5 / math.sqrt(26), (1 / math.sqrt(26), 0, 5 / math.sqrt(26)),
                 5 / math.sqrt(26), None, 25 / 26, id="spot-inside"),
    pytest.param((0, 0, 0), (0, 0, 1), pl.DirectionalLight(direction=(4, 0, 3)), (0, 0, 7),
                 0.6, (-0.8, 0, 0.6), 0.6, None, 1.0, id="directional"),
    pytest.param((0, 0, 0), (0, 0, 2.5), pl.DirectionalLight(direction=(0, 0, 1)), (0, 0, 1),
                 1.0, (0, 0, 1), 1.0, 1.0, 1.0, id="unnormalised-normal"),
]


@pytest.mark.parametrize("point,normal,light,eye,nl,r,rv,nh,f", ROWS)
def test_table_phong(point, normal, light, eye, nl, r, rv, nh, f):
    inputs = dict(point=point, normal=normal, light=light, eye=eye)
    vec = pl.vectors(point, normal, eye=eye, light=light)
    assert vec.nl == pytest.approx(nl, abs=1e-12), inputs
    np.testing.assert_allclose(vec.r, r, atol=1e-12, err_msg=str(inputs))
    assert vec.rv == pytest.approx(rv, abs=1e-12), inputs
    assert vec.attenuation * vec.spot == pytest.approx(f, rel=1e-12), inputs

    s = pl.shade([point], [normal], eye=eye, material=MAT, lights=[AMBIENT, light])
    diffuse = 0.5 * max(nl, 0) * f
    specular = 0.25 * max(rv, 0) ** 2 * f if nl > 0 else 0.0
    np.testing.assert_allclose(s.ambient[0], 0.1, rtol=1e-12, err_msg=str(inputs))
    np.testing.assert_allclose(s.diffuse[0], diffuse, rtol=1e-12, atol=1e-15, err_msg=str(inputs))
    np.testing.assert_allclose(s.specular[0], specular, rtol=1e-12, atol=1e-15, err_msg=str(inputs))
    np.testing.assert_allclose(s.color[0], 0.1 + diffuse + specular, rtol=1e-12, err_msg=str(inputs))


@pytest.mark.parametrize("point,normal,light,eye,nl,r,rv,nh,f",
                         [row for row in ROWS if row.values[7] is not None])
def test_table_blinn_phong(point, normal, light, eye, nl, r, rv, nh, f):
    inputs = dict(point=point, normal=normal, light=light, eye=eye)
    vec = pl.vectors(point, normal, eye=eye, light=light)
    assert vec.nh == pytest.approx(nh, abs=1e-12), inputs
    s = pl.shade([point], [normal], eye=eye, material=MAT, lights=[light], model="blinn-phong")
    np.testing.assert_allclose(s.specular[0], 0.25 * nh**2 * f, rtol=1e-12, err_msg=str(inputs))


def test_rgb_coefficients_multiply_per_channel():
    # a red light on a green surface reflects nothing
    mat = pl.Material(ka=0, kd=(0, 1, 0), ks=(0, 1, 0), shininess=10)
    red = pl.DirectionalLight(direction=(0, 0, 1), color=(1, 0, 0))
    s = pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 3), material=mat, lights=[red])
    assert s.color.tolist() == [[0.0, 0.0, 0.0]], s


def test_separate_diffuse_and_specular_intensities_and_emission():
    mat = pl.Material(ka=0, kd=1, ks=1, shininess=1, emission=(0.1, 0.2, 0.3))
    light = pl.DirectionalLight(direction=(0, 0, 1), intensity=2, diffuse=(0.5, 0, 0), specular=(0, 0, 0.25))
    s = pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 3), material=mat, lights=[light])
    np.testing.assert_allclose(s.diffuse[0], [1.0, 0, 0])
    np.testing.assert_allclose(s.specular[0], [0, 0, 0.5])
    np.testing.assert_allclose(s.emission[0], [0.1, 0.2, 0.3])
    np.testing.assert_allclose(s.color[0], [1.1, 0.2, 0.8])


def test_lights_sum():
    mat = pl.Material(ka=0, kd=0.5, ks=0.0, shininess=1)
    a = pl.DirectionalLight(direction=(0, 0, 1))
    b = pl.DirectionalLight(direction=(3, 0, 4))
    one = pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 3), material=mat, lights=[a]).color
    two = pl.shade([[0, 0, 0]], [[0, 0, 1]], eye=(0, 0, 3), material=mat, lights=[a, b]).color
    np.testing.assert_allclose(two - one, 0.5 * 0.8)


def test_homogeneous_lights():
    assert pl.light_from_homogeneous((0, 0, 1, 0)) == pl.DirectionalLight(direction=(0, 0, 1))
    assert pl.light_from_homogeneous((2, 4, 6, 2)) == pl.PointLight(position=(1, 2, 3))


def test_infinite_viewer_uses_constant_v():
    # with view_direction, v is the same at every point: r·v depends on n only
    mat = pl.Material(ka=0, kd=0, ks=1, shininess=1)
    light = pl.DirectionalLight(direction=(0, 0, 1))
    pts = [[0, 0, 0], [100, -50, 3]]
    s = pl.shade(pts, [[0, 0, 1]] * 2, view_direction=(0, 0, 1), material=mat, lights=[light])
    np.testing.assert_array_equal(s.specular[0], s.specular[1])
    np.testing.assert_allclose(s.specular[0], 1.0)


def test_two_sided_flips_normals_that_face_away():
    mat = pl.Material(ka=0, kd=1, ks=0, shininess=1)
    light = pl.PointLight(position=(0, 0, 5))
    back = [[0, 0, -1]]
    one = pl.shade([[0, 0, 0]], back, eye=(0, 0, 5), material=mat, lights=[light])
    two = pl.shade([[0, 0, 0]], back, eye=(0, 0, 5), material=mat, lights=[light], two_sided=True)
    assert one.diffuse[0, 0] == 0 and two.diffuse[0, 0] == pytest.approx(1.0)
    assert pl.vectors((0, 0, 0), (0, 0, -1), eye=(0, 0, 5), light=light, two_sided=True).flipped


def test_broadcast_and_dtype():
    mat = pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=8)
    light = pl.PointLight(position=(1, 2, 3))
    pts = np.zeros((4, 5, 3), np.float32)
    s = pl.shade(pts, np.array([0, 0, 1], np.float32), eye=(0, 0, 4), material=mat, lights=[light])
    for name in ("ambient", "diffuse", "specular", "emission", "color"):
        arr = getattr(s, name)
        assert arr.shape == (4, 5, 3) and arr.dtype == np.float32, (name, arr.shape, arr.dtype)
    s64 = pl.shade(pts.astype(np.float64), [0, 0, 1], eye=(0, 0, 4), material=mat, lights=[light])
    assert s64.color.dtype == np.float64
