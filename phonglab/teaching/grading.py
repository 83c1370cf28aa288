"""Graded practice: a student's ``shade`` for one point, compared with the core.

The student writes ``shade(point, normal, eye, material, lights)`` in a file
of their own (``phonglab grade --template`` writes a starter);
:func:`grade_file` runs it on the cases of
:mod:`phonglab.teaching.grade_cases` in an isolated worker process
(:mod:`phonglab.teaching.sandbox`), compares every answer with
:func:`phonglab.core.shade` and, for a group that fails, looks for the
common mistake (:data:`phonglab.teaching.MISTAKES`) whose output the
student's matches.

The contract
------------
``shade(point, normal, eye, material, lights)`` returns the colour of ONE
surface point as 3 floats (R, G, B), unclamped, computed in float64:

- ``point``, ``normal``, ``eye``: NumPy arrays of 3 float64 numbers; the
  normal may have any length (normalise it); the viewer is local,
  ``v = normalize(eye − point)``.
- ``material``: a read-only :class:`~phonglab.teaching.shade_helpers.Material`
  (``ka``, ``kd``, ``ks``, ``emission`` RGB triples, ``shininess`` α ≥ 0).
- ``lights``: a list of read-only lights of
  :mod:`~phonglab.teaching.shade_helpers`, whose ``ambient_rgb``,
  ``diffuse_rgb`` and ``specular_rgb`` are the effective intensities
  ``Ia``, ``Id``, ``Is``: ``AmbientLight`` (adds ``ka∘Ia``; only ambient
  lights add ambient light), ``PointLight`` (``l = normalize(position − p)``,
  ``f = 1/(a + b·d + c·d²)``), ``DirectionalLight`` (``l =
  normalize(direction)``, towards the light, ``f = 1``) and ``SpotLight``
  (a point light with ``f`` times ``max(0, −l·s)^exponent`` inside the cone
  ``−l·s ≥ cos(cutoff)``, edge included, 0 outside; ``s =
  normalize(direction)``; ``cutoff = 180`` is a plain point light).

It must equal ``phonglab.shade(point, normal, material=material,
lights=lights, eye=eye, model="phong").color``: the one-sided Phong model

.. math::

    I = k_e + k_a \\circ I_a + \\sum_l f_l \\left[ k_d \\circ I_{d,l} \\max(0, n\\cdot l)
        + k_s \\circ I_{s,l} S_l \\right], \\qquad r = 2(n\\cdot l)n - l,

with ``S = max(0, r·v)^α`` where ``n·l > 0`` and ``r·v > 0`` and 0
elsewhere (also for α = 0: ``0 ** 0`` is 1, ``S`` is not); a light on the
point (``l`` of length 0) or a zero normal adds no diffuse or specular
light, and an eye exactly on the point (``v`` of length 0) sees no specular
light (``r·v = 0``).

The student's process has NumPy, ``math`` and
:mod:`phonglab.teaching.shade_helpers` (``normalize``, ``dot``,
``reflect``), not the phonglab package: the expected colours are computed
here, never in the sandbox.

Scoring
-------
Each group of cases is worth points (100 in all); a group scores
``points × passed / cases``. A case passes when every channel is within
``atol + rtol·|expected|`` of the core, the group's tolerance (justified in
:mod:`~phonglab.teaching.grade_cases`). An exception, a NaN or inf, a wrong
shape or type, a time-out or a refused action (opening a file, starting a
program) is a failed case with a one-line message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from phonglab import core as pl
from phonglab.teaching.grade_cases import GROUPS, Case, Group
from phonglab.teaching import MISTAKES
from phonglab.teaching.sandbox import (Cancel, Cancelled, Limits, LoadError, Outcome, Sandbox,
                                       SandboxUnavailable, StudentFile, cancelled_by)
from phonglab.teaching.worked import worked_lines

__all__ = [
    "GROUPS", "Case", "Group", "CaseResult", "Diagnosis", "GroupResult", "Report",
    "expected", "within", "diagnose", "grade", "grade_file", "encode_scene",
    "format_report", "gradescope_results", "starter_text", "case_text", "group_text", "Wording", "wording",
    "LoadError", "Limits", "Outcome", "Sandbox", "SandboxUnavailable", "StudentFile", "Cancel", "Cancelled",
    "cancelled_by",
]


def expected(case: Case) -> np.ndarray:
    """The core's colour for ``case``: one-sided Phong, local viewer, float64, shape (3,)."""
    s = pl.shade(np.array([case.point], np.float64), np.array([case.normal], np.float64),
                 material=case.material, lights=case.lights, eye=case.eye, model="phong")
    return np.array(s.color[0])


def within(want, got, rtol: float, atol: float) -> bool:
    """Every channel of ``got`` within ``atol + rtol·|want|`` (False for NaN or inf)."""
    want, got = np.asarray(want, np.float64), np.asarray(got, np.float64)
    return bool(np.all(np.abs(got - want) <= atol + rtol * np.abs(want)))


