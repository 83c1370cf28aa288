"""``phonglab new lesson FILE``: write a minimal lesson that passes ``phonglab check``.

The new lesson has a sphere, a material, an ambient and a point light, one
control, one experiment, a question with its answer and one executable claim
per experiment, so an author starts from something that works and opens in
``phonglab serve FILE``. Every key is explained in ``lessons/FORMAT.md``.

Exit status: 0 when the file was written, 2 when it exists (without
``--force``), its name does not end in ``.md`` or it cannot be written.
"""

from __future__ import annotations

import re
from pathlib import Path

from phonglab.bench.usage import UsageError

#: what ``phonglab new`` can write
KINDS = ("lesson",)

TEMPLATE = '''+++
number = {number}
title = "{title}"
goal = "Say in one sentence what the student will be able to do after this lesson."
controls = ["material.shininess", "lights[1].position"]
question = "Ask one question the lesson answers. Why does the highlight get smaller when α grows?"
answer = "Give the answer here: a larger α makes (r·v)^α fall off faster away from the mirror direction."
interpolation = "pixel"

[geometry]
kind = "sphere"
resolution = 64

[material]
ka = [0.8, 0.3, 0.2]
kd = [0.8, 0.3, 0.2]
ks = 0.5
shininess = 20

[[lights]]
type = "ambient"
intensity = 0.2

[[lights]]
type = "point"
position = [2.0, 2.5, 3.0]

[camera]
eye = [0, 0, 5.5]

[[experiments]]
label = "Shininess 100"
text = "Set the shininess to 100. What happens to the size of the highlight?"
set = {{ "material.shininess" = 100 }}

# Each claim is a sentence of the lesson, run on this scene by `phonglab check` and the tests:
# about the model's numbers ("model") or the picture the page shows ("picture", the shown_*
# functions); false_when makes the sentence false, and the check must then fail.
# (See lessons/FORMAT.md for the functions a check may call.)
[[claims]]
says = "The highlight's peak is k_s I_s = 0.5."
about = "model"
check = "abs(peak('specular') - 0.5) < 0.01"
false_when = {{ set = {{ "material.ks" = 0.3 }} }}

[[claims]]
says = "With α = 100 the highlight is smaller: it reflects about a fifth of the light it reflects at α = 20."
about = "model"
experiment = 1
check = "abs(mean('specular') / 0.0106 - 0.2) < 0.03"
false_when = {{ set = {{ "material.shininess" = 20 }} }}

[[claims]]
says = "On the screen the highlight of α = 100 covers a smaller part of the sphere: levels of 20 and up in the specular picture cover under 3 % of it."
about = "picture"
experiment = 1
check = "shown_fraction('specular', 20, 255) < 0.03"
false_when = {{ set = {{ "material.shininess" = 20 }} }}
+++

## What this lesson is about

Write the lesson here, in Markdown. Maths goes between dollar signs:
$I = k_a I_a + k_d I_d \\max(0, \\mathbf{{n}} \\cdot \\mathbf{{l}})$, or on its own line:

$$\\mathbf{{r}} = 2 (\\mathbf{{n}} \\cdot \\mathbf{{l}})\\, \\mathbf{{n}} - \\mathbf{{l}}$$

## Try it

Tell the student what to try with the controls and the experiment.
'''


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "new",
        help="write a minimal lesson to start from",
        description="Write a minimal, valid lesson (checked by phonglab check, opened by phonglab serve).",
    )
    parser.add_argument("kind", choices=KINDS, help="what to write")
    parser.add_argument("file", metavar="FILE", help="the new lesson, e.g. lessons/15-my-topic.md")
    parser.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    return parser


def lesson_text(path) -> str:
    """The new lesson's text: number from the file name's digits (else 1), title from the rest of the name."""
    path = Path(path)
    digits = re.match(r"\d+", path.name)
    number = int(digits.group()) if digits else 1
    stem = path.stem[digits.end():] if digits else path.stem
    title = stem.strip("-_ ").replace("-", " ").replace("_", " ").capitalize() or "A new lesson"
    return TEMPLATE.format(number=number, title=title.replace('"', "'"))


def _same_number(path: Path):
    """Another lesson in ``path``'s folder whose file name starts with the same number, or None."""
    from phonglab.scene import lesson_files
    from phonglab.scene.lessons import number_from_name

    number = number_from_name(path)
    if number is None:
        return None
    return next((other for other in lesson_files(path.parent)
                 if other.resolve() != path.resolve() and number_from_name(other) == number), None)


def run(args) -> int:
    path = Path(args.file)
    if path.suffix.lower() != ".md":
        raise UsageError(f"FILE: a lesson must end in .md, got {args.file!r}")
    if path.exists() and not args.force:
        raise UsageError(f"FILE: {args.file} exists; use --force to overwrite it")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(lesson_text(path), encoding="utf-8")
    except OSError as exc:
        raise UsageError(f"FILE: cannot write {args.file}: {exc.strerror}") from None
    print(f"wrote {path}; check it with: phonglab check {path}; open it with: phonglab serve {path}")
    taken = _same_number(path)
    if taken:
        print(f"note: {taken.name} starts with the same lesson number; "
              "give the new lesson a number of its own (phonglab check reports two lessons under one number)")
    if not re.match(r"\d", path.name):
        print("note: the lesson list shows only files whose name starts with the lesson number, "
              "e.g. 15-my-topic.md")
    return 0
