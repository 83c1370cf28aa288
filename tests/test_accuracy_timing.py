"""How the accuracy studies time their work: warm-ups first, then the fastest of N samples, in turns.

The mechanism is tested with a fake clock and counted calls; no test asserts
a real time (a shared machine is sometimes busy).
"""

from __future__ import annotations

import pytest

from phonglab.accuracy import interpolation, timing


class FakeClock:
    """A clock that moves only when a fake function 'runs': costs are given per call."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def costly(clock, costs, log, name):
    """A function whose n-th call takes ``costs[n]`` fake seconds; each call is logged as ``name``."""
    calls = iter(costs)

    def fn():
        log.append(name)
        clock.now += next(calls)
        return name

    return fn


def test_interleaved_times_warms_every_function_up_before_any_sample_and_reports_the_fastest():
    clock, log = FakeClock(), []
    # the warm-ups are slow (a start-up burst), then five samples each; min_seconds 0: one call per sample
    slow_start = [1000.0] * timing.WARMUPS
    fns = {"a": costly(clock, slow_start + [3, 1, 2, 100, 4], log, "a"),
           "b": costly(clock, slow_start + [10, 30, 20, 50, 40], log, "b")}
    times = timing.interleaved_times(fns, 5, min_seconds=0.0, clock=clock)
    assert times == {"a": 1, "b": 10}, f"the fastest samples after the warm-ups, got {times}; calls {log}"
    warm = 2 * timing.WARMUPS
    assert sorted(log[:warm]) == sorted(["a", "b"] * timing.WARMUPS), f"warm-ups of both first, got {log}"
    assert log[warm:] == ["a", "b"] * 5, f"samples taken in turns, one of each per round, got {log}"


def test_best_time_does_not_time_its_warm_up():
    clock, log = FakeClock(), []
    fn = costly(clock, [500.0] * timing.WARMUPS + [7, 5, 6], log, "f")
    seconds, result = timing.best_time(fn, 3, min_seconds=0.0, clock=clock)
    assert (seconds, result) == (5, "f"), f"the fastest of the 3 samples after {timing.WARMUPS} warm-ups: {log}"
    assert len(log) == timing.WARMUPS + 3, log


def test_the_interpolation_study_times_every_case_and_the_exact_sphere_in_one_set_of_turns(monkeypatch):
    """Timed one resolution after another, the first (8 segments) paid for a busy start and looked slowest."""
    seen = []

    def fake_times(fns, repeats, **options):
        seen.append((list(fns), repeats))
        return {name: 0.001 * (i + 1) for i, name in enumerate(fns)}

    monkeypatch.setattr(interpolation, "interleaved_times", fake_times)
    study = interpolation.run((8, 16), size=32, repeats=4)
    assert len(seen) == 1, f"one set of turns for every case, got {len(seen)} calls: {seen}"
    names, repeats = seen[0]
    expected = {"reference"} | {(m, r) for m in interpolation.METHODS for r in (8, 16)}
    assert set(names) == expected and repeats == 4, f"cases timed together: {names}, repeats {repeats}"
    times = {name: 0.001 * (i + 1) for i, name in enumerate(names)}
    assert study["reference_time"] == times["reference"] and study["repeats"] == 4, study
    for row in study["rows"]:
        assert row["time"] == times[(row["method"], row["resolution"])], row


def test_the_panels_pick_times_the_method_and_the_exact_sphere_in_turns_fastest_of_5(monkeypatch):
    seen = []

    def fake_times(fns, repeats, **options):
        seen.append((sorted(fns), repeats))
        return {"method": 0.002, "reference": 0.001}

    monkeypatch.setattr(interpolation, "interleaved_times", fake_times)
    view = interpolation.error_images("pixel", 16, size=32)
    assert seen == [(["method", "reference"], 5)], f"one set of turns, fastest of 5: {seen}"
    assert (view.time, view.reference_time, view.repeats) == (0.002, 0.001, 5), view


def test_the_panel_says_how_its_times_were_measured():
    from phonglab.app.accuracy_panel import error_panel

    panel = error_panel("gouraud", 16, 200.0)
    assert "fastest of 5" in panel["timing"] and "vary" in panel["timing"], panel["timing"]
    time = next(f for f in panel["figures"] if f["name"] == "time")
    assert "fastest of 5" in time["title"], time
