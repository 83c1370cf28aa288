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

from phonglab.scene.model import SceneError, did_you_mean

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

#: the project's assets folder (scene files, meshes)
ASSETS_DIR = Path(__file__).resolve().parents[2] / "assets"


def pyvista_examples_dir() -> Path | None:
    """The ``examples`` folder of the installed pyvista package, or None."""
    spec = importlib.util.find_spec("pyvista")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(list(spec.submodule_search_locations)[0]) / "examples"


def pyvista_mesh_path(name: str) -> Path:
    """The file of the shipped mesh ``name``.

    Raises
    ------
    SceneError
        If ``name`` is not one of :data:`PYVISTA_MESHES` or its file is absent.
    """
    if name not in PYVISTA_MESHES:
        raise SceneError(
            "must be one of " + ", ".join(f'"{n}"' for n in PYVISTA_MESHES) + " (meshes shipped with pyvista)",
            field="name",
            value=name,
            hint=did_you_mean(name, PYVISTA_MESHES),
        )
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
        If the extension is not a mesh format or no file exists.
    """
    if not isinstance(path, str) or not path:
        raise SceneError("must be a mesh file name", field="path", value=path)
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
        if option.is_file():
            return str(option.resolve())
    raise SceneError(
        "no such mesh file",
        field="path",
        value=path,
        hint="looked in " + ", ".join(str(t.parent) for t in tried),
    )


def check_geometry_source(kind: str, name, path, base_dir=None) -> tuple[str | None, str | None]:
    """Check ``name`` and ``path`` against the geometry ``kind``.

    Returns
    -------
    (name, path)
        ``path`` made absolute for ``kind="file"``.

    Raises
    ------
    SceneError
        A name on a kind other than "pyvista", a path on a kind other than
        "file", a missing or unknown name, a missing or unreadable file.
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
        pyvista_mesh_path(name)
    if kind == "file":
        if path is None:
            raise SceneError('is required with kind = "file": a mesh file such as "meshes/bunny.ply"', field="path")
        path = resolve_mesh_path(path, base_dir)
    return name, path


def mesh_file(geometry) -> Path | None:
    """The file to read for a geometry: the shipped mesh or the file; None if parametric."""
    if geometry.kind == "pyvista":
        return pyvista_mesh_path(geometry.name)
    if geometry.kind == "file":
        return Path(geometry.path)
    return None
