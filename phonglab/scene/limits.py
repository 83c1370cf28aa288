"""Limits a whole scene must keep, checked with its fields by every way in (file, --set, the page).

The fields of a scene are each checked where they are read; what is
checked here needs the scene's parts together, or bounds a field for the
sake of the work or the arithmetic downstream:

* every position, direction and probe coordinate (the camera's eye,
  focal point and up vector: in :class:`~phonglab.scene.parts.Camera`) is at most :data:`~phonglab.scene.schema.MAX_COORDINATE` in
  size: past it, a squared distance overflows float32 and labels are drawn
  at NaN;
* at most :data:`~phonglab.scene.schema.MAX_LIGHTS` lights;
* the exposure at most :data:`~phonglab.scene.schema.EXPOSURE_LIMIT`: with
  it, the core's limits on coefficients, intensities and exponents keep every
  value the shading and display steps form finite in float32 (the
  derivation is in :mod:`phonglab.core.model`);
* a Monte Carlo area light evaluates ``samples`` rays per shaded point: at
  most :data:`~phonglab.scene.schema.MAX_AREA_SAMPLE_POINTS` of them. The
  shaded points are the mesh's vertices, or in a per-pixel scene
  (``interpolation = "pixel"``) the picture's pixels: checked here for a
  picture of :data:`PIXEL_PICTURE` pixels (the largest view the page
  shades per pixel), and again by :func:`check_picture_work` once an
  export's size is known.

:func:`check_limits` is called by :func:`phonglab.scene.build.scene_parts`,
which loading, editing (``Scene.replace``, the page's controls) and the
command line all go through, so ``phonglab check``, ``phonglab export`` and
the page accept exactly the same scenes.
"""

from __future__ import annotations

from phonglab.scene.errors import SceneError, join_path
from phonglab.scene.meshsize import mesh_vertices
from phonglab.core.model import limit_text
from phonglab.scene.schema import EXPOSURE_LIMIT, MAX_AREA_SAMPLE_POINTS, MAX_COORDINATE, MAX_LIGHTS

#: area-light methods that shoot ``samples`` rays per point
MONTE_CARLO_METHODS = ("uniform", "stratified")
#: pixels a per-pixel scene's area light is checked for before the picture's size is known:
#: the largest view the page shades per pixel, 1600 × 1600 (``phonglab.app.view_input.MAX_PIXEL_SIDE``)
PIXEL_PICTURE = 1600 * 1600


def check_coordinates(path: str, vector) -> None:
    """Refuse a vector with a coordinate larger than :data:`MAX_COORDINATE` in size.

    Raises
    ------
    SceneError
        Naming the field, the vector and the bound.
    """
    if vector is not None and any(abs(float(c)) > MAX_COORDINATE for c in vector):
        raise SceneError(f"must have every coordinate within ±{MAX_COORDINATE:,.0f} scene units", field=path,
                         value=tuple(vector))


def check_light_count(count: int) -> None:
    """Refuse more than :data:`MAX_LIGHTS` lights."""
    if count > MAX_LIGHTS:
        raise SceneError(f"has {count} lights, at most {MAX_LIGHTS} allowed", field="lights")


def check_exposure(exposure) -> None:
    """Refuse an exposure above :data:`~phonglab.scene.schema.EXPOSURE_LIMIT` (its lower bound is the field's own check)."""
    if exposure is not None and float(exposure) > EXPOSURE_LIMIT:
        raise SceneError(f"must be a finite number in (0, {limit_text(EXPOSURE_LIMIT)}]", field="exposure", value=exposure)


