"""The lesson-format reference (lessons/FORMAT.md) against the tables the loader enforces, both ways."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from phonglab.scene import MESH_EXTENSIONS, PYVISTA_MESHES, lesson_files, schema
from phonglab.teaching.mistakes import MISTAKES

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "lessons" / "FORMAT.md"


def tables(text: str) -> dict[str, list[list[list[str]]]]:
    """heading -> its Markdown tables, each a list of rows of cells (header and rule rows left out)."""
    found: dict[str, list] = {}
    heading, current = None, None
    for line in text.splitlines():
        if line.startswith("#"):
            heading, current = line.lstrip("#").strip(), None
            found.setdefault(heading, [])
        elif line.startswith("|") and heading is not None:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if current is None:
                current = []
                found[heading].append(current)
                continue  # the header row
            if set("".join(cells)) <= set("-: "):
                continue  # the rule row
            current.append(cells)
        else:
            current = None
    return found


TABLES = tables(REFERENCE.read_text(encoding="utf-8"))
ALL_LIGHT_KEYS = {"type", *schema.HOMOGENEOUS_KEYS, *(k for keys in schema.LIGHT_KEYS.values() for k in keys)}
#: section heading -> the keys the loader allows there
SECTIONS = {
    "scene keys": set(schema.SCENE_KEYS),
    "lesson keys": set(schema.LESSON_KEYS),
    "[geometry]": set(schema.GEOMETRY_KEYS),
    "[material]": set(schema.MATERIAL_KEYS),
    "[[objects]]": set(schema.OBJECT_KEYS),
    "[[lights]]": ALL_LIGHT_KEYS,
    "[camera]": set(schema.CAMERA_KEYS),
    "[area_light]": set(schema.AREA_LIGHT_KEYS),
    "[[experiments]]": set(schema.EXPERIMENT_KEYS),
    "[[claims]]": set(schema.CLAIM_KEYS),
    "[check]": set(schema.CHECK_KEYS),
}


def rows(section: str) -> dict[str, list[str]]:
    """key -> its row (key, type, default, allowed) in the section's first table."""
    assert TABLES.get(section), f"{REFERENCE.name}: no table under the heading {section!r}"
    out = {}
    for cells in TABLES[section][0]:
        key = re.fullmatch(r"`([^`]+)`", cells[0])
        assert key and len(cells) == 4, f"{REFERENCE.name} [{section}]: row {cells} is not | `key` | type | default | allowed |"
        out[key.group(1)] = cells
    return out


@pytest.mark.parametrize("section", list(SECTIONS))
def test_every_key_is_documented_and_every_documented_key_exists(section):
    documented = set(rows(section))
    allowed = SECTIONS[section]
    assert documented == allowed, (f"{section}: in the loader, not documented: {sorted(allowed - documented)}; "
                                   f"documented, not in the loader: {sorted(documented - allowed)}")


@pytest.mark.parametrize("section, required", [
    ("[material]", schema.MATERIAL_REQUIRED),
    ("[[claims]]", schema.CLAIM_REQUIRED),
    ("[[experiments]]", ("label",)),
    ("[geometry]", ("kind",)),
])
def test_required_keys_say_so(section, required):
    table = rows(section)
    for key in required:
        assert table[key][2] == "required", f"{section}.{key}: default column {table[key][2]!r}, expected 'required'"


@pytest.mark.parametrize("section, key, values", [
    ("scene keys", "model", schema.MODELS),
    ("scene keys", "interpolation", schema.INTERPOLATIONS),
    ("[geometry]", "kind", schema.GEOMETRY_KINDS),
    ("[geometry]", "name", tuple(PYVISTA_MESHES)),
    ("[geometry]", "path", MESH_EXTENSIONS),
    ("[area_light]", "method", schema.AREA_METHODS),
    ("[[lights]]", "type", tuple(schema.LIGHT_KEYS)),
    ("lesson keys", "mistake", tuple(MISTAKES)),
])
def test_allowed_values_are_listed(section, key, values):
    allowed = rows(section)[key][3]
    missing = [v for v in values if f"`\"{v}\"`" not in allowed and f"`{v}`" not in allowed]
    assert not missing, f"{section}.{key}: allowed values not listed: {missing} (row says {allowed!r})"


