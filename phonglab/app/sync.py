"""Cheaper full synchronisations of the local view: remember serialised meshes.

``VtkLocalView.update()`` serialises the whole render window, twice. For
every mesh, trame-vtk re-exports the triangle list in VTK's legacy layout
into a new array and hashes it (MD5 of 6.4 MB for a 100k-vertex sphere),
even when nothing about the mesh changed: about 20 ms per serialisation.
When a light moves, only the arrows and a few colours change.

:func:`install` registers a wrapper around trame-vtk's ``vtkPolyData``
serialiser (``register_instance_serializer``, trame-vtk's extension point).
The wrapper keys each result on the identity and modification time of
every array and cell array the dataset holds, and of the mapper settings
that choose its colour array. On a hit it returns the remembered result and
registers its arrays with the synchronisation context again, so the browser
can still fetch any of them by hash. Anything that changes an array (the
colours, a new mesh) changes the key, and the real serialiser runs.
"""

from __future__ import annotations

import copy
import time
import weakref
from collections import OrderedDict

#: remembered meshes per synchronisation context (one per browser session)
CACHE_SIZE = 16

_caches: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _ref(obj) -> str:
    from trame_vtk.modules.vtk.serializers.utils import reference_id

    return reference_id(obj)


def _arrays_key(fields) -> tuple:
    return tuple(
        (fields.GetArrayName(i), _ref(fields.GetAbstractArray(i)), fields.GetAbstractArray(i).GetMTime(),
         fields.IsArrayAnAttribute(i))
        for i in range(fields.GetNumberOfArrays())
    )


def signature(parent, dataset, dataset_id) -> tuple | None:
    """What a polydata's serialisation depends on; None when it cannot be told."""
    points = dataset.GetPoints()
    if points is None:
        return None
    cells = tuple(
        (_ref(c), c.GetMTime(), c.GetNumberOfCells()) if c is not None else None
        for c in (dataset.GetVerts(), dataset.GetLines(), dataset.GetPolys(), dataset.GetStrips())
    )
    mapper = ()
    if parent is not None and parent.IsA("vtkMapper"):
        mapper = (_ref(parent), parent.GetScalarVisibility(), parent.GetScalarMode(), parent.GetArrayAccessMode(),
                  parent.GetArrayName(), parent.GetArrayId())
    return (
        dataset_id,
        _ref(parent) if parent is not None else None,
        mapper,
        (_ref(points.GetData()), points.GetData().GetMTime()),
        cells,
        _arrays_key(dataset.GetPointData()),
        _arrays_key(dataset.GetCellData()),
    )


def _remembering(serializer):
    def serialize_polydata(parent, dataset, dataset_id, context, depth, *args, **kwargs):
        key = signature(parent, dataset, dataset_id) if not args and not kwargs else None
        if key is None:
            return serializer(parent, dataset, dataset_id, context, depth, *args, **kwargs)
        cache = _caches.setdefault(context, OrderedDict())
        hit = cache.get(key)
        if hit is not None:
            result, arrays = hit
            now = time.time()
            for data_hash, record in arrays:
                context.cache_data_array(data_hash, {**record, "ts": now})
            cache.move_to_end(key)
            return copy.deepcopy(result)
        # the real serialiser, noting every array it registers
        arrays = []
        register = context.cache_data_array

        def note(data_hash, record):
            arrays.append((data_hash, record))
            register(data_hash, record)

        context.cache_data_array = note
        try:
            result = serializer(parent, dataset, dataset_id, context, depth)
        finally:
            del context.cache_data_array  # back to the class's method
        if result is not None:
            cache[key] = (copy.deepcopy(result), arrays)
            while len(cache) > CACHE_SIZE:
                cache.popitem(last=False)
        return result

    serialize_polydata.__wrapped__ = serializer
    serialize_polydata._phonglab_remembering = True
    return serialize_polydata


def install() -> None:
    """Wrap trame-vtk's polydata serialiser, unless it is wrapped already.

    trame-vtk registers its serialisers again whenever a session's protocol
    starts, so this is called after every session start, not once.
    """
    from trame_vtk.modules.vtk.serializers import initialize_serializers
    from trame_vtk.modules.vtk.serializers.registry import SERIALIZERS, register_instance_serializer

    if "vtkPolyData" not in SERIALIZERS:
        initialize_serializers()
    current = SERIALIZERS["vtkPolyData"]
    if getattr(current, "_phonglab_remembering", False):
        return
    register_instance_serializer("vtkPolyData", _remembering(current))
