"""Limits a whole scene must keep, checked with its fields by every way in (file, --set, the page).

The fields of a scene are each checked where they are read; what is
checked here needs the scene's parts together, or bounds a field for the
sake of the work or the arithmetic downstream:

* every position, direction and probe coordinate (the camera's eye,
  focal point and up vector: in :class:`~phonglab.scene.parts.Camera`) is at most :data:`~phonglab.scene.schema.MAX_COORDINATE` in
  size: past it, a squared distance overflows float32 and labels are drawn
  at NaN;
* at most :data:`~phonglab.scene.schema.MAX_LIGHTS` lights;
* a Monte Carlo area light evaluates ``samples`` rays per shaded vertex: at
  most :data:`~phonglab.scene.schema.MAX_AREA_SAMPLE_POINTS` of them.

:func:`check_limits` is called by :func:`phonglab.scene.build.scene_parts`,
which loading, editing (``Scene.replace``, the page's controls) and the
command line all go through, so ``phonglab check``, ``phonglab export`` and
the page accept exactly the same scenes.
"""

from __future__ import annotations

from phonglab.scene.errors import SceneError, join_path
from phonglab.scene.meshsize import mesh_vertices
from phonglab.scene.schema import MAX_AREA_SAMPLE_POINTS, MAX_COORDINATE, MAX_LIGHTS

#: area-light methods that shoot ``samples`` rays per point
MONTE_CARLO_METHODS = ("uniform", "stratified")


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


def check_area_work(area, vertices: int | None) -> None:
    """Refuse a Monte Carlo area light whose samples × vertices pass :data:`MAX_AREA_SAMPLE_POINTS`."""
    if area is None or area.method not in MONTE_CARLO_METHODS or not vertices:
        return
    work = area.samples * vertices
    if work > MAX_AREA_SAMPLE_POINTS:
        most = max(1, MAX_AREA_SAMPLE_POINTS // vertices)
        raise SceneError(
            f"{area.samples} samples × {vertices:,} mesh vertices = {work:,} rays, at most "
            f"{MAX_AREA_SAMPLE_POINTS:,} allowed",
            field="area_light.samples",
            value=area.samples,
            hint=f"use at most {most} samples here, a lower geometry.resolution, or method = \"exact\"",
        )


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

    def run(fn, *args):
        try:
            fn(*args)
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
    if area is not None and not errors and parts.get("geometry") is not None:
        try:
            run(check_area_work, area, mesh_vertex_count(parts["geometry"]))
        except SceneError as exc:  # the mesh file's own problem was reported where it was read
            errors.append(exc.located(field="geometry"))
    return errors


__all__ = ["check_limits", "check_coordinates", "check_light_count", "check_area_work", "mesh_vertex_count",
           "MONTE_CARLO_METHODS"]
