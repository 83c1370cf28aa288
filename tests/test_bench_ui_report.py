"""``phonglab bench ui`` prints the turn latency as ratios to the baseline's key press, at the median and p90."""

from __future__ import annotations

import re

from phonglab.bench import ui, ui_report


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


def test_the_server_records_wall_and_cpu_time_and_the_report_shows_both(tmp_path, monkeypatch, capsys):
    # on 2 cores the browser's software drawing takes CPU from the server: the report tells the two apart
    import time

    from phonglab.app import timing

    path = tmp_path / "timing.txt"
    monkeypatch.setenv(timing.ENV, str(path))
    with timing.timed("view"):
        time.sleep(0.05)  # waiting: wall time only
        sum(i * i for i in range(200_000))  # working: wall and CPU time
    records = dict(timing.read(path))
    assert set(records) == {"view", "view" + timing.CPU_SUFFIX}, records
    wall, cpu = records["view"], records["view" + timing.CPU_SUFFIX]
    assert wall >= 50 and 0 < cpu < wall - 40, records
    turn = {"latency_ms": [100.0], "server_ms": [40.0], "server_cpu_ms": [22.0], "step_px": 24, "missed": 0}
    ui._report_turn(turn, [200.0])
    out = capsys.readouterr().out
    assert "(of which the server's own CPU time: median 22.0 ms)" in out, out


def test_a_probe_keeps_only_the_server_records_its_own_steps_bring(tmp_path, monkeypatch):
    # two tabs of one server record under one label; a turn's panels record under it too
    from phonglab.app import timing
    from phonglab.bench.ui_probe import Probe

    path = tmp_path / "timing.txt"
    monkeypatch.setenv(timing.ENV, str(path))
    first, second = (Probe(None, timing_path=path, label="view") for _ in range(2))
    timing.record_lap("view", 10.0, 5.0)  # a warm-up step
    first.start_measuring()
    second.start_measuring()
    for probe, wall, cpu in ((first, 20.0, 4.0), (second, 30.0, 3.0)):
        before = probe.records()
        timing.record_lap("view", wall, cpu)
        probe.keep(100.0, before)
    timing.record_lap("view", 99.0, 99.0)  # the panels after a drag: no key press's
    got = [(p.server_ms(), p.server_ms(cpu=True)) for p in (first, second)]
    assert got == [([20.0], [4.0]), ([30.0], [3.0])], got


def test_the_lesson_report_gives_the_server_process_cpu_against_its_target(capsys):
    lesson = {"latency_ms": [50.0, 70.0], "process_cpu_ms": [2.5, 2.9, 3.6], "server_cpu_ms": [1.5, 1.9],
              "points": 1986}
    ui_report._report_lesson(lesson)
    out = capsys.readouterr().out
    assert "median 2.90 ms" in out and "target <= 3 ms  PASS" in out and "handlers: median 1.70 ms" in out, out
    ui_report._report_lesson({**lesson, "process_cpu_ms": [3.5]})
    assert "MISS" in capsys.readouterr().out
