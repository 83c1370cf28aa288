"""The grader's worked answer: the core's record at one case, as lines of text.

For a failed case the report shows, besides the expected colour, what the
model used to get it: per light the vectors, the light factor, the cosines,
the weights and the terms, and the ambient term. With a diagnosed mistake it
shows the same lines for the mistaken code, so a student can compare them
with their own intermediate values. Everything is read from the record of
:func:`phonglab.core.shade_reference` (``trace=True``; a mistake's own
record for a mistake); nothing here computes the model.
"""

from __future__ import annotations

import numpy as np

from phonglab.core.reference import shade_reference

__all__ = ["worked_lines"]

#: recorded values not shown: the inputs the case already lists, and a light's sum of its two terms
_HIDDEN = {"I_d", "I_s", "adds"}


def _fmt(x) -> str:
    x = np.asarray(x, dtype=np.float64)
    if x.ndim == 0:
        return f"{float(x) + 0.0:.6g}"
    return "(" + ", ".join(f"{float(c) + 0.0:.6g}" for c in x) + ")"


def worked_lines(case, mistake=None) -> list[str]:
    """The record of the model (or of ``mistake``) at ``case``, one line per part of the sum.

    Parameters
    ----------
    case : phonglab.teaching.grade_cases.Case
        One point, its normal, the eye, the material and the lights.
    mistake : phonglab.teaching.Mistake, optional
        Work the mistaken code's answer instead of the model's.

    Returns
    -------
    list of str
        ``ambient ...``, one ``light i (kind): name = value, ...`` line per
        light in the order the record holds its values, and the total.
    """
    shade = shade_reference if mistake is None else mistake.shade
    with np.errstate(over="ignore", invalid="ignore"):
        shading, record = shade(np.array([case.point], np.float64), np.array([case.normal], np.float64),
                                material=case.material, lights=list(case.lights), eye=case.eye, model="phong",
                                trace=True)
    record = record.at(0)
    lines = [f"ambient = {_fmt(record['ambient'])}, emission = {_fmt(record['emission'])}"]
    for light in record.lights:
        shown = [f"{name} = {_fmt(value)}" for name, value in light.values.items() if name not in _HIDDEN]
        lines.append(f"light {light.index} ({light.kind}): " + ", ".join(shown))
    lines.append(f"total = {_fmt(shading.color[0])}")
    return lines
