"""``phonglab plan FILE``: show which effects a scene computes and which it skips.

Prints each computed effect and each skipped one with the reason, as text or,
with ``--json``, as ``{"file", "computed": [{"effect", "reason"}], "skipped": [...]}``.
``--set PATH=VALUE`` changes a field first (``--set material.ks=0``).

Exit status: 0 on success, 1 when the file has problems (printed as by
``phonglab check``), 2 for a bad ``--set``.
"""

from __future__ import annotations

import json
import sys


def add_parser(subparsers):
    parser = subparsers.add_parser(
        "plan",
        help="show which effects a scene computes and skips",
        description="Show which lighting effects a scene or lesson computes, and why the others are skipped.",
    )
    parser.add_argument("file", metavar="FILE", help="a scene file (.toml) or a lesson (.md)")
    parser.add_argument(
        "--set",
        dest="settings",
        action="append",
        default=[],
        metavar="PATH=VALUE",
        help="change a field first, e.g. --set material.ks=0 (repeatable)",
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of text")
    return parser


def format_plan(name: str, scene, scene_plan) -> str:
    """The plan as aligned text: a heading, then the computed and skipped effects."""
    rows = [("computed", scene_plan.computed), ("skipped", scene_plan.skipped)]
    width = max((len(effect) for _, items in rows for effect, _ in items), default=0)
    lines = [f"{name}: {scene.model}, {scene.interpolation} interpolation, {len(scene.lights)} lights"]
    for heading, items in rows:
        lines.append(f"{heading}:")
        for effect, reason in items:
            lines.append(f"  {effect:<{width}}  {reason}")
        if not items:
            lines.append("  (none)")
    return "\n".join(lines)


def run(args) -> int:
    from phonglab.cli import UsageError
    from phonglab.scene import Lesson, SceneError, load, parse_setting, plan

    try:
        settings = [parse_setting(text) for text in args.settings]
    except SceneError as exc:
        raise UsageError(f"--set: {exc}") from None
    try:
        loaded = load(args.file)
    except SceneError as exc:
        for error in getattr(exc, "errors", [exc]):
            print(error, file=sys.stderr)
        return 1
    scene = loaded.scene if isinstance(loaded, Lesson) else loaded
    for (path, value), text in zip(settings, args.settings):
        try:
            scene = scene.replace(path, value)
        except SceneError as exc:
            raise UsageError(f"--set {text}: " + "; ".join(str(e) for e in getattr(exc, "errors", [exc]))) from None
    scene_plan = plan(scene)
    if args.json:
        print(json.dumps({"file": args.file, **scene_plan.as_dict()}, indent=2, ensure_ascii=False))
    else:
        print(format_plan(args.file, scene, scene_plan))
    return 0
