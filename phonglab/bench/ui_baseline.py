"""The minimal trame app that ``phonglab bench ui`` compares phonglab against.

One slider (the shininess α) re-shades a sphere of about 100 000 vertices
with plain NumPy Phong and hands the colours to a ``VtkLocalView`` the way a
trame tutorial does: write the colour array, then ``view.update()``. Nothing
else is on the page. It is what a reasonable first attempt at phonglab's job
would cost, so phonglab should be no slower.

Run on its own::

    python -m phonglab.bench.ui_baseline --port 8091 [--view-size 800x600]
"""

from __future__ import annotations

import argparse

import numpy as np
from trame.app import TrameApp
from trame.ui.vuetify3 import VAppLayout
from trame.widgets import html
from trame.widgets import vtk as vtk_widgets
from trame.widgets import vuetify3 as v3
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow

import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL window classes)

from phonglab.app.timing import timed

#: sphere segments: 320 around × 315 from pole to pole = 100 162 vertices
THETA, PHI = 320, 315
#: the fixed scene: one white point light, a red plastic material, the eye on +z
LIGHT = np.array([2.0, 2.5, 3.0])
EYE = np.array([0.0, 0.0, 4.0])
KA, KD, KS = 0.1, np.array([0.8, 0.3, 0.2]), 0.6


class BaselineApp(TrameApp):
    """One slider, one sphere, plain NumPy shading, ``view.update()`` per change.

    Parameters
    ----------
    server : trame server or name, optional
    view_size : (int, int) or None
        The view's size in CSS pixels (None: fill the window).
    """

    def __init__(self, server=None, view_size=None):
        super().__init__(server)
        self.view_size = view_size
        # the sphere and its colour array (uint8 RGB, written in place)
        source = vtkSphereSource()
        source.SetRadius(1.0)
        source.SetThetaResolution(THETA)
        source.SetPhiResolution(PHI)
        source.Update()
        self.polydata = source.GetOutput()
        points = vtk_to_numpy(self.polydata.GetPoints().GetData()).astype(np.float64)
        self.points = points
        self.normals = vtk_to_numpy(self.polydata.GetPointData().GetNormals()).astype(np.float64)
        self.colors = np.zeros((len(points), 3), np.uint8)
        self.vtk_colors = numpy_to_vtk(self.colors, deep=False)
        self.vtk_colors.SetName("rgb")
        self.polydata.GetPointData().SetScalars(self.vtk_colors)
        # VTK pipeline: colours shown as they are, lighting off
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(self.polydata)
        mapper.SetColorModeToDirectScalars()
        mapper.SetScalarModeToUsePointData()
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().LightingOff()
        renderer = vtkRenderer()
        renderer.AddActor(actor)
        renderer.SetBackground(0.13, 0.14, 0.17)
        camera = renderer.GetActiveCamera()
        camera.SetPosition(*EYE)
        camera.SetFocalPoint(0, 0, 0)
        camera.SetViewUp(0, 1, 0)
        self.render_window = vtkRenderWindow()
        self.render_window.SetOffScreenRendering(1)
        self.render_window.AddRenderer(renderer)
        self.shade(40.0)
        self.state.change("shininess")(self.on_shininess)
        self._build_ui()

    def shade(self, shininess: float) -> None:
        """Phong with one point light, written into the colour array."""
        n, p = self.normals, self.points
        l = LIGHT - p
        l /= np.linalg.norm(l, axis=1, keepdims=True)
        v = EYE - p
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        nl = np.einsum("ij,ij->i", n, l)
        r = 2.0 * nl[:, None] * n - l
        rv = np.clip(np.einsum("ij,ij->i", r, v), 0.0, None)
        specular = np.where(nl > 0, KS * rv**shininess, 0.0)
        color = KA + np.clip(nl, 0.0, None)[:, None] * KD + specular[:, None]
        self.colors[:] = np.clip(color * 255.0 + 0.5, 0, 255).astype(np.uint8)
        self.vtk_colors.Modified()

    def on_shininess(self, shininess, **_):
        with timed("baseline"):
            self.shade(float(shininess))
            self.view.update()

    def _build_ui(self):
        style = "width: 100%; height: 100%;"
        if self.view_size:
            style = f"width: {self.view_size[0]}px; height: {self.view_size[1]}px;"
        with VAppLayout(self.server, full_height=True) as self.ui:
            with v3.VContainer(fluid=True, classes="pa-4"):
                v3.VSlider(
                    v_model=("shininess", 40),
                    min=1,
                    max=400,
                    step=1,
                    label="shininess",
                    hide_details=True,
                    classes="bench-slider",
                    style="max-width: 480px;",
                )
                with html.Div(classes="bench-view", style=style):
                    self.view = vtk_widgets.VtkLocalView(self.render_window)


def _size(text: str):
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be WIDTHxHEIGHT, got {text!r}") from None
    if not (50 <= w <= 8000 and 50 <= h <= 8000):
        raise argparse.ArgumentTypeError(f"sizes must be 50..8000 pixels, got {text!r}")
    return (w, h)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8091)
    parser.add_argument("--view-size", type=_size, default=None, metavar="WxH")
    args, _ = parser.parse_known_args(argv)
    app = BaselineApp(view_size=args.view_size)
    app.server.start(host=args.host, port=args.port, open_browser=False, show_connection_info=False, timeout=0)


if __name__ == "__main__":
    main()
