"""Later: a tab's put-off work, one mechanism (named jobs, each once, in the order added)."""

from __future__ import annotations

import asyncio

from phonglab.app.later import Later


def jobs(later, done, *names, delay=0.002):
    for name in names:
        later.add(name, lambda name=name: done.append(name), delay=delay)


def test_without_a_loop_an_asked_job_runs_at_once():
    done = []
    later = Later()
    jobs(later, done, "turn end", "panels")
    later.ask("panels")
    later.ask("panels")
    assert done == ["panels", "panels"] and not later.waiting("panels")


def test_on_the_loop_each_job_runs_once_in_the_order_added():
    done = []
    later = Later()
    jobs(later, done, "turn end", "panels")

    async def main():
        later.ask("panels")  # asked first, added second: runs after "turn end"
        later.ask("turn end")
        later.ask("panels")
        assert done == [] and later.waiting("panels") and later.waiting("turn end")
        while later.waiting("panels"):
            await asyncio.sleep(0.001)

    asyncio.run(main())
    assert done == ["turn end", "panels"], done


def test_a_job_with_no_delay_runs_first_and_a_failure_stops_nothing():
    done, failed = [], []
    later = Later(lambda name, exc: failed.append((name, str(exc))))
    later.add("camera", lambda: done.append("camera"))

    def broken():
        raise RuntimeError("no panels")

    later.add("panels", broken, delay=0.002)
    jobs(later, done, "after", delay=0.002)

    async def main():
        later.ask("panels")
        later.ask("after")
        later.ask("camera")
        await asyncio.sleep(0.02)

    asyncio.run(main())
    assert done == ["camera", "after"] and failed == [("panels", "no panels")], (done, failed)


def test_cancel_and_run_waiting():
    done = []
    later = Later()
    jobs(later, done, "turn end", "panels")

    async def main():
        later.ask("turn end")
        later.ask("panels")
        later.cancel("turn end")
        later.run_waiting()  # at once, not at its time
        assert done == ["panels"], done
        later.ask("panels")
        later.cancel()
        await asyncio.sleep(0.01)

    asyncio.run(main())
    assert done == ["panels"], done
