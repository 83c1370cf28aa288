"""The arrows and bulbs the view moves at every step of a slider keep the shapes VTK's sources give them.

:func:`phonglab.render.glyphs.arrow` and a point light's bulb are built once
and then turned and moved with NumPy; these tests hold them to what building
them again with PyVista (``pv.Arrow``, ``pv.Sphere``) gives, in every direction.
"""

from __future__ import annotations

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")

from phonglab import core  # noqa: E402
from phonglab.render import glyphs  # noqa: E402

DIRECTIONS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1e-9, 1, 0), (0, -1, 1e-9),
              (0.3, -0.95, 0.1), (2.0, 3.0, -6.0)]
DIRECTIONS += [tuple(d) for d in np.random.default_rng(7).normal(size=(20, 3))]


def built_arrow(start, direction, length):
    """The arrow as PyVista builds it, with the same triangles and normals as the glyphs'."""
    mesh = pv.Arrow(start=tuple(map(float, start)), direction=tuple(glyphs._unit(direction)),
                    tip_length=glyphs.TIP_LENGTH, tip_radius=glyphs.TIP_RADIUS / length,
                    shaft_radius=glyphs.SHAFT_RADIUS / length, tip_resolution=24, shaft_resolution=16, scale=length)
    return mesh.triangulate().compute_normals(cell_normals=False, point_normals=True, split_vertices=True,
                                              feature_angle=45.0)


def _normals(mesh):
    return mesh.compute_normals(cell_normals=False, point_normals=True, split_vertices=False,
                                consistent_normals=False).point_data["Normals"]


@pytest.mark.parametrize("direction", DIRECTIONS)
@pytest.mark.parametrize("start, length", [((0.1, -0.2, 0.3), 0.6), ((-3.0, 2.0, 40.0), 0.45)])
def test_an_arrow_is_the_arrow_pyvista_builds(direction, start, length):
    arrow = glyphs.arrow(start, direction, (240, 228, 66), (0.2, 0.1, 1.0), length=length)
    built = built_arrow(start, direction, length)
    where = f"direction {direction}, start {start}, length {length}"
    assert (arrow.n_points, arrow.n_cells) == (built.n_points, built.n_cells), where
    # the same points in the same order (VTK may split a flat quad along either diagonal: the faces may differ)
    assert np.abs(np.asarray(arrow.points) - np.asarray(built.points)).max() < 1e-5 * (1 + np.abs(start).max()), where
    assert arrow.area == pytest.approx(built.area, rel=1e-5), where
    tip = np.asarray(start) + length * glyphs._unit(direction)
    assert np.linalg.norm(np.asarray(arrow.points) - tip, axis=1).min() < 1e-5 * (1 + np.abs(start).max()), where
    # every face is wound outwards as in the built arrow: the summed face normals agree at each point
    assert (np.einsum("ij,ij->i", _normals(arrow), _normals(built)) > 0.99).all(), where
    rgb = arrow.point_data[glyphs.COLOR_ARRAY]
    assert rgb.dtype == np.uint8 and rgb.shape == (arrow.n_points, 3), where


def test_an_arrows_relief_is_lit_from_over_the_viewers_shoulder():
    # the side facing the eye (view_direction points from the glyph to the eye) is the brighter one
    arrow = glyphs.arrow((0, 0, 0), (1, 0, 0), (200, 200, 200), (0, 0, 1), length=0.6)
    z = np.asarray(arrow.points)[:, 2]
    rgb = arrow.point_data[glyphs.COLOR_ARRAY].astype(float).sum(axis=1)
    shaft = np.asarray(arrow.points)[:, 0] < 0.3
    towards_eye = rgb[shaft & (z > 0.015)].mean()
    away = rgb[shaft & (z < -0.015)].mean()
    assert towards_eye > away + 30, (towards_eye, away)


@pytest.mark.parametrize("position", [(0.0, 0.0, 0.0), (1.5, 2.0, -3.0), (1000.0, 0.1, 0.2)])
def test_a_bulb_is_the_ball_pyvista_builds_at_the_light(position):
    light = core.PointLight(position=position, color=(1.0, 0.5, 0.25))
    bulb = glyphs.light_marker(light, (0, 0, 1))
    built = pv.Sphere(radius=glyphs.LIGHT_MARKER_SIZE, center=position, theta_resolution=24, phi_resolution=16)
    built = built.triangulate()
    assert (bulb.n_points, bulb.n_cells) == (built.n_points, built.n_cells), position
    assert np.abs(np.asarray(bulb.points) - np.asarray(built.points)).max() < 1e-4, position
    assert np.array_equal(bulb.faces, built.faces), position
    assert (bulb.point_data[glyphs.COLOR_ARRAY] == glyphs.light_color_255(light)).all(), position


def test_the_arrows_kept_shape_cannot_be_changed_by_a_caller():
    arrow = glyphs.arrow((0, 0, 0), (0, 0, 1), (255, 0, 0), (0, 0, 1), length=0.6)
    arrow.points[:] = 0.0  # the caller's copy
    again = glyphs.arrow((0, 0, 0), (0, 0, 1), (255, 0, 0), (0, 0, 1), length=0.6)
    assert np.abs(np.asarray(again.points)).max() > 0.5
    points, normals, faces = glyphs._arrow_model(0.6)
    with pytest.raises(ValueError):
        points[0, 0] = 1.0