def _ratio(want, got, rtol, atol) -> float:
    """How many tolerances away ``got`` is: <= 1 passes; inf for NaN or inf."""
    err = np.abs(np.asarray(got) - want) / (atol + rtol * np.abs(want))
    return float(np.max(np.where(np.isfinite(err), err, np.inf)))


#: a light's fields that its effective intensities already include
_COLOUR_FIELDS = ("color", "intensity", "diffuse", "specular")


def encode_scene(material: pl.Material, lights) -> dict:
    """The material and lights as JSON for the worker, which rebuilds them as ``shade_helpers`` objects.

    Only what the contract names travels: the material's ``ka``, ``kd``,
    ``ks``, ``emission`` and ``shininess``; each light's class name, its
    geometry and its effective intensities ``ambient_rgb``, ``diffuse_rgb``
    and ``specular_rgb``.
    """
    def light(lt):
        data = {"type": type(lt).__name__}
        data.update({f.name: getattr(lt, f.name) for f in fields(lt) if f.name not in _COLOUR_FIELDS})
        data.update(ambient_rgb=lt.ambient_rgb, diffuse_rgb=lt.diffuse_rgb, specular_rgb=lt.specular_rgb)
        return data

    return {"material": {name: getattr(material, name) for name in ("ka", "kd", "ks", "emission", "shininess")},
            "lights": [light(lt) for lt in lights]}


@dataclass(frozen=True)
class CaseResult:
    """One case: the core's colour, the student's (None on error) and the verdict."""

    case: Case
    expected: np.ndarray
    got: np.ndarray | None
    error: str | None
    passed: bool
    ratio: float  # error in tolerances (inf on error)


@dataclass(frozen=True)
class Diagnosis:
    """A catalogue mistake that the student's wrong answers match."""

    name: str
    title: str
    looks_like: str
    wrong: str
    right: str
    matched: int  # failing cases it matches
    failing: int  # failing cases with a number to compare
    equally: tuple[str, ...] = ()  # other mistakes matching the same number of cases: the cases cannot tell them apart


@dataclass(frozen=True)
class GroupResult:
    group: Group
    cases: tuple[CaseResult, ...]
    diagnosis: Diagnosis | None

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.cases)

    @property
    def score(self) -> float:
        return round(self.group.points * sum(c.passed for c in self.cases) / len(self.cases), 2)

    @property
    def worst(self) -> CaseResult | None:
        """The failed case furthest from the core (an error counts as furthest)."""
        failed = [c for c in self.cases if not c.passed]
        return max(failed, key=lambda c: c.ratio) if failed else None


@dataclass(frozen=True)
class Report:
    source: str
    groups: tuple[GroupResult, ...]
    isolation: tuple[str, ...] = ()

    @property
    def score(self) -> float:
        return round(sum(g.score for g in self.groups), 2)

    @property
    def max_score(self) -> float:
        return float(sum(g.group.points for g in self.groups))

    @property
    def passed(self) -> bool:
        return all(g.passed for g in self.groups)

    @property
    def diagnosis(self) -> list[str]:
        """The names of the mistakes found, each once, in group order."""
        names = [name for g in self.groups if g.diagnosis for name in (g.diagnosis.name, *g.diagnosis.equally)]
        return list(dict.fromkeys(names))


@dataclass(frozen=True)
class Wording:
    """How a mistake reads to a student who wrote ``shade`` for one point."""

    title: str
    looks_like: str
    wrong: str
    right: str


#: mistakes whose catalogue wording speaks of another setting, in the terms of the exercise
#: (the catalogue's "interpolated normals" are the normal argument here: same numbers, another line)
EXERCISE_WORDING = {
    "unnormalised-normals": Wording(
        "The normal not normalised",
        "n·l and r·v scale with the normal's length: too dark where it is shorter than 1, too bright where "
        "it is longer, and a highlight dims or blows up.",
        "n = normal",
        "n = normalize(normal)",
    ),
}


def wording(name: str) -> Wording:
    """The mistake ``name`` in the exercise's terms (the catalogue's own wording unless it speaks of another setting)."""
    if name in EXERCISE_WORDING:
        return EXERCISE_WORDING[name]
    m = MISTAKES[name]
    return Wording(m.title, m.looks_like, m.wrong, m.right)


def _mistake_color(mistake, case: Case) -> np.ndarray | None:
    try:
        s = mistake.shade(np.array([case.point], np.float64), np.array([case.normal], np.float64),
                          material=case.material, lights=list(case.lights), eye=case.eye, model="phong")
        return np.asarray(s.color, np.float64).reshape(-1, 3)[0]
    except Exception:  # noqa: BLE001 - a mistake that cannot shade this case does not match it
        return None