def test_defaults_match_the_code():
    from phonglab import core
    from phonglab.scene import Camera, Geometry

    assert rows("[geometry]")["resolution"][2] == f"`{Geometry.__dataclass_fields__['resolution'].default}`"
    camera = rows("[camera]")
    for key in ("eye", "focal_point", "up"):
        default = Camera.__dataclass_fields__[key].default
        assert camera[key][2] == "`[" + ", ".join(f"{x:g}" for x in default) + "]`", (key, camera[key][2], default)
    assert camera["view_angle"][2] == f"`{Camera.__dataclass_fields__['view_angle'].default:g}`"
    spot = rows("[[lights]]")
    assert spot["cutoff"][2] == f"`{core.SpotLight.__dataclass_fields__['cutoff'].default:g}`"
    assert spot["exponent"][2] == f"`{core.SpotLight.__dataclass_fields__['exponent'].default:g}`"
    assert rows("[material]")["opacity"][2] == f"`{core.Material.__dataclass_fields__['opacity'].default:g}`"
    for key, value in schema.SCENE_DEFAULTS.items():
        shown = rows("scene keys")[key][2]
        if isinstance(value, str) and value:
            assert shown == f'`"{value}"`', (key, shown, value)
        elif isinstance(value, bool):
            assert shown == f"`{str(value).lower()}`", (key, shown, value)


def test_every_claim_function_is_documented_and_nothing_else():
    table = TABLES["[[claims]]"][1]
    documented = {name for cells in table for name in re.findall(r"`(\w+)\(", cells[0])}
    assert documented == set(schema.CLAIM_FUNCTIONS), (
        f"undocumented: {sorted(set(schema.CLAIM_FUNCTIONS) - documented)}; "
        f"documented but unknown: {sorted(documented - set(schema.CLAIM_FUNCTIONS))}")
    words = " ".join(" ".join(cells) for cells in table)
    for word in (*schema.PROBE_QUANTITIES, *schema.ERROR_MEASURES):
        assert f"'{word}'" in words, f"claim word {word!r} is not documented"


def test_the_reference_is_not_a_lesson():
    assert REFERENCE not in lesson_files(REFERENCE.parent)


def test_the_claims_keys_say_what_they_allow():
    row = rows("[[claims]]")
    for word in schema.CLAIM_ABOUT:
        assert f'`"{word}"`' in row["about"][3], row["about"]
    for key in schema.FALSE_WHEN_KEYS:
        assert f"`{key}" in row["false_when"][3], row["false_when"]


AREA_SCENE = """\
[geometry]
kind = "plane"

[material]
ka = 0
kd = 1
ks = 0
shininess = 1

[area_light]
position = [1.0, 1.0, 0.0]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
"""


def test_area_light_position_is_the_centre_as_the_reference_says(tmp_path):
    # the reference says what the position means; the core must light the floor as it says: symmetric
    # about the position (a corner would make it symmetric about position + edge_u/2)
    from phonglab import core
    from phonglab.scene import load_scene

    assert "centre" in rows("[area_light]")["position"][3], rows("[area_light]")["position"]
    path = tmp_path / "panel.toml"
    path.write_text(AREA_SCENE)
    light = load_scene(path).area_light.light
    up = np.array([0.0, 1.0, 0.0])
    left, right = np.array([0.6, 0.0, 0.0]), np.array([1.4, 0.0, 0.0])
    e_left, e_right = (float(core.area_irradiance(light, p, up, method="exact")) for p in (left, right))
    assert abs(e_left - e_right) < 1e-9 * e_left, (light.position, e_left, e_right)
    below = float(core.area_irradiance(light, np.array([1.0, 0.0, 0.0]), up, method="exact"))
    assert below > e_left, (below, e_left)


@pytest.mark.parametrize("section, key", [("scene keys", "probe"), ("[[lights]]", "position"), ("[camera]", "eye"),
                                          ("[camera]", "focal_point"), ("[area_light]", "position")])
def test_every_position_says_which_point_it_is(section, key):
    meaning = rows(section)[key][3]
    assert re.search(r"\b(point|centre|corner)\b", meaning), f"{section}.{key}: {meaning!r} does not say which point"
