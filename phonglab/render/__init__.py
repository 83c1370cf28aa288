"""phonglab.render: PyVista/VTK rendering of scenes lit by the core, and figures.

The only layer that touches VTK. VTK rasterizes and displays; every colour
comes from :mod:`phonglab.core` (through :func:`phonglab.scene.shade`) and
reaches VTK as uint8 RGB scalars on actors with lighting off.

* :func:`build_mesh` — the triangle mesh of a scene's geometry, with normals.
* :class:`SceneView` — a render window with the shaded mesh, the vectors
  N, L, R, V, H at the probe and markers for the lights and the eye.
* :func:`figure` — PNG/SVG/PDF figures: renders, per-term views, sweeps, plots.

Both can show a lesson's common mistake (``mistake=``, a name from
:data:`phonglab.teaching.MISTAKES`): the same render code, shaded with the
deliberately wrong variant (:meth:`SceneView.set_mistake`; ``figure(...,
mistake=..., compare=True)`` for the correct and the wrong picture side by side).

A material's opacity below 1 is drawn in every mode and every picture: the
mesh's near and far layers blended over what lies behind them, in linear
light (:mod:`~phonglab.render.translucency`).

The names above load VTK (and matplotlib) on first use, so the VTK-free
modules (:mod:`~phonglab.render.framing`, :mod:`~phonglab.render.camera`,
:mod:`~phonglab.render.options`, :mod:`~phonglab.render._files`) import
without them.
"""

from phonglab.render.errors import FigureError

__all__ = ["FigureError", "SceneView", "build_mesh", "figure", "render"]


def __getattr__(name):
    # VTK and matplotlib load only when a name that needs them is asked for
    if name == "SceneView":
        from phonglab.render.view import SceneView

        return SceneView
    if name == "build_mesh":
        from phonglab.render.mesh import build_mesh

        return build_mesh
    if name in ("figure", "render"):
        from phonglab.render import figures

        return getattr(figures, name)
    raise AttributeError(f"module 'phonglab.render' has no attribute {name!r}")
