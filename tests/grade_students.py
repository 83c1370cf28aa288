"""Student files for the grader's tests, each made from the correct one by changing the lines of one mistake.

``tests/data/grade/correct.py`` is an independent, correct textbook loop.
Each catalogue mistake is that file with a few lines replaced, written out
when a test asks for it, so the correct loop is kept once and every wrong
file shows, in this table, exactly which lines it changes.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data" / "grade"
CORRECT = DATA / "correct.py"

_CORRECT_DOC = '"""A correct shade(), written independently of phonglab: a plain textbook loop, one point at a time."""'
_SPECULAR = """            if rv > 0:
                specular = rv ** material.shininess"""

#: file name -> (its docstring, [(correct lines, wrong lines), ...]); each correct text occurs once
STUDENTS: dict[str, tuple[str, list[tuple[str, str]]]] = {
    "no_clamp_diffuse.py": (
        'The textbook loop with the diffuse weight n·l not clamped at 0 (mistake "no-clamp-diffuse").',
        [("diffuse = max(0.0, nl)", "diffuse = nl  # wrong: no max(0, ·)")],
    ),
    "ungated_specular.py": (
        'The textbook loop with specular light computed even where n·l <= 0 (mistake "ungated-specular").',
        [("""        if nl > 0:
            r = [2 * nl * n[i] - l[i] for i in range(3)]
            rv = dot(r, v)
            if rv > 0:
                specular = rv ** material.shininess""",
          """        r = [2 * nl * n[i] - l[i] for i in range(3)]
        rv = dot(r, v)
        if rv > 0:  # wrong: no n·l > 0 gate
            specular = rv ** material.shininess""")],
    ),
    "zero_shininess.py": (
        'The textbook loop with the specular exponent 0 (mistake "zero-shininess").',
        [(_SPECULAR, "            specular = max(0.0, rv) ** 0  # wrong: the exponent is 0")],
    ),
    "unnormalised_normals.py": (
        'The textbook loop using the normal as given, not renormalised (mistake "unnormalised-normals").',
        [("n, _ = unit([float(x) for x in normal])", "n = [float(x) for x in normal]  # wrong: not normalised")],
    ),
    "reflect_wrong_way.py": (
        "The textbook loop with the mirror vector reversed: r = l − 2(n·l)n.",
        [("r = [2 * nl * n[i] - l[i] for i in range(3)]",
          "r = [l[i] - 2 * nl * n[i] for i in range(3)]  # wrong: reversed")],
    ),
    "unnormalised_light.py": (
        'The textbook loop with the light vector not normalised (mistake "unnormalised-light").',
        [("            l, d = unit(sub(list(light.position), p))",
          "            l = sub(list(light.position), p)  # wrong: not normalised\n"
          "            d = math.sqrt(dot(l, l))")],
    ),
    "unnormalised_view.py": (
        'The textbook loop with the view vector not normalised (mistake "unnormalised-view").',
        [("v, _ = unit(sub([float(x) for x in eye], p))",
          "v = sub([float(x) for x in eye], p)  # wrong: not normalised")],
    ),
    "view_from_eye.py": (
        'The textbook loop with the view vector from the eye to the point (mistake "view-from-eye").',
        [("v, _ = unit(sub([float(x) for x in eye], p))",
          "v, _ = unit(sub(p, [float(x) for x in eye]))  # wrong: from the eye to the point")],
    ),
    "attenuated_ambient.py": (
        'The textbook loop scaling the ambient light by the lamp\'s attenuation (mistake "attenuated-ambient").',
        [("    color = list(material.emission)\n",
          "    color = list(material.emission)\n    ambient = [0.0, 0.0, 0.0]\n    f_first = None\n"),
         ("color[i] += material.ka[i] * light.ambient_rgb[i]", "ambient[i] += material.ka[i] * light.ambient_rgb[i]"),
         ("                    f = 0.0\n",
          "                    f = 0.0\n"
          "            if f_first is None:\n"
          "                f_first = f  # wrong: the first lamp's f, used for the ambient light below\n"),
         ("    return color\n",
          "    scale = 1.0 if f_first is None else f_first\n"
          "    for i in range(3):\n"
          "        color[i] += ambient[i] * scale  # wrong: the ambient light attenuated\n"
          "    return color\n")],
    ),
    "spot_cutoff_in_degrees.py": (
        'The textbook loop comparing the spot cosine with the cutoff in degrees (mistake "spot-cutoff-in-degrees").',
        [("if cos_axis >= math.cos(math.radians(light.cutoff)):",
          "if cos_axis >= light.cutoff:  # wrong: a cosine against degrees")],
    ),
    "zero_to_the_zero.py": (
        'The textbook loop trusting the clamp alone where r·v <= 0: 0 ** 0 = 1 at α = 0 (mistake "zero-to-the-zero").',
        [(_SPECULAR, "            specular = max(0.0, rv) ** material.shininess  # wrong at α = 0: 0 ** 0 == 1")],
    ),
    "power_before_max.py": (
        'The textbook loop raising r·v to α before the max (mistake "power-before-max").',
        [(_SPECULAR, "            specular = max(0.0, rv ** material.shininess)  # wrong: the power before the max")],
    ),
}

_folder: Path | None = None


def student_source(name: str) -> str:
    """The text of the student file ``name``: the correct loop with that mistake's lines replaced."""
    doc, changes = STUDENTS[name]
    text = CORRECT.read_text(encoding="utf-8")
    assert text.count(_CORRECT_DOC) == 1, "tests/data/grade/correct.py lost its docstring line"
    text = text.replace(_CORRECT_DOC, f'"""{doc}"""')
    for right, wrong in changes:
        count = text.count(right)
        assert count == 1, f"{name}: the correct lines {right!r} occur {count} times in correct.py, not once"
        text = text.replace(right, wrong)
    return text


def student_path(name: str) -> Path:
    """The student file ``name``: a file of tests/data/grade, or one of :data:`STUDENTS` written to a temporary folder."""
    if name not in STUDENTS:
        return DATA / name
    global _folder
    if _folder is None:
        _folder = Path(tempfile.mkdtemp(prefix="phonglab-students-"))
        atexit.register(shutil.rmtree, _folder, True)
    path = _folder / name
    if not path.exists():
        path.write_text(student_source(name), encoding="utf-8")
    return path
