"""The worker processes that take heavy work off the server's event loop (phonglab.app.worker)."""

from __future__ import annotations

import asyncio
import contextlib
import os
import time
from pathlib import Path

import pytest

from phonglab.app import worker


class Unpicklable(Exception):
    """An exception its class cannot rebuild from its args (a required keyword)."""

    def __init__(self, text, *, field):
        super().__init__(f"{field}: {text}")


def raise_unpicklable():
    raise Unpicklable("went wrong", field="material.ks")


def slow(value, seconds):
    time.sleep(seconds)
    return value


class State(dict):
    """Enough of a trame state for TabJob: keys, and a ``with`` block that counts flushes."""

    flushes = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.flushes += 1


@pytest.fixture(scope="module", autouse=True)
def stopped_afterwards():
    yield
    worker.shutdown()
    assert not worker.started()


def test_a_job_runs_in_another_process_at_a_lower_priority():
    pid, nice = worker.submit(os.getpid).result(timeout=120), worker.submit(os.nice, 0).result(timeout=60)
    assert pid != os.getpid(), pid
    assert nice == os.nice(0) + worker.NICE, (nice, os.nice(0))


def test_an_exception_that_cannot_travel_back_arrives_as_its_text():
    with pytest.raises(worker.WorkerError, match="Unpicklable: material.ks: went wrong"):
        worker.submit(raise_unpicklable).result(timeout=60)
    assert worker.submit(abs, -3).result(timeout=60) == 3, "the pool stopped working after the failure"


def test_jobs_past_the_limit_are_refused_at_once():
    first = worker.submit(slow, 1, 1.0, limit=1)
    with pytest.raises(worker.ServerBusy, match="try again"):
        worker.submit(slow, 2, 0.0, limit=1)
    assert first.result(timeout=60) == 1
    assert worker.submit(slow, 3, 0.0, limit=1).result(timeout=60) == 3
    assert worker.pending() == 0


def test_a_tab_runs_one_job_at_a_time_and_drops_what_it_no_longer_wants():
    state = State()
    job = worker.TabJob(state, "busy")
    delivered, failures = [], []

    async def scenario():
        assert job.start(slow, ("old", 0.5), delivered.append, failures.append)
        assert state["busy"] and job.busy
        assert not job.start(slow, ("refused", 0.0), delivered.append, failures.append), "a second job started"
        job.forget()  # e.g. another lesson was opened: the old figure is not wanted any more
        assert not state["busy"]
        assert job.start(slow, ("new", 0.0), delivered.append, failures.append)
        for _ in range(600):
            if not job.busy:
                break
            await asyncio.sleep(0.1)
        await asyncio.sleep(1.0)  # time for the old one to arrive, were it delivered
        assert job.start(raise_unpicklable, (), delivered.append, failures.append)
        for _ in range(600):
            if not job.busy:
                break
            await asyncio.sleep(0.1)

    asyncio.run(scenario())
    assert delivered == ["new"], delivered
    assert [type(f).__name__ for f in failures] == ["WorkerError"], failures
    assert state["busy"] is False and state.flushes == 2, (state, state.flushes)


# ---------------------------------------------------------------------------
# a server killed outright takes its workers with it


def _children(pid: int) -> dict[int, str]:
    """The processes whose parent is ``pid``: pid -> command line."""
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            parent = int(stat[stat.rindex(")") + 2:].split()[1])
            if parent == pid:
                found[int(entry.name)] = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, ValueError):
            continue
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return state[state.rindex(")") + 2] != "Z"  # a zombie has ended


def _wait_for(condition, seconds: float, step: float = 0.1):
    """Poll ``condition()`` until it is true or ``seconds`` pass; its last value."""
    deadline = time.monotonic() + seconds
    while True:
        value = condition()
        if value or time.monotonic() > deadline:
            return value
        time.sleep(step)


#: how long the workers of a killed server may live on: they notice at once and end at their next Python
#: step (within a second here, under load); before, they rendered on for the rest of their job
WORKERS_END_WITHIN = 5.0


#: a process that starts the workers, hands one a job of ten minutes and waits
_PARENT = """
import os, sys, time
from phonglab.app import worker
worker.submit(os.getpid).result(timeout=300)  # the pool runs
worker.submit(time.sleep, 600)
print("ready", flush=True)
time.sleep(600)
"""


