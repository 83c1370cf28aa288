"""The probe: the surface point where the vectors N, L, R, V, H are drawn, and the vectors there.

Every vector comes from :func:`phonglab.core.vectors` for the scene's eye
(two-sided lighting's flipped normal included); directions point *away from
the surface point*.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv

from phonglab import core
from phonglab.render import mesh as meshes
from phonglab.scene import viewer

#: a stand-in light for :func:`phonglab.core.vectors` when the scene has no directed light (only N and V are used)
_NO_LIGHT = core.DirectionalLight(direction=(0.0, 0.0, 1.0))


def default_probe(mesh: pv.PolyData, camera) -> tuple[np.ndarray, np.ndarray]:
    """Where the vectors go when a scene gives no probe.

    The first surface point on the ray from the eye through the focal point;
    if that ray misses the mesh (a torus's hole), the surface point nearest
    the eye.
    """
    hit = meshes.ray_hit(mesh, camera.eye, camera.focal_point)
    return hit if hit is not None else meshes.surface_point(mesh, camera.eye)


def locate_probe(mesh: pv.PolyData, scene) -> tuple[np.ndarray, np.ndarray]:
    """The probe point on ``mesh`` and the unit normal there: the scene's probe, or :func:`default_probe`."""
    if scene.probe is None:
        return default_probe(mesh, scene.camera)
    return meshes.surface_point(mesh, scene.probe)


def directed_light_index(lights, choice: int | None = None) -> int | None:
    """Index of the light the vectors L, R, H refer to: ``choice`` if it is a directed light, else the first one that shines.

    A light switched off (intensity 0: it adds nothing) is passed over for
    the next directed light that adds light, so that the arrows and the
    readout follow the light that lights the picture (lesson 7 turns its
    spotlight off for the sun). None when every light is ambient (no light
    has a direction); the first directed light when none shines.
    """
    if choice is not None and 0 <= choice < len(lights) and not isinstance(lights[choice], core.AmbientLight):
        return choice
    directed = [i for i, light in enumerate(lights) if not isinstance(light, core.AmbientLight)]
    shining = [i for i in directed if lights[i].shines]
    return (shining or directed or [None])[0]


def probe_vectors(scene, point, normal, light_index: int | None):
    """The core's vectors at the probe, and the directions to draw.

    Parameters
    ----------
    scene : Scene
    point, normal : 3 floats
        The probe and the surface normal there.
    light_index : int or None
        The directed light L, R, H refer to (:func:`directed_light_index`).

    Returns
    -------
    (ProbeVectors or None, dict)
        The vectors (None without a directed light) and letter -> unit
        direction: N, L, R, V, H, or only N and V without a directed light.
    """
    # N (flipped towards the eye in two-sided lighting) and V come from the core, light or not
    light = scene.lights[light_index] if light_index is not None else _NO_LIGHT
    vec = core.vectors(point, normal, light=light, two_sided=scene.two_sided, **viewer(scene))
    if light_index is None:
        return None, {"N": vec.n, "V": vec.v}
    return vec, {"N": vec.n, "L": vec.l, "R": vec.r, "V": vec.v, "H": vec.h}
