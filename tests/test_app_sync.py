"""The remembering polydata serialiser gives trame-vtk's results, faster, and follows every change."""

from __future__ import annotations

import numpy as np
import pytest

from phonglab.app import sync
from phonglab.bench.scenes import red_sphere
from phonglab.render import SceneView
from phonglab.render.glyphs import COLOR_ARRAY


@pytest.fixture(scope="module")
def view():
    v = SceneView(red_sphere(32), size=(200, 150), labels=False, vtk_text=False)
    yield v
    v.close()


def serialize_twice(window, remembering: bool):
    from trame_vtk.modules.vtk.serializers import SynchronizationContext, initialize_serializers, serialize

    initialize_serializers()  # trame-vtk's own serialisers
    if remembering:
        sync.install()
    context = SynchronizationContext()
    context.set_ignore_last_dependencies(True)  # whole states, as for a new subscription
    return context, serialize(None, window, "w", context, 1), serialize(None, window, "w", context, 1)


def hashes(state) -> list[str]:
    from trame_vtk.modules.vtk.serializers import extract_array_hash

    return sorted(entry["hash"] for entry in extract_array_hash(state))


def test_results_equal_trame_vtks_own(view):
    _, plain, _ = serialize_twice(view.render_window, remembering=False)
    context, first, second = serialize_twice(view.render_window, remembering=True)
    assert first == plain and second == plain
    # every array the state names can be fetched from the context
    for data_hash in hashes(second):
        assert context.get_cached_data_array(data_hash, binary=True), data_hash


def test_a_changed_colour_array_is_serialised_again(view):
    context, before, _ = serialize_twice(view.render_window, remembering=True)
    from trame_vtk.modules.vtk.serializers import serialize

    colours = view.mesh.point_data[COLOR_ARRAY]
    colours[...] = 255 - np.asarray(colours)
    view.mesh.point_data.GetArray(COLOR_ARRAY).Modified()
    after = serialize(None, view.render_window, "w", context, 1)
    changed = set(hashes(after)) - set(hashes(before))
    assert len(changed) == 1, f"expected only the colour array to change, got {changed}"
    new_hash = changed.pop()
    data = np.frombuffer(context.get_cached_data_array(new_hash, binary=True), np.uint8)
    assert np.array_equal(data, np.asarray(colours).ravel())


def test_install_twice_wraps_once():
    from trame_vtk.modules.vtk.serializers.registry import SERIALIZERS

    sync.install()
    first = SERIALIZERS["vtkPolyData"]
    sync.install()
    assert SERIALIZERS["vtkPolyData"] is first
    assert not getattr(first.__wrapped__, "_phonglab_remembering", False)


def test_the_mesh_goes_to_the_browser_without_its_normals(view):
    from phonglab.app.client import dataset_id

    # the browser draws with lighting off: it gets points, triangles and colours only
    _, state, _ = serialize_twice(view.render_window, remembering=True)
    mesh_id = dataset_id(view.mesh_actor.GetMapper())

    def find(node):
        if isinstance(node, dict):
            if node.get("id") == mesh_id:
                return node
            node = list(node.values())
        if isinstance(node, list):
            for item in node:
                found = find(item)
                if found is not None:
                    return found
        return None

    mesh = find(state)
    assert mesh is not None, f"no dataset {mesh_id} in the serialised window"
    names = [field["name"] for field in mesh["properties"]["fields"]]
    assert names == [COLOR_ARRAY], f"the mesh sends {names}"
    # the server keeps the normals for the core's shading
    assert view.mesh.point_data["Normals"].shape == (view.mesh.n_points, 3)


def test_letters_the_mesh_hides_are_sent_as_behind():
    from phonglab.app.client import arrow_tips

    tips = [("N", (0, 0, 1), (0, 0, 2)), ("L", (0, 0, 1), (1, 0, 2))]
    legend = [{"letter": "N", "color": "#112233"}, {"letter": "L", "color": "#445566"}]
    sent = arrow_tips(tips, legend, hidden={"L"})
    assert [(t["letter"], t["behind"]) for t in sent] == [("N", False), ("L", True)], sent
    assert [t["color"] for t in sent] == ["#112233", "#445566"], sent
