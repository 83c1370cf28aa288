"""Exact visibility in NumPy: camera rays, the analytic sphere and triangle meshes.

The accuracy studies need to know, for every pixel, which surface point the
camera sees, without any rasterizer's own rounding in the way. Each pixel
casts one ray through its centre from the eye:

- :func:`hit_sphere` intersects the rays with the exact sphere (the
  reference: exact position and normal, float64);
- :func:`hit_mesh` intersects them with every triangle of a mesh that can
  cover the pixel (Möller–Trumbore), keeps the nearest hit, and returns the
  triangle and the barycentric weights of the hit point. Barycentric weights
  of the 3-D hit point are exactly the perspective-correct weights a GPU
  interpolates with.

The camera follows VTK's conventions: ``view_angle`` is the vertical field of
view in degrees, row 0 is the top of the image.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["View", "Rays", "camera_rays", "hit_sphere", "MeshHits", "hit_mesh"]


@dataclass(frozen=True)
class View:
    """A pinhole camera and an image size.

    Attributes
    ----------
    eye, focal_point, up : 3 floats
    view_angle : float
        Vertical field of view, degrees.
    width, height : int
        Image size in pixels.
    """

    eye: tuple[float, float, float] = (0.0, 0.0, 4.0)
    focal_point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    view_angle: float = 30.0
    width: int = 128
    height: int = 128

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit ``forward``, ``right`` and ``up`` vectors of the camera, float64."""
        eye = np.asarray(self.eye, dtype=np.float64)
        forward = np.asarray(self.focal_point, dtype=np.float64) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, self.up)
        right /= np.linalg.norm(right)
        return forward, right, np.cross(right, forward)

    def scale(self) -> tuple[float, float]:
        """Half-width and half-height of the image plane at distance 1."""
        half_h = math.tan(math.radians(self.view_angle) / 2)
        return half_h * self.width / self.height, half_h


@dataclass(frozen=True)
class Rays:
    """One ray per pixel: ``origin + t·directions[row, col]``."""

    origin: np.ndarray  # (3,)
    directions: np.ndarray  # (height, width, 3), unit


def camera_rays(view: View) -> Rays:
    """The rays through the pixel centres of ``view``, float64."""
    forward, right, up = view.basis()
    half_w, half_h = view.scale()
    # pixel centres on the image plane at distance 1: x to the right, y up
    x = ((np.arange(view.width) + 0.5) / view.width * 2 - 1) * half_w
    y = (1 - (np.arange(view.height) + 0.5) / view.height * 2) * half_h
    d = forward + x[None, :, None] * right + y[:, None, None] * up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return Rays(origin=np.asarray(view.eye, dtype=np.float64), directions=d)


def hit_sphere(rays: Rays, centre=(0.0, 0.0, 0.0), radius: float = 1.0):
    """Where each ray first meets the exact sphere.

    Returns
    -------
    points, normals : ndarray, shape (height, width, 3), float64
        Hit point and exact outward unit normal (NaN where missed).
    mask : ndarray of bool, shape (height, width)

    Notes
    -----
    With ``q = origin − centre`` and unit ``d``, ``t² + 2 (q·d) t + |q|² − r² = 0``;
    the near root is taken as ``t = c / (−b + √disc)`` (with ``b = q·d``,
    ``c = |q|² − r²``), which avoids the cancellation of ``−b − √disc``.
    """
    centre = np.asarray(centre, dtype=np.float64)
    q = rays.origin - centre
    d = rays.directions
    b = d @ q
    c = q @ q - radius * radius
    disc = b * b - c
    mask = (disc >= 0) & (b < 0)
    root = np.sqrt(np.where(mask, disc, 0))
    denom = np.where(mask, -b + root, 1)
    t = np.where(mask, c / denom, np.nan)
    points = rays.origin + t[..., None] * d
    normals = (points - centre) / radius
    return points, normals, mask


@dataclass(frozen=True)
class MeshHits:
    """The nearest triangle hit through each pixel.

    Attributes
    ----------
    mask : ndarray of bool, (height, width)
        True where the ray hits the mesh.
    triangle : ndarray of int, (n_hit,)
        The triangle hit, for the pixels of ``mask`` in row-major order.
    weights : ndarray, (n_hit, 3), float64
        Barycentric weights of the hit point in that triangle (sum 1).
    points : ndarray, (n_hit, 3), float64
        The hit points.
    """

    mask: np.ndarray
    triangle: np.ndarray
    weights: np.ndarray
    points: np.ndarray


