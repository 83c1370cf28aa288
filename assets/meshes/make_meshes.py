"""Generate the small example meshes in this folder (run: python assets/meshes/make_meshes.py).

``blob.ply``: a subdivided icosahedron with a smooth bump pattern, 642
vertices, written as ASCII PLY *without* normals, so the renderer has to
compute them. Pure NumPy: the output is the same on every machine.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def icosphere(subdivisions: int):
    """Vertices on the unit sphere and triangles of a subdivided icosahedron."""
    t = (1 + 5**0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(v, float) / np.linalg.norm(v) for v in verts]
    for _ in range(subdivisions):
        midpoint = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return np.array(verts), np.array(faces)


def blob():
    """The icosphere with a few smooth bumps: radius 1 + 0.15 sin(3x) sin(2y) cos(2z)."""
    verts, faces = icosphere(3)
    x, y, z = verts.T
    radius = 1 + 0.15 * np.sin(3 * x) * np.sin(2 * y + 0.5) * np.cos(2 * z)
    return verts * radius[:, None], faces


def write_ply(path: Path, verts, faces) -> None:
    """ASCII PLY with positions and triangles only; written to a temp file, then renamed."""
    lines = ["ply", "format ascii 1.0", "comment phonglab example mesh, see make_meshes.py",
             f"element vertex {len(verts)}", "property float x", "property float y", "property float z",
             f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    lines += [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
    lines += [f"3 {a} {b} {c}" for a, b, c in faces]
    tmp = path.with_suffix(".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(path)


if __name__ == "__main__":
    write_ply(HERE / "blob.ply", *blob())
    print(f"wrote {HERE / 'blob.ply'}")
