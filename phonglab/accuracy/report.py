"""Plain-text tables of the accuracy studies."""

from __future__ import annotations

import math

from phonglab.accuracy.timing import WARMUPS


def _num(x, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def _ms(seconds) -> str:
    """A time in ms below a second, else in s."""
    return f"{seconds * 1e3:.3g} ms" if seconds < 1 else f"{seconds:.3g} s"


def _table(headers, rows) -> list[str]:
    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) for i, h in enumerate(headers)]
    line = "  ".join(str(h).rjust(w) for h, w in zip(headers, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(str(c).rjust(w) for c, w in zip(r, widths)) for r in rows]
    return out


def _interpolation(study) -> list[str]:
    out = [f"reference time: {_ms(study['reference_time'])}"]
    if study.get("repeats"):  # how the times were taken: they are live and vary between runs
        out.append(f"times: the fastest of {study['repeats']} runs each, after {WARMUPS} untimed warm-ups, "
                   f"every case timed in turns; compare times of one run")
    rows = [
        (r["resolution"], r["method"], r["shades"], _num(r["rmse"]), _num(r["max_error"]),
         _num(r["highlight_rmse"]), _num(r["peak_error"]), _ms(r["time"]))
        for r in study["rows"]
    ]
    out += _table(("resolution", "method", "shades", "RMSE", "max error", "highlight RMSE",
                   "peak error", "time"), rows)
    return out


def _precision(study) -> list[str]:
    rows = [
        (r["case"], r["term"], r["precision"], _num(r["max_rel_error"]), _num(r["median_rel_error"]),
         f"{r['time_per_million']:.3g} s")
        for r in study["rows"]
    ]
    return _table(("case", "term", "precision", "max rel. error", "median rel. error", "time / 1e6 points"), rows)


def _models(study) -> list[str]:
    rows = [(t["setup"], t["model"], f"{t['time_per_million']:.3g} s", f"{t['ratio']:.2f}")
            for t in study["timing"]]
    out = _table(("setup", "model", "time / 1e6 points", "vs phong"), rows)
    out.append("")
    rows = [(r["setup"], f"{r['alpha']:g}", f"{r['blinn_exponent']} = {r['blinn_shininess']:g}",
             _num(r["max_diff"]), _num(r["rms_diff"])) for r in study["rows"]]
    out += _table(("setup", "phong a", "blinn-phong exponent", "max |difference|", "RMS difference"), rows)
    return out


def _area_light(study) -> list[str]:
    rows = [(r["method"], r["samples"] or "-", _num(r["error"]), _ms(r["time"])) for r in study["rows"]]
    out = _table(("method", "N", "relative error", "time"), rows)
    out.append("")
    for method, slope in study["slopes"].items():
        out.append(f"fitted slope of log(error) against log(N), {method}: {slope:+.2f}"
                   + ("  (1/sqrt(N) is -0.50)" if method == "uniform" else ""))
    return out


_FORMATTERS = {"interpolation": _interpolation, "precision": _precision, "models": _models,
               "area_light": _area_light}


def format_report(results: dict) -> str:
    """All studies as text: a title, the reference and a table each."""
    out = []
    for number, study in enumerate(results["studies"], 1):
        out.append(f"{number}. {study['title']}")
        out.append(f"   error against: {study['reference']}")
        out.append("")
        out += [("   " + line).rstrip() for line in _FORMATTERS[study["name"]](study)]
        out.append("")
    return "\n".join(out).rstrip() + "\n"