def _pixel_boxes(view: View, corners: np.ndarray):
    """Pixel-centre bounding boxes of triangles, ``(col0, col1, row0, row1)`` inclusive.

    ``corners`` is (T, 3, 3). Triangles reaching behind the eye get the whole
    image (the projection is not valid there).
    """
    forward, right, up = view.basis()
    half_w, half_h = view.scale()
    q = corners - np.asarray(view.eye, dtype=np.float64)
    depth = q @ forward
    safe = np.where(depth > 0, depth, 1)
    # image-plane coordinates -> pixel coordinates (centre of pixel j is j)
    col = ((q @ right) / safe / half_w + 1) / 2 * view.width - 0.5
    row = (1 - (q @ up) / safe / half_h) / 2 * view.height - 0.5
    behind = (depth <= 0).any(axis=1)
    c0 = np.where(behind, 0, np.floor(col.min(axis=1)))
    c1 = np.where(behind, view.width - 1, np.ceil(col.max(axis=1)))
    r0 = np.where(behind, 0, np.floor(row.min(axis=1)))
    r1 = np.where(behind, view.height - 1, np.ceil(row.max(axis=1)))
    c0, r0 = np.maximum(c0, 0), np.maximum(r0, 0)
    c1, r1 = np.minimum(c1, view.width - 1), np.minimum(r1, view.height - 1)
    return c0.astype(np.int64), c1.astype(np.int64), r0.astype(np.int64), r1.astype(np.int64)


def hit_mesh(view: View, points, triangles, *, rays: Rays | None = None, block: int = 1 << 20) -> MeshHits:
    """Cast the view's pixel rays at a triangle mesh, exactly, in float64.

    Parameters
    ----------
    view : View
    points : array_like, (V, 3)
    triangles : array_like of int, (T, 3)
    rays : Rays, optional
        ``camera_rays(view)``, if already made.
    block : int
        Candidate (triangle, pixel) pairs tested at once.

    Returns
    -------
    MeshHits

    Notes
    -----
    Candidates are the pixels whose centre lies in a triangle's projected
    bounding box; each is tested with Möller–Trumbore:

    .. math:: o + t d = (1 - u - w) a + u b + w c, \\quad u, w \\ge 0, \\; u + w \\le 1, \\; t > 0

    and the smallest ``t`` per pixel wins. A tolerance of ``1e-12`` on the
    barycentric tests keeps rays through a shared edge from slipping between
    the two triangles.
    """
    rays = camera_rays(view) if rays is None else rays
    p = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    corners = p[tri]  # (T, 3, 3)
    c0, c1, r0, r1 = _pixel_boxes(view, corners)
    widths = np.maximum(c1 - c0 + 1, 0)
    counts = widths * np.maximum(r1 - r0 + 1, 0)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    total = int(offsets[-1])
    edge1 = corners[:, 1] - corners[:, 0]
    edge2 = corners[:, 2] - corners[:, 0]
    directions = rays.directions.reshape(-1, 3)
    eps = 1e-12

    found_pixel, found_t, found_tri, found_uv = [], [], [], []
    for start in range(0, total, block):
        stop = min(start + block, total)
        k = np.arange(start, stop)
        # which triangle and which pixel of its box each candidate is
        t_id = np.searchsorted(offsets, k, side="right") - 1
        local = k - offsets[t_id]
        col = c0[t_id] + local % widths[t_id]
        row = r0[t_id] + local // widths[t_id]
        pixel = row * view.width + col
        d = directions[pixel]
        e1, e2 = edge1[t_id], edge2[t_id]
        # Möller–Trumbore
        pvec = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, pvec)
        ok = np.abs(det) > 0
        inv = 1.0 / np.where(ok, det, 1.0)
        tvec = rays.origin - corners[t_id, 0]
        u = np.einsum("ij,ij->i", tvec, pvec) * inv
        qvec = np.cross(tvec, e1)
        w = np.einsum("ij,ij->i", d, qvec) * inv
        t = np.einsum("ij,ij->i", e2, qvec) * inv
        ok &= (u >= -eps) & (w >= -eps) & (u + w <= 1 + eps) & (t > 0)
        found_pixel.append(pixel[ok])
        found_t.append(t[ok])
        found_tri.append(t_id[ok])
        found_uv.append(np.stack([u[ok], w[ok]], axis=1))

    pixel = np.concatenate(found_pixel)
    t = np.concatenate(found_t)
    t_id = np.concatenate(found_tri)
    uv = np.concatenate(found_uv) if found_uv else np.zeros((0, 2))
    # nearest hit per pixel: sort by pixel, then by distance, keep the first
    order = np.lexsort((t, pixel))
    pixel, t, t_id, uv = pixel[order], t[order], t_id[order], uv[order]
    first = np.ones(pixel.size, dtype=bool)
    first[1:] = pixel[1:] != pixel[:-1]
    pixel, t, t_id, uv = pixel[first], t[first], t_id[first], uv[first]

    mask = np.zeros(view.height * view.width, dtype=bool)
    mask[pixel] = True
    u = np.clip(uv[:, 0], 0, 1)
    w = np.clip(uv[:, 1], 0, 1)
    s = np.maximum(u + w, 1)  # a hit a hair outside the edge is put back on it
    weights = np.stack([1 - (u + w) / s, u / s, w / s], axis=1)
    hit_points = rays.origin + t[:, None] * directions[pixel]
    # pixels come out sorted, i.e. in row-major order, like image[mask]
    return MeshHits(mask=mask.reshape(view.height, view.width), triangle=t_id, weights=weights, points=hit_points)
