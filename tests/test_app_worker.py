"""The worker processes that take heavy work off the server's event loop (phonglab.app.worker)."""

from __future__ import annotations

import asyncio
import os
import time

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
