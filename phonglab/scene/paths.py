"""Where meshes come from: PyVista's shipped example meshes and mesh files.

Only file names and extensions are checked here; reading a mesh is the
renderer's job (``phonglab.render``). This module never imports PyVista: it
finds the installed package's folder with :func:`importlib.util.find_spec`,
which does not run the package.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

from phonglab.scene.errors import SceneError, did_you_mean
from phonglab.scene.meshsize import check_mesh_size

#: meshes that ship inside the pyvista package (``pyvista/examples/``), by name
PYVISTA_MESHES = {
    "airplane": "airplane.ply",
    "ant": "ant.ply",
    "globe": "globe.vtk",
    "hexbeam": "hexbeam.vtk",
    "nut": "nut.ply",
    "sphere": "sphere.ply",
}

#: file extensions of surface meshes PyVista reads
MESH_EXTENSIONS = (".ply", ".obj", ".stl", ".vtk", ".vtp", ".vtu", ".g", ".facet")

#: the longest mesh path a scene may give, in characters (Linux's PATH_MAX)
MAX_PATH_CHARS = 4096

#: the project's assets folder (scene files, meshes)
ASSETS_DIR = Path(__file__).resolve().parents[2] / "assets"


def pyvista_examples_dir() -> Path | None:
    """The ``examples`` folder of the installed pyvista package, or None."""
    spec = importlib.util.find_spec("pyvista")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(list(spec.submodule_search_locations)[0]) / "examples"


def check_mesh_name(name) -> str:
    """``name`` if it is one of :data:`PYVISTA_MESHES`; SceneError otherwise (no file is looked at)."""
    if name not in PYVISTA_MESHES:
        raise SceneError(
            "must be one of " + ", ".join(f'"{n}"' for n in PYVISTA_MESHES) + " (meshes shipped with pyvista)",
            field="name",
            value=name,
            hint=did_you_mean(name, PYVISTA_MESHES),
        )
    return name


def pyvista_mesh_path(name: str) -> Path:
    """The file of the shipped mesh ``name``.

    Raises
    ------
    SceneError
        If ``name`` is not one of :data:`PYVISTA_MESHES` or its file is absent.
    """
    check_mesh_name(name)
    folder = pyvista_examples_dir()
    path = folder / PYVISTA_MESHES[name] if folder else None
    if path is None or not path.is_file():
        raise SceneError(
            "names a mesh that is missing from the installed pyvista package",
            field="name",
            value=name,
            hint=f"looked for {path}" if path else "pyvista is not installed",
        )
    return path


def resolve_mesh_path(path: str, base_dir: str | os.PathLike | None = None) -> str:
    """An absolute, existing mesh file for ``path``.

    A relative path is looked up in ``base_dir`` (the scene file's folder;
    the current folder when None), then in ``assets/``.

    Raises
    ------
    SceneError
        If the path is longer than :data:`MAX_PATH_CHARS`, the extension is
        not a mesh format, the system refuses the name, or no file exists.
    """
    if not isinstance(path, str) or not path:
        raise SceneError("must be a mesh file name", field="path", value=path)
    if len(path) > MAX_PATH_CHARS or "\0" in path:
        problem = (f"is too long: {len(path):,} characters, at most {MAX_PATH_CHARS:,} allowed"
                   if len(path) > MAX_PATH_CHARS else "must not contain a NUL character")
        raise SceneError(problem, field="path", value=path)
    suffix = Path(path).suffix.lower()
    if suffix not in MESH_EXTENSIONS:
        raise SceneError(
            "must be a mesh file ending in " + " ".join(MESH_EXTENSIONS),
            field="path",
            value=path,
        )
    candidate = Path(path).expanduser()
    if candidate.is_absolute():
        tried = [candidate]
    else:
        folders = [Path(base_dir) if base_dir is not None else Path.cwd(), ASSETS_DIR]
        tried = [folder / candidate for folder in folders]
    for option in tried:
        try:
            if option.is_file():
                return str(option.resolve())
            if option.exists():  # a folder, a FIFO, a device: never opened
                raise SceneError("must name a regular mesh file, not a folder, FIFO or device", field="path",
                                 value=path)
        except OSError as exc:  # a name the system refuses (a part longer than 255 bytes, a loop of links)
            raise SceneError(f"cannot be used as a file name: {exc.strerror or exc}", field="path",
                             value=path) from None
    raise SceneError(
        "no such mesh file",
        field="path",
        value=path,
        hint="looked in " + ", ".join(str(t.parent) for t in tried),
    )


def check_geometry_source(kind: str, name, path) -> None:
    """Check that ``name`` and ``path`` fit the geometry ``kind``, without looking at any file.

    Raises
    ------
    SceneError
        A name on a kind other than "pyvista", a path on a kind other than
        "file", a missing name or path, a name that is not a shipped mesh.
    """
    if kind != "pyvista" and name is not None:
        raise SceneError('is only used with kind = "pyvista"', field="name", value=name)
    if kind != "file" and path is not None:
        raise SceneError('is only used with kind = "file"', field="path", value=path)
    if kind == "pyvista":
        if name is None:
            raise SceneError(
                'is required with kind = "pyvista"; one of ' + ", ".join(f'"{n}"' for n in PYVISTA_MESHES),
                field="name",
            )
        check_mesh_name(name)
    if kind == "file" and path is None:
        raise SceneError('is required with kind = "file": a mesh file such as "meshes/bunny.ply"', field="path")


def find_mesh_file(kind: str, name, path, base_dir=None) -> str | None:
    """The mesh file a geometry reads, checked on disk; None for the parametric kinds.

    Called once, when a scene is loaded: the shipped mesh must be present in
    the installed pyvista, a ``kind = "file"`` path must name an existing
    mesh file (see :func:`resolve_mesh_path`; the result is absolute).

    A mesh file's header is read too (:func:`phonglab.scene.meshsize.check_mesh_size`):
    a file past the size, vertex or triangle limits is refused here, before
    any reader allocates what it announces.

    Raises
    ------
    SceneError
        A shipped mesh missing from pyvista, a path that is not a mesh file,
        a mesh past the limits.
    """
    if kind == "pyvista":
        return str(pyvista_mesh_path(name))
    if kind == "file":
        found = resolve_mesh_path(path, base_dir)
        check_mesh_size(found)
        return found
    return None
