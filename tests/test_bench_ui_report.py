"""``phonglab bench ui`` prints the turn latency as ratios to the baseline's key press, at the median and p90."""

from __future__ import annotations

import re

from phonglab.bench import ui


def test_the_turn_report_gives_median_and_p90_ratios(capsys):
    baseline = [float(ms) for ms in range(100, 200, 10)]  # p50 145, p90 181
    turn = {"latency_ms": [float(ms) for ms in range(50, 150, 10)], "server_ms": [12.0, 14.0, 40.0],
            "step_px": 24, "missed": 1}
    ui._report_turn(turn, baseline)
    out = capsys.readouterr().out
    median = float(re.search(r"turn / baseline key press \(medians\): ([0-9.]+)", out).group(1))
    p90 = float(re.search(r"turn ratio at the 90th percentile: ([0-9.]+)", out).group(1))
    assert median == round(95 / 145, 2), out
    assert p90 == round(ui.percentile(turn["latency_ms"], 90) / ui.percentile(baseline, 90), 2), out
    assert "server per re-shade median 14.0 ms" in out and "PASS" in out, out
