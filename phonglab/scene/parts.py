"""The parts of a scene: its mesh, its camera and its optional area light.

Each part checks its own fields once, when it is made, and stores them in a
canonical form (vectors as tuples of floats); the file loader builds the
parts with these constructors and adds the file, line and table to their
errors. A bad field raises :class:`SceneError` naming the field, the bad
value and what is allowed. No part reads a file: whether a mesh file exists
is checked when a scene is loaded (:func:`phonglab.scene.paths.find_mesh_file`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from phonglab import core
from phonglab.scene.checks import check_bool, check_choice, check_int, check_number, check_vector, collect, setter
from phonglab.scene.errors import SceneError
from phonglab.scene.limits import check_coordinates
from phonglab.scene.objects import SCALE_RANGE
from phonglab.scene.paths import check_geometry_source
from phonglab.scene.schema import AREA_METHODS, AREA_SAMPLES_RANGE, GEOMETRY_KINDS, RESOLUTION_RANGE


def _check_center(value) -> tuple[float, float, float]:
    """Three finite numbers within the coordinate bound."""
    center = check_vector("center", value)
    check_coordinates("center", center)
    return center


@dataclass(frozen=True)
class Geometry:
    """The mesh a scene shows.

    Parameters
    ----------
    kind : str
        One of ``"sphere"``, ``"torus"``, ``"plane"``, ``"cube"``, ``"cylinder"``,
        ``"supertoroid"`` (built from a formula), ``"pyvista"`` (a mesh shipped
        inside the pyvista package, chosen by ``name``) or ``"file"`` (any mesh
        PyVista can read, at ``path``).
    resolution : int
        Segments around, for the parametric kinds; ignored for meshes.
    name : str or None
        For ``kind="pyvista"``: which shipped mesh (see
        :data:`phonglab.scene.paths.PYVISTA_MESHES`).
    path : str or None
        For ``kind="file"``: the mesh file. The loader resolves a relative path
        against the scene file's folder, then ``assets/``, checks that the
        file exists and stores it absolute; the dataclass does not look at files.
    center : tuple of 3 floats
        Where the shape's own origin is placed in the scene (default the origin).
    scale : float
        How much the shape is enlarged about its own origin, before it is
        moved to ``center``; from 0.001 to 1000 (default 1).

    Notes
    -----
    Each shape is built at scale 1 around the origin
    (:func:`phonglab.render.mesh.build_mesh`): a sphere of radius 1, a plane
    of side 2.4 lying in z = 0 with its normal +z, a mesh file fitted to the
    unit sphere. A point ``p`` of that shape is placed at
    ``center + scale · p``; normals are unchanged (the scale is the same
    along every axis and positive).
    """

    kind: str
    resolution: int = 48
    name: str | None = None
    path: str | None = None
    center: tuple[float, float, float] = (0.0, 0.0, 0.0)
    scale: float = 1.0

    def __post_init__(self):
        collect(
            [
                setter(self, "kind", lambda v: check_choice("kind", v, GEOMETRY_KINDS)),
                setter(
                    self, "resolution", lambda v: check_int("resolution", v, low=RESOLUTION_RANGE[0], high=RESOLUTION_RANGE[1])
                ),
                setter(self, "center", _check_center),
                setter(self, "scale", lambda v: check_number("scale", v, low=SCALE_RANGE[0], high=SCALE_RANGE[1])),
            ]
        )
        # a name for shipped meshes, a path for kind="file"; the files themselves are checked at load
        check_geometry_source(self.kind, self.name, self.path)


@dataclass(frozen=True)
class Camera:
    """Where the scene is seen from.

    Parameters
    ----------
    eye, focal_point, up : tuple of 3 floats
        VTK's camera position, the point it looks at, and its up direction.
    view_angle : float
        VTK's vertical view angle in degrees, in (0, 180).
    infinite_viewer : bool
        If true, lighting uses the constant view direction
        :math:`v = (e - f)/\\lVert e - f \\rVert` instead of the direction from
        each point to the eye.
    """

    eye: tuple[float, float, float] = (0.0, 0.0, 4.0)
    focal_point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    view_angle: float = 30.0
    infinite_viewer: bool = False

    def __post_init__(self):
        collect(
            [
                setter(self, "eye", lambda v: check_vector("eye", v)),
                setter(self, "focal_point", lambda v: check_vector("focal_point", v)),
                setter(self, "up", lambda v: check_vector("up", v, nonzero=True)),
                setter(
                    self,
                    "view_angle",
                    lambda v: check_number("view_angle", v, low=0, high=180, low_open=True, high_open=True),
                ),
                setter(self, "infinite_viewer", lambda v: check_bool("infinite_viewer", v)),
            ]
        )
        # within the coordinate bound first: past it the tests below overflow
        collect([lambda key=key: check_coordinates(key, getattr(self, key)) for key in ("eye", "focal_point", "up")])
        d = [e - f for e, f in zip(self.eye, self.focal_point)]
        if not any(d):
            raise SceneError("must differ from camera.focal_point", field="eye", value=self.eye)
        # up must not be parallel to the viewing direction
        cross = (
            d[1] * self.up[2] - d[2] * self.up[1],
            d[2] * self.up[0] - d[0] * self.up[2],
            d[0] * self.up[1] - d[1] * self.up[0],
        )
        norm_d = math.sqrt(sum(c * c for c in d))
        norm_u = math.sqrt(sum(c * c for c in self.up))
        if math.sqrt(sum(c * c for c in cross)) <= 1e-9 * norm_d * norm_u:
            raise SceneError(
                "must not be parallel to the viewing direction eye - focal_point", field="up", value=self.up
            )

    @property
    def view_direction(self) -> tuple[float, float, float]:
        """The unit vector from the focal point towards the eye."""
        d = [e - f for e, f in zip(self.eye, self.focal_point)]
        n = math.sqrt(sum(c * c for c in d))
        return (d[0] / n, d[1] / n, d[2] / n)


@dataclass(frozen=True)
class AreaLightSetup:
    """A scene's area light and how its integral is evaluated.

    Parameters
    ----------
    light : phonglab.core.AreaLight
    method : str
        ``"exact"`` (Lambert's closed form), ``"point"`` (a point light at its
        centre), ``"uniform"`` or ``"stratified"`` (Monte Carlo).
    samples : int
        Monte Carlo samples per point, 1 to 4096; a fixed seed keeps the
        picture still while sliders move.
    """

    light: core.AreaLight
    method: str = "exact"
    samples: int = 64

    def __post_init__(self):
        collect(
            [
                setter(self, "method", lambda v: check_choice("area_light.method", v, AREA_METHODS)),
                setter(self, "samples", lambda v: check_int("area_light.samples", v, low=AREA_SAMPLES_RANGE[0], high=AREA_SAMPLES_RANGE[1])),
            ]
        )


__all__ = ["Geometry", "Camera", "AreaLightSetup"]