def diagnose(group: Group, results) -> Diagnosis | None:
    """The catalogue mistake matching most of the group's wrong numbers, if it matches more than half.

    Every mistake of :data:`~phonglab.teaching.MISTAKES` is evaluated on the
    group's failing cases that returned a number; it matches a case when the
    student's colour is within the group's tolerance of the mistake's. The
    mistake matching the most cases wins, provided it matches more than half
    of them; between mistakes that match as many, the one that also gives
    the student's right answers (on the group's passing cases) wins. Mistakes that match as many
    cases are named too (``equally``): for one-sided Phong, for instance, a
    reversed ``r`` and a reversed ``v`` give the same ``r·v``.
    """
    wrong = [r for r in results if not r.passed and r.got is not None]
    if not wrong:
        return None
    right = [r for r in results if r.passed]

    def matches(mistake, rs):
        count = 0
        for r in rs:
            mine = _mistake_color(mistake, r.case)
            if mine is not None and within(mine, r.got, group.rtol, group.atol):
                count += 1
        return count

    # the wrong answers it explains, then (to break a tie) the right answers it also gives
    counts = {m.name: (matches(m, wrong), 0) for m in MISTAKES.values()}
    best_count = max(c for c, _ in counts.values())
    if 2 * best_count <= len(wrong):
        return None
    counts = {name: (c, matches(MISTAKES[name], right)) for name, (c, _) in counts.items() if c == best_count}
    top = max(counts.values())
    best, *equally = [name for name, count in counts.items() if count == top]
    said = wording(best)
    return Diagnosis(best, said.title, said.looks_like, said.wrong, said.right, best_count, len(wrong),
                     tuple(equally))


def grade(outcomes, groups=GROUPS, *, source: str = "", isolation=()) -> Report:
    """Compare outcomes with the core, group by group.

    Parameters
    ----------
    outcomes : sequence of sequences of Outcome
        ``outcomes[i][j]`` is the student's answer to ``groups[i].cases[j]``.
    """
    results = []
    for group, answers in zip(groups, outcomes):
        cases = []
        for case, outcome in zip(group.cases, answers):
            want = expected(case)
            got, error = outcome.value, outcome.error
            if got is not None and not np.all(np.isfinite(got)):
                error = f"shade returned {_fmt(got)}: NaN or inf"
                ratio, ok = math.inf, False
            elif got is None:
                ratio, ok = math.inf, False
            else:
                ratio = _ratio(want, got, group.rtol, group.atol)
                ok = within(want, got, group.rtol, group.atol)
            cases.append(CaseResult(case, want, None if error else got, error, ok, ratio))
        results.append(GroupResult(group, tuple(cases), diagnose(group, cases)))
    return Report(source, tuple(results), tuple(isolation))


def grade_file(path, limits: Limits = Limits(), groups=GROUPS) -> Report:
    """Run the student's file in the sandbox on every case and grade it.

    Parameters
    ----------
    path : path or StudentFile
        The student's file, or its text held in memory (the page's paste).

    Raises
    ------
    LoadError
        When the file cannot be loaded (syntax error, import error, no
        ``shade``), with the reason on one line.
    SandboxUnavailable
        When this machine cannot make the sandbox (the reason says what to install).
    Cancelled
        When the grading's :class:`~phonglab.teaching.sandbox.Cancel` was flipped.
    """
    outcomes = []
    with Sandbox(path, limits) as box:
        for group in groups:
            answers = []
            for case in group.cases:
                answers += box.evaluate([case.point], [case.normal], eye=case.eye,
                                        scene=encode_scene(case.material, case.lights))
            outcomes.append(answers)
        isolation = box.isolation
    source = path.name if isinstance(path, StudentFile) else str(path)
    return grade(outcomes, groups, source=source, isolation=isolation)


def starter_text() -> str:
    """The starter file: the contract in its docstring and ``shade`` to fill in."""
    return Path(__file__).with_name("shade_starter.py").read_text(encoding="utf-8")


# ---------------------------------------------------------------------------
# the report


def _fmt(v) -> str:
    return "(" + ", ".join(f"{float(x) + 0.0:.10g}" for x in np.asarray(v).ravel()) + ")"  # + 0.0: no "-0"


def _light_text(light) -> str:
    """A light's class and the fields that differ from their defaults."""
    shown = []
    order = sorted(fields(light), key=lambda f: f.name not in ("position", "direction"))
    for f in order:
        value = getattr(light, f.name)
        if f.name in ("position", "direction") or value != f.default:
            shown.append(f"{f.name}={_fmt(value) if isinstance(value, tuple) else f'{value:g}'}")
    return f"{type(light).__name__}({', '.join(shown)})"