def test_workers_end_with_their_parent_killed_mid_job():
    import signal
    import subprocess
    import sys

    parent = subprocess.Popen([sys.executable, "-c", _PARENT], stdout=subprocess.PIPE, text=True,
                              start_new_session=True)
    try:
        assert parent.stdout.readline().strip() == "ready", "the parent did not start its workers"
        workers = _wait_for(lambda: {p: c for p, c in _children(parent.pid).items() if "spawn_main" in c}, 60)
        assert len(workers) == worker.WORKERS, _children(parent.pid)
        os.kill(parent.pid, signal.SIGKILL)
        parent.wait(30)
        _wait_for(lambda: not any(_alive(p) for p in workers), WORKERS_END_WITHIN)
        left = [p for p in workers if _alive(p)]
        assert not left, f"workers {left} still run {WORKERS_END_WITHIN:.0f} s after their parent was killed mid-job"
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(parent.pid, signal.SIGKILL)  # the workers share the parent's process group
        parent.wait(30)


def _cpu_seconds(pid: int) -> float:
    """User and system CPU time ``pid`` has used, in seconds (0 once it is gone)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return 0.0
    fields = stat[stat.rindex(")") + 2:].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


#: a lesson whose figure takes seconds of work: per-pixel shading under a sampled area light
SLOW_EXPORT = ('interpolation = "pixel"\ntitle = "Slow to export"', """[geometry]
kind = "sphere"
resolution = 256

[material]
ka = 0.1
kd = 0.6
ks = 0.5
shininess = 20

[[lights]]
type = "point"
position = [2, 2, 3]

[area_light]
position = [0, 2, 2]
method = "uniform"
samples = 8
""")


def test_workers_end_with_a_server_killed_mid_export(tmp_path):
    import re
    import signal

    from app_support import serving
    from test_app_security import logged_in, run

    from phonglab.bench.scenes import lesson

    lessons = tmp_path / "lessons"
    lessons.mkdir()
    (lessons / "01-slow.md").write_text(lesson(*SLOW_EXPORT, "# Slow to export"), encoding="utf-8")

    async def export(port):
        client = await logged_in(port)
        state = (await client.call("trame.state.get"))["result"]["state"]
        page = state["trame__template_main"]
        button = re.search(r'<VBtn class="phonglab-export [^\n]*?@click="trigger\(\'(trigger__\d+)\'\)"', page)
        assert button, page[:2000]
        answer = await client.call("trame.trigger", [button.group(1), [], {}])
        await client.__aexit__()
        return answer

    def spawned(server):
        found = {p: c for p, c in _children(server).items() if "spawn_main" in c}
        return found if len(found) >= worker.WORKERS else {}

    with serving(lessons, log_path=tmp_path / "serve.log") as served:
        server = served["process"].pid
        answer = run(export(served["port"]))
        assert "error" not in answer, answer
        workers = _wait_for(lambda: spawned(server), 120)
        assert len(workers) >= worker.WORKERS, f"no export workers under the server: {_children(server)}"
        # mid-export: a worker has worked another second since it was seen (on the figure, or on the
        # imports before it)
        first = {p: _cpu_seconds(p) for p in workers}
        busy = _wait_for(lambda: any(_cpu_seconds(p) - first[p] > 1.0 for p in workers), 180)
        assert busy, "no worker took up the export"
        os.kill(server, signal.SIGKILL)
        served["process"].wait(30)
        _wait_for(lambda: not any(_alive(p) for p in workers), WORKERS_END_WITHIN)
        left = [p for p in workers if _alive(p)]
        assert not left, (f"export workers {left} still run {WORKERS_END_WITHIN:.0f} s after the server was killed: "
                          f"{[workers[p] for p in left]}")


def _has_vtk(pid: int) -> bool:
    """Whether process ``pid`` has VTK's libraries loaded (it made a figure, or imported the renderer)."""
    try:
        return "libvtk" in Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return False


def test_serve_starts_the_workers_warm_before_any_tab(tmp_path):
    from app_support import serving

    from phonglab.bench.scenes import write_lessons

    lessons = tmp_path / "lessons"
    lessons.mkdir()
    write_lessons(lessons)
    with serving(lessons, log_path=tmp_path / "serve.log") as served:
        server = served["process"].pid

        def warm():
            found = [p for p, c in _children(server).items() if "spawn_main" in c]
            return found if len(found) == worker.WORKERS and all(_has_vtk(p) for p in found) else None

        workers = _wait_for(warm, 180, step=0.5)
        assert workers, (f"{worker.WORKERS} workers with VTK loaded were not running 180 s after the server started, "
                         f"with no tab open: {_children(server)}")
