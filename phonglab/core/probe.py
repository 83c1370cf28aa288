"""The vectors of the model at one surface point, for arrows and readouts.

Directions point *away from the surface point*: ``n`` the unit normal, ``l``
towards the light, ``v`` towards the eye, ``r = 2(n·l)n − l``,
``h = normalize(l + v)``. :func:`vectors` reads them from the record of the
reference kernel (:func:`~phonglab.core.shade_reference` with ``trace=True``)
at that one point, so the arrows and numbers a lesson shows are the vectors
the model's sum used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .checks import viewer
from .model import AmbientLight, InvalidValue, Light, Material, vec3
from .record import Record
from .reference import shade_reference

__all__ = ["ProbeVectors", "vectors"]

#: any material will do: the vectors do not depend on it
_MATERIAL = Material(ka=0.0, kd=1.0, ks=1.0, shininess=1.0)


@dataclass(frozen=True)
class ProbeVectors:
    """The vectors of the model at one surface point, all unit, float64.

    ``nl``, ``rv`` and ``nh`` are the raw cosines (not clamped), so a negative
    ``nl`` shows the light is behind the surface. ``distance`` is None for a
    directional light; ``attenuation`` and ``spot`` are the factors ``f_l``
    is made of.
    """

    n: np.ndarray
    l: np.ndarray
    r: np.ndarray
    v: np.ndarray
    h: np.ndarray
    nl: float
    rv: float
    nh: float
    distance: float | None
    attenuation: float
    spot: float
    flipped: bool

    @classmethod
    def of(cls, record: Record, light_index: int) -> ProbeVectors:
        """The vectors of ``lights[light_index]`` in the record of one point (:meth:`Record.at`)."""
        light = record.light(light_index)

        def scalar(name, default=None):
            return float(light.values[name]) if name in light.values else default

        return cls(
            n=np.array(record["n"], np.float64), l=np.array(light["l"], np.float64),
            r=np.array(light["r"], np.float64), v=np.array(record["v"], np.float64),
            h=np.array(light["h"], np.float64),
            nl=scalar("n·l"), rv=scalar("r·v"), nh=scalar("n·h"), distance=scalar("d"),
            attenuation=scalar("attenuation", 1.0), spot=scalar("spot", 1.0), flipped=bool(record["flipped"]),
        )


def vectors(point, normal, *, light: Light, eye=None, view_direction=None, two_sided: bool = False) -> ProbeVectors:
    """Unit N, L, R, V, H and the cosines n·l, r·v, n·h at one point.

    Parameters
    ----------
    point, normal : 3 floats
    light : PointLight, DirectionalLight or SpotLight
    eye, view_direction : 3 floats, keyword-only (exactly one)
    two_sided : bool
        Negate the normal if it faces away from the eye (``flipped`` says so).

    Returns
    -------
    ProbeVectors

    Notes
    -----
    .. math:: r = 2(n\\cdot l)n - l, \\qquad h = \\frac{l + v}{|l + v|}

    The record of :func:`~phonglab.core.shade_reference` at the point, in
    float64: the same light factors (:func:`~phonglab.core.attenuation`,
    :func:`~phonglab.core.spot_factor`) and flip
    (:func:`~phonglab.core.face_forward`) as both kernels.

    Examples
    --------
    >>> import phonglab as pl
    >>> pv = pl.vectors((0, 0, 0), (0, 0, 1), eye=(0, 0, 3),
    ...                 light=pl.DirectionalLight(direction=(1, 0, 1)))
    >>> pv.r.round(4).tolist(), round(pv.nl, 4)
    ([-0.7071, 0.0, 0.7071], 0.7071)
    """
    if isinstance(light, AmbientLight) or not isinstance(light, Light):
        raise InvalidValue("light", light, "must be a point, directional or spot light "
                           "(ambient light has no direction)")
    eye, view_direction = viewer(eye, view_direction)
    p = np.asarray(vec3("point", point), np.float64)
    n = np.asarray(vec3("normal", normal), np.float64)
    _, record = shade_reference(p[None], n[None], material=_MATERIAL, lights=[light], eye=eye,
                                view_direction=view_direction, two_sided=two_sided, trace=True)
    return ProbeVectors.of(record.at(0), 0)
