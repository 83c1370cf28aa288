"""How big a mesh file is, read from its header before any reader allocates.

A mesh reader trusts the counts a file announces: a 200-byte PLY header that
claims two billion vertices makes it allocate tens of gigabytes. So a mesh
file is sized here first, cheaply, without PyVista:

* every format: the file size, at most :data:`~phonglab.scene.schema.MAX_MESH_BYTES`;
* PLY: the ``element vertex N`` and ``element face N`` lines of its header;
* OBJ: the ``v`` lines and the triangles the ``f`` lines make (a face of
  ``k`` corners makes ``k - 2``);
* STL: the binary count (checked against the file size) or the ASCII
  ``facet`` count; each triangle brings three vertices;
* legacy VTK: the ``POINTS``, ``POLYGONS``, ``TRIANGLE_STRIPS`` and
  ``CELLS`` counts; XML VTK: ``NumberOfPoints`` and ``NumberOfPolys``/``NumberOfCells``;
* other formats: the file size alone.

The counts are then held against :data:`~phonglab.scene.schema.MAX_MESH_VERTICES`
and :data:`~phonglab.scene.schema.MAX_MESH_TRIANGLES`.
"""

from __future__ import annotations

import functools
import os
import re
import struct

from phonglab.scene.errors import SceneError
from phonglab.scene.schema import MAX_MESH_BYTES, MAX_MESH_TRIANGLES, MAX_MESH_VERTICES

#: bytes read for a header (PLY headers and legacy VTK headers are short)
HEADER_BYTES = 64 * 1024


def _ply_counts(head: bytes) -> tuple[int | None, int | None]:
    """Vertex and face counts from a PLY header (None when not announced)."""
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        raise ValueError("is not a PLY file (no ply ... end_header header)")
    counts = dict(re.findall(rb"^element[ \t]+(\w+)[ \t]+(\d+)", head[:end], re.M))
    vertices = int(counts[b"vertex"]) if b"vertex" in counts else None
    faces = int(counts[b"face"]) if b"face" in counts else None
    return vertices, faces


def _obj_counts(data: bytes) -> tuple[int, int]:
    """Vertex lines and the triangles that the face lines make."""
    vertices = len(re.findall(rb"^[ \t]*v[ \t]", data, re.M))
    triangles = 0
    for corners in re.findall(rb"^[ \t]*f[ \t]+([^\r\n]*)", data, re.M):
        triangles += max(0, len(corners.split()) - 2)
    return vertices, triangles


def _stl_counts(data: bytes, size: int) -> tuple[int, int]:
    """Three vertices per triangle; binary count checked against the file size."""
    if size >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * n == size:
            return 3 * n, n
    if data.lstrip()[:5].lower() == b"solid":
        n = len(re.findall(rb"\bfacet\b", data))
        return 3 * n, n
    raise ValueError("is not an STL file (its triangle count does not match its size)")


def _vtk_counts(data: bytes) -> tuple[int, int]:
    """Points and cells announced by a legacy (``POINTS n``) or XML (``NumberOfPoints="n"``) VTK file."""
    points = [int(n) for n in re.findall(rb"^[ \t]*POINTS[ \t]+(\d+)", data, re.M)]
    points += [int(n) for n in re.findall(rb'NumberOfPoints="(\d+)"', data)]
    cells = [int(n) for n in re.findall(rb"^[ \t]*(?:POLYGONS|TRIANGLE_STRIPS|CELLS)[ \t]+(\d+)", data, re.M)]
    cells += [int(n) for n in re.findall(rb'NumberOf(?:Polys|Strips|Cells)="(\d+)"', data)]
    return sum(points), sum(cells)


def mesh_counts(path) -> tuple[int | None, int | None]:
    """The vertices and triangles a mesh file announces, read without PyVista.

    Returns
    -------
    vertices, triangles : int or None
        None where the format does not say (only the file size is checked).

    Raises
    ------
    SceneError
        The file is larger than :data:`MAX_MESH_BYTES`, cannot be read, or
        its header is malformed.
    """
    try:
        size = os.path.getsize(path)
        if size > MAX_MESH_BYTES:
            raise SceneError(f"is too large a mesh file: {size:,} bytes, at most {MAX_MESH_BYTES:,} allowed",
                             field="path", value=os.fspath(path))
        suffix = os.path.splitext(os.fspath(path))[1].lower()
        with open(path, "rb") as f:
            data = f.read(HEADER_BYTES) if suffix == ".ply" else f.read()
    except OSError as exc:
        raise SceneError(f"cannot read the mesh file: {exc.strerror}", field="path", value=os.fspath(path)) from None
    try:
        if suffix == ".ply":
            return _ply_counts(data)
        if suffix == ".obj":
            return _obj_counts(data)
        if suffix == ".stl":
            return _stl_counts(data, size)
        if suffix in (".vtk", ".vtp", ".vtu"):
            return _vtk_counts(data)
    except ValueError as exc:
        raise SceneError(str(exc), field="path", value=os.fspath(path)) from None
    return None, None


def check_mesh_size(path) -> None:
    """Refuse a mesh file past the size, vertex or triangle limit, before it is read.

    Raises
    ------
    SceneError
        On field ``path``, naming the count and the limit.
    """
    vertices, triangles = mesh_counts(path)
    if vertices is not None and vertices > MAX_MESH_VERTICES:
        raise SceneError(f"has too many vertices: {vertices:,}, at most {MAX_MESH_VERTICES:,} allowed",
                         field="path", value=os.fspath(path))
    if triangles is not None and triangles > MAX_MESH_TRIANGLES:
        raise SceneError(f"has too many triangles: {triangles:,}, at most {MAX_MESH_TRIANGLES:,} allowed",
                         field="path", value=os.fspath(path))


def mesh_vertices(path) -> int | None:
    """The vertex count a mesh file announces (None when its format does not say).

    Remembered per file version (path, size, modification time): the page
    asks on every edit of a scene with a Monte Carlo area light.
    """
    try:
        stat = os.stat(path)
    except OSError:
        return None
    return _cached_vertices(os.fspath(path), stat.st_size, stat.st_mtime_ns)


@functools.lru_cache(maxsize=32)
def _cached_vertices(path: str, size: int, stamp: int) -> int | None:
    return mesh_counts(path)[0]