def case_text(case: Case, indent: str = "    ") -> str:
    """The inputs of a case, one per line."""
    m = case.material
    lines = [
        f"point={_fmt(case.point)} normal={_fmt(case.normal)} eye={_fmt(case.eye)}",
        f"material: ka={_fmt(m.ka)} kd={_fmt(m.kd)} ks={_fmt(m.ks)} shininess={m.shininess:g} "
        f"emission={_fmt(m.emission)}",
        "lights: " + ("none" if not case.lights else "; ".join(_light_text(lt) for lt in case.lights)),
    ]
    return "\n".join(indent + line for line in lines)


def group_text(g: GroupResult) -> str:
    """One group's block of the report: verdict, worst case and diagnosis."""
    n_pass = sum(c.passed for c in g.cases)
    mark = "PASS" if g.passed else "FAIL"
    lines = [f"{mark} {g.group.title}: {g.score:g}/{g.group.points:g} points "
             f"({n_pass} of {len(g.cases)} cases)"]
    worst = g.worst
    if worst is not None:
        lines.append(f"  worst case: {worst.case.what}")
        lines.append(case_text(worst.case))
        lines.append(f"    expected {_fmt(worst.expected)}")
        if worst.error:
            lines.append(f"    got      an error: {worst.error}")
        else:
            lines.append(f"    got      {_fmt(worst.got)}  (tolerance {g.group.rtol:g} relative "
                         f"+ {g.group.atol:g} absolute)")
        errors = sorted({c.error for c in g.cases if c.error and c.error != worst.error})
        for e in errors[:3]:
            lines.append(f"    also: {e}")
        lines += ["    worked answer (what the model used):"] + [f"      {x}" for x in worked_lines(worst.case)]
    d = g.diagnosis
    if d is not None:
        lines.append(f"  diagnosis: this looks like the mistake \"{d.name}\" ({d.title}), matching "
                     f"{d.matched} of {d.failing} wrong cases")
        lines.append(f"    wrong: {d.wrong}")
        lines.append(f"    right: {d.right}")
        lines.append(f"    what it looks like: {d.looks_like}")
        if worst is not None:
            lines += ["    that mistake's answer to the worst case:"] + [
                f"      {x}" for x in worked_lines(worst.case, MISTAKES[d.name])]
        for name in d.equally:
            m = wording(name)
            lines.append(f"  or, with the same numbers in every case here, the mistake \"{name}\" ({m.title})")
            lines.append(f"    wrong: {m.wrong}")
            lines.append(f"    right: {m.right}")
    return "\n".join(lines)


def format_report(report: Report) -> str:
    """The terminal report: a header, every group, the total."""
    head = [f"phonglab grade {report.source}"]
    head += [f"  isolation: {item}" for item in report.isolation]
    body = [group_text(g) for g in report.groups]
    total = f"Total: {report.score:g}/{report.max_score:g}"
    if report.diagnosis:
        total += "  (mistakes found: " + ", ".join(report.diagnosis) + ")"
    return "\n".join(head) + "\n\n" + "\n\n".join(body) + "\n\n" + total


def gradescope_results(report: Report | None, *, load_error: str | None = None,
                       execution_time: float | None = None, groups=GROUPS) -> dict:
    """The run as Gradescope's ``results.json``.

    Top level: ``score``, ``max_score``, ``output``, ``visibility``,
    ``stdout_visibility``, ``tests`` (one per group: ``name``, ``number``,
    ``score``, ``max_score``, ``status`` "passed"/"failed", ``output``,
    ``visibility``), plus ``diagnosis`` (the catalogue names found, also in
    ``extra_data``). A file that could not be loaded scores 0 in every group,
    with the reason as each test's output.
    """
    tests = []
    if report is None:
        for i, group in enumerate(groups, 1):
            tests.append({"name": group.title, "number": str(i), "score": 0.0, "max_score": float(group.points),
                          "status": "failed", "output": f"not run: {load_error}", "visibility": "visible"})
        score, max_score, diagnosis = 0.0, float(sum(g.points for g in groups)), []
        output = f"The file could not be loaded: {load_error}"
    else:
        for i, g in enumerate(report.groups, 1):
            tests.append({"name": g.group.title, "number": str(i), "score": g.score,
                          "max_score": float(g.group.points), "status": "passed" if g.passed else "failed",
                          "output": group_text(g), "visibility": "visible"})
        score, max_score, diagnosis = report.score, report.max_score, report.diagnosis
        output = f"{score:g}/{max_score:g}" + (f"; mistakes found: {', '.join(diagnosis)}" if diagnosis else "")
    results = {"score": score, "max_score": max_score, "output": output, "visibility": "visible",
               "stdout_visibility": "hidden", "tests": tests, "diagnosis": diagnosis,
               "extra_data": {"diagnosis": diagnosis}}
    if execution_time is not None:
        results["execution_time"] = round(execution_time, 3)
    return results
