"""What the app's tests share: a LessonApp on a lesson folder of its own, and a browser camera turned about the eye."""

from __future__ import annotations

import numpy as np


def open_app(folder, name: str, text: str, server_name: str):
    """A :class:`~phonglab.app.lesson_app.LessonApp` on ``folder`` holding one lesson file ``name`` with ``text``.

    Close it with ``.close()``; exports go to ``folder / "exports"``.
    """
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    (folder / name).write_text(text, encoding="utf-8")
    server = get_server(f"{server_name}-{folder.name}", client_type="vue3")
    return LessonApp(server, target=folder, export_dir=folder / "exports")


def browser_camera(scene, degrees: float) -> dict:
    """A browser camera as vtk.js sends it: the scene's eye turned ``degrees`` about the up axis."""
    c = scene.camera
    a = np.radians(degrees)
    offset = np.subtract(c.eye, c.focal_point)
    turn = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    return {"position": (np.add(c.focal_point, turn @ offset)).tolist(), "focalPoint": list(c.focal_point),
            "viewUp": list(c.up), "viewAngle": c.view_angle}
