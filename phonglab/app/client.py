"""The browser side of the app: phonglab's Vue plugin and the colour push.

A slider that changes only the material re-shades the mesh but moves
nothing: only the mesh's colour array differs. trame-vtk's
``VtkLocalView.update()`` would serialise the whole scene twice (a delta for
the browser and a full state for late joiners), hash every array again, and
the browser would then ask for the new array in a second round trip. Instead
the server puts the new colour bytes in one state variable, and the
``<phonglab-colors>`` component (``www/phonglab.js``), placed inside the local
view, writes them into the browser's copy of that array and re-renders.

The server's render window keeps the same colours (the render layer updates
its array in place), so any later full synchronisation agrees with what the
browser shows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from trame_client.widgets.core import AbstractElement

#: folder served to the browser under ``/__phonglab``
WWW = Path(__file__).with_name("www")

#: trame module: serve ``www/``, load ``phonglab.js`` (the Vue plugin ``window.phonglab``) and ``formulas.js``
MODULE = {
    "serve": {"__phonglab": str(WWW)},
    "scripts": ["__phonglab/phonglab.js", "__phonglab/formulas.js"],
    "styles": ["__phonglab/phonglab.css"],
    "vue_use": ["phonglab"],
}


class ColorPush(AbstractElement):
    """``<phonglab-colors>``: applies colour pushes to the enclosing local view.

    Parameters
    ----------
    push : tuple
        The state binding, e.g. ``("view_colors", None)``.
    expect : tuple
        A binding, true when the server answers a turn of the view with
        colours (not while it sends a picture instead): only then may the
        browser hold a turned frame for them (see ``www/phonglab.js``).
    picture : tuple
        The binding of the core's picture over the view (per-pixel mode):
        the letters hidden during a drag come back with its next one.
    """

    def __init__(self, **kwargs):
        super().__init__("phonglab-colors", **kwargs)
        if self.server:
            self.server.enable_module(MODULE)
        self._attr_names += ["push", "expect", "picture"]


def dataset_id(mapper) -> str:
    """The id under which trame-vtk registers a mapper's input in the browser.

    trame-vtk names a mapper's dataset ``"<mapper reference id>-dataset"``.
    """
    from trame_vtk.modules.vtk.serializers.utils import reference_id

    return f"{reference_id(mapper)}-dataset"


def array_hash(vtk_array) -> str:
    """The hash under which trame-vtk sends ``vtk_array`` to a browser (and caches it, so it is not hashed twice)."""
    from trame_vtk.modules.vtk.serializers.helpers import digest

    return digest(vtk_array)


def color_payload(mapper, colors: np.ndarray, *, name: str, location: str, vtk_array=None) -> dict:
    """The state value for :class:`ColorPush`: which array, and its new bytes.

    Parameters
    ----------
    mapper : vtkMapper
        The mapper whose input holds the array.
    colors : ndarray
        The array's new values, in the array's own dtype and layout.
    name : str
        The array's name.
    location : {"point", "cell"}
        Point or cell data.
    vtk_array : vtkDataArray, optional
        The array itself, holding ``colors``: the payload then carries its
        trame-vtk ``hash``, and the browser files the bytes under it, so the
        next full synchronisation of the scene neither downloads the array
        again nor rebuilds the mesh.
    """
    if location not in ("point", "cell"):
        raise ValueError(f"location must be 'point' or 'cell', got {location!r}")
    payload = {
        "dataset": dataset_id(mapper),
        "name": name,
        "location": location,
        "data": np.ascontiguousarray(colors).tobytes(),
    }
    if vtk_array is not None:
        payload["hash"] = array_hash(vtk_array)
    return payload


#: state key the browser sets to the ``hash`` of the pushed colours it shows (None when it could not apply a
#: push), as a turn of the view starts and during it: not after a slider's push, which is whole anyway. A
#: value it has not updated names older colours than the last push, so the next push is whole: safe
SHOWN_KEY = "view_colors_shown"


def color_change(payload: dict, previous: dict | None, values: np.ndarray, base_values: np.ndarray | None) -> dict:
    """``payload`` as a change from the previous push, when that is smaller: only the rows that differ.

    Turning the view moves the highlight and nothing else (diffuse light does
    not depend on the eye): about 1 % of a sphere's vertices change colour.
    The change names the push it starts from (``base``: that push's
    ``hash``) and carries ``rows`` (uint32 row numbers) and ``values`` (those
    rows' new bytes) instead of ``data``. The browser applies it only to the
    colours of that push; otherwise it ignores it, and the next full
    synchronisation of the scene (the drag's end) brings the colours, and
    it sets :data:`SHOWN_KEY` to None so that the next push is whole. The
    caller sends a change only when :data:`SHOWN_KEY` is ``previous``'s hash.

    Parameters
    ----------
    payload : dict
        A :func:`color_payload` with its ``hash``.
    previous : dict or None
        The payload pushed before (None: nothing pushed yet).
    values, base_values : ndarray
        The new colours and those of ``previous``, row per point or cell.
    """
    if (previous is None or base_values is None or "hash" not in previous or "hash" not in payload
            or any(previous.get(key) != payload[key] for key in ("dataset", "name", "location"))
            or np.shape(base_values) != np.shape(values) or np.ndim(values) != 2):
        return payload
    values, base_values = np.asarray(values), np.asarray(base_values)
    rows = np.flatnonzero((values != base_values).any(axis=1)).astype(np.uint32)
    changed = np.ascontiguousarray(values[rows])
    if rows.nbytes + changed.nbytes >= len(payload["data"]) // 2:
        return payload  # most rows changed: the whole array is as cheap
    change = {key: value for key, value in payload.items() if key != "data"}
    change.update(base=previous["hash"], rows=rows.tobytes(), values=changed.tobytes())
    return change


class ArrowLetters(AbstractElement):
    """``<phonglab-letters>``: the letters N, L, R, V, H at the arrow tips of the enclosing local view.

    The browser projects each tip with its own camera on every frame the
    camera changes (so the letters follow a drag at once), places each
    letter just past its tip along the arrow, and moves a letter that would
    cover another one aside. vtk.js cannot draw VTK's text actors, hence HTML.

    Parameters
    ----------
    tips : tuple
        The state binding, e.g. ``("arrow_tips", [])``: see :func:`arrow_tips`.
    hidden : tuple
        A binding that hides the letters (pixel mode's image carries its own).
    camera : tuple
        A binding to the camera the tips were made for (``{"position": [x, y, z], "view_angle": degrees}``).
    covered : tuple
        A binding that is true while the core's picture covers the view: the
        letters then show only while the browser's camera is ``camera``, the
        camera of that picture (its numbers and tips come with it).
    """

    def __init__(self, **kwargs):
        super().__init__("phonglab-letters", **kwargs)
        if self.server:
            self.server.enable_module(MODULE)
        self._attr_names += ["tips", "hidden", "camera", "covered"]


def arrow_tips(tips, legend, hidden=()) -> list[dict]:
    """The state value for :class:`ArrowLetters`.

    Parameters
    ----------
    tips : sequence of (letter, base, tip)
        As :meth:`phonglab.render.SceneView.arrow_tips` gives them (world coordinates).
    legend : sequence of dict
        The page's legend entries (``letter``, ``color``): each letter's colour.
    hidden : collection of str
        Letters whose arrow tip the mesh hides from the camera
        (:meth:`phonglab.render.SceneView.hidden_letters`): marked ``behind``, not drawn.
    """
    colours = {entry["letter"]: entry["color"] for entry in legend}
    return [{"letter": letter, "base": [round(c, 6) for c in base], "tip": [round(c, 6) for c in tip],
             "color": colours.get(letter, "#ffffff"), "behind": letter in hidden} for letter, base, tip in tips]
