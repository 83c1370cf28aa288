"""``phonglab bench ui``'s report: the figures it measured, each against its target with PASS or MISS."""

from __future__ import annotations

import statistics

#: targets printed with PASS/MISS
RATIO_TARGET = 1.0
SERVER_MS_TARGET = 30.0
#: the server's CPU time per slider update on a lesson's own mesh (lesson 4's), ms
LESSON_CPU_MS_TARGET = 3.0


def percentile(values, q: float) -> float:
    """The q-th percentile (0..100), linear between order statistics."""
    ordered = sorted(values)
    if not ordered:
        return float("nan")
    position = (len(ordered) - 1) * q / 100.0
    lower = int(position)
    upper = min(lower + 1, len(ordered) - 1)
    return ordered[lower] + (ordered[upper] - ordered[lower]) * (position - lower)


def _verdict(value: float, target: float) -> str:
    return "PASS" if value <= target else "MISS"


def _report(results: dict, points: int) -> None:
    rows = []
    for name in ("baseline", "phonglab"):
        r = results[name]
        rows.append(
            (
                name,
                f"{statistics.median(r['latency_ms']):.1f}",
                f"{percentile(r['latency_ms'], 95):.1f}",
                f"{statistics.median(r['server_ms']):.1f}" if r["server_ms"] else "n/a",
                f"{percentile(r['server_ms'], 95):.1f}" if r["server_ms"] else "n/a",
                r["canvas"],
                str(len(r["latency_ms"])),
            )
        )
    headers = ("app", "median ms", "p95 ms", "server median ms", "server p95 ms", "canvas px", "presses")
    widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(headers)]
    print(f"phonglab bench ui: key press to changed pixels, headless Chromium, sphere of {points} vertices "
          "(the apps measured in turn, interleaved)")
    print("  ".join(h.ljust(w) for h, w in zip(headers, widths)))
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    ratio = statistics.median(results["phonglab"]["latency_ms"]) / statistics.median(results["baseline"]["latency_ms"])
    server = results["phonglab"]["server_ms"]
    server_median = statistics.median(server) if server else float("inf")
    print(f"latency ratio phonglab / baseline (medians): {ratio:.2f}  target <= {RATIO_TARGET:.1f}  "
          f"{_verdict(ratio, RATIO_TARGET)}")
    print(f"phonglab server time per update (median): {server_median:.1f} ms  target <= {SERVER_MS_TARGET:.0f} ms  "
          f"{_verdict(server_median, SERVER_MS_TARGET)}{_cpu_note(results['phonglab'].get('server_cpu_ms'))}"
          f"{_process_note(results['phonglab'].get('process_cpu_ms'))}")
    if "lesson" in results:
        _report_lesson(results["lesson"])
    turn = results["phonglab"].get("turn")
    if turn:
        _report_turn(turn, results["baseline"]["latency_ms"])


def _report_lesson(lesson: dict) -> None:
    """Lesson 4's mesh: the server process's CPU time per slider update, against its target."""
    cpu = lesson.get("process_cpu_ms") or []
    latency = lesson["latency_ms"]
    print(f"lesson 4's mesh ({lesson.get('points', '?')} vertices, Gouraud), {len(latency)} key presses: "
          f"median {statistics.median(latency):.1f} ms from the key to the pushed colours shown")
    if not cpu:
        print("phonglab server CPU per slider update, lesson 4's mesh: n/a (the server's CPU clock cannot be read here)")
        return
    median = statistics.median(cpu)
    handlers = lesson.get("server_cpu_ms")
    inside = f"; in the update's own handlers: median {statistics.median(handlers):.2f} ms" if handlers else ""
    print(f"phonglab server CPU per slider update, lesson 4's mesh (the whole server process): median {median:.2f} ms, "
          f"p95 {percentile(cpu, 95):.2f} ms  target <= {LESSON_CPU_MS_TARGET:.0f} ms  "
          f"{_verdict(median, LESSON_CPU_MS_TARGET)}{inside}")


def _process_note(cpu_ms) -> str:
    """The server process's whole CPU time per update (relay, state messages and panels included)."""
    if not cpu_ms:
        return ""
    return f"; the whole server process: median {statistics.median(cpu_ms):.1f} ms CPU"


def _report_turn(turn: dict, baseline_latency: list) -> None:
    """Turn of the view to re-shaded pixels, against the baseline's key press to pixels (median and p90)."""
    latency, server = turn["latency_ms"], turn["server_ms"]
    median = statistics.median(latency)
    baseline_ms = statistics.median(baseline_latency)
    server_median = statistics.median(server) if server else float("inf")
    print(f"turn to re-shaded pixels ({len(latency)} drags of {turn['step_px']} px, {turn['missed']} without a "
          f"re-shade): median {median:.1f} ms, "
          f"p95 {percentile(latency, 95):.1f} ms; server per re-shade median {server_median:.1f} ms, "
          f"p95 {percentile(server, 95) if server else float('nan'):.1f} ms")
    ratio = median / baseline_ms
    print(f"turn ratio phonglab turn / baseline key press (medians): {ratio:.2f}  target <= {RATIO_TARGET:.1f}  "
          f"{_verdict(ratio, RATIO_TARGET)}")
    print(f"turn ratio at the 90th percentile: {percentile(latency, 90) / percentile(baseline_latency, 90):.2f} "
          f"(turn p90 {percentile(latency, 90):.1f} ms, baseline key press p90 "
          f"{percentile(baseline_latency, 90):.1f} ms)")
    print(f"phonglab server time per re-shade (median): {server_median:.1f} ms  target <= {SERVER_MS_TARGET:.0f} ms  "
          f"{_verdict(server_median, SERVER_MS_TARGET)}{_cpu_note(turn.get('server_cpu_ms'))}")


def _cpu_note(cpu_ms) -> str:
    """How much of the server's wall-clock time was its own CPU time (the browser draws on the same cores)."""
    if not cpu_ms:
        return ""
    return f"  (of which the server's own CPU time: median {statistics.median(cpu_ms):.1f} ms)"