def mesh_vertex_count(geometry) -> int | None:
    """About how many vertices the geometry's mesh has (None when unknown).

    Parametric shapes follow the resolution ``n`` (see
    :func:`phonglab.render.mesh.build_mesh`); a mesh file says so in its header.
    """
    n = int(geometry.resolution)
    half = max(3, n // 2)
    if geometry.kind == "sphere":
        return n * (half + 1)
    if geometry.kind in ("torus", "supertoroid"):
        return (n + 1) * (half + 1)
    if geometry.kind == "plane":
        return (n + 1) ** 2
    if geometry.kind == "cube":
        side = max(1, n // 4) + 1
        return 6 * side * side
    if geometry.kind == "cylinder":
        return 4 * (n + 1)
    if geometry.kind == "file" and geometry.path:
        return mesh_vertices(geometry.path)
    return None


def check_area_work(area, vertices: int | None, *, pixels: int | None = None) -> None:
    """Refuse a Monte Carlo area light whose samples × shaded points pass :data:`MAX_AREA_SAMPLE_POINTS`.

    The shaded points are ``pixels`` when given (a per-pixel picture of that
    many pixels), else the mesh's ``vertices``.
    """
    if area is None or area.method not in MONTE_CARLO_METHODS:
        return
    points = pixels if pixels is not None else vertices
    if not points:
        return
    work = area.samples * points
    if work > MAX_AREA_SAMPLE_POINTS:
        most = max(1, MAX_AREA_SAMPLE_POINTS // points)
        if pixels is not None:
            what, smaller = "pixels shaded per pixel", "a smaller picture, interpolation = \"gouraud\""
        else:
            what, smaller = "mesh vertices", "a lower geometry.resolution"
        raise SceneError(
            f"{area.samples} samples × {points:,} {what} = {work:,} rays, at most "
            f"{MAX_AREA_SAMPLE_POINTS:,} allowed",
            field="area_light.samples",
            value=area.samples,
            hint=f"use at most {most} samples here, {smaller}, or method = \"exact\"",
        )


def shaded_points(scene_or_parts, *, pixels: int | None = None) -> tuple[int | None, int | None]:
    """``(vertices, pixels)`` a scene's area light is evaluated at: one of them is None.

    A per-pixel scene shades ``pixels`` points (:data:`PIXEL_PICTURE` when
    None); any other shades its mesh's vertices (every object's).
    """
    get = scene_or_parts.get if isinstance(scene_or_parts, dict) else lambda key: getattr(scene_or_parts, key)
    if get("interpolation") == "pixel":
        return None, int(pixels if pixels is not None else PIXEL_PICTURE)
    objects = get("objects") or ()
    if len(objects) > 1:  # every object's vertices are shaded
        counts = [mesh_vertex_count(o.geometry) for o in objects]
        return (None if None in counts else sum(counts)), None
    return mesh_vertex_count(get("geometry")), None


def check_picture_work(scene, pixels: int) -> None:
    """Refuse rendering ``scene`` as a picture of ``pixels`` pixels when its area light's work passes the limit.

    Only a per-pixel scene's work depends on the picture's size; call this
    before rendering a picture larger than :data:`PIXEL_PICTURE` (an export
    at its size × supersample²).

    Raises
    ------
    SceneError
        Naming ``area_light.samples``, the rays and the limit.
    """
    if scene.area_light is None or scene.interpolation != "pixel":
        return
    check_area_work(scene.area_light, None, pixels=int(pixels))


def _light_vectors(light, table, path):
    """(field path, vector) of a light's position and direction, named as its table names them."""
    named_homogeneous = isinstance(table, dict) and "homogeneous" in table
    for key in ("position", "direction"):
        vector = getattr(light, key, None)
        if vector is not None:
            yield join_path(path, "homogeneous" if named_homogeneous else key), vector


def check_limits(parts: dict, data: dict) -> list[SceneError]:
    """Every limit problem of a scene's checked parts (``data`` is its table form, for field names)."""
    errors = []

    def run(fn, *args, **kwargs):
        try:
            fn(*args, **kwargs)
        except SceneError as exc:
            errors.append(exc)

    lights = parts.get("lights") or ()
    run(check_light_count, len(lights))
    tables = data.get("lights") if isinstance(data.get("lights"), list) else []
    for i, light in enumerate(lights[:MAX_LIGHTS + 1]):
        table = tables[i] if i < len(tables) else None
        for path, vector in _light_vectors(light, table, f"lights[{i}]"):
            run(check_coordinates, path, vector)
    area = parts.get("area_light")
    if area is not None:
        for key in ("position", "edge_u", "edge_v"):
            run(check_coordinates, f"area_light.{key}", getattr(area.light, key, None))
    run(check_coordinates, "probe", parts.get("probe"))
    run(check_exposure, parts.get("exposure"))
    if area is not None and not errors and parts.get("geometry") is not None:
        try:
            vertices, pixels = shaded_points(parts)
            run(check_area_work, area, vertices, pixels=pixels)
        except SceneError as exc:  # the mesh file's own problem was reported where it was read
            errors.append(exc.located(field="geometry"))
    return errors


__all__ = ["check_limits", "check_coordinates", "check_light_count", "check_exposure", "check_area_work", "mesh_vertex_count",
           "shaded_points", "check_picture_work", "MONTE_CARLO_METHODS", "PIXEL_PICTURE"]
