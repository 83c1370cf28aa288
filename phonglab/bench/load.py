"""``phonglab bench load``: a class of simulated students against one server, no browsers.

Each student (:class:`~phonglab.bench.load_student.Student`) opens the lesson
as the page does and then acts ``--rate`` times a second: mostly a slider
move, sometimes a click on the view (the probe) or a turn of it. A student
with an action still unanswered skips its next turn, as a person waits for
the picture, so an overloaded server shows as fewer updates per second than
asked, not as a queue that grows without end.

The bench starts the server itself (``phonglab serve LESSON`` in a process
of its own; with ``--launcher`` also ``phonglab serve --launcher``, one
process per student, and prints both), or uses ``--url``. It runs rounds
of 1, 2, 4, … students up to ``--clients`` and prints, per round: actions
per second asked and achieved, latency from sending to the reply and to
the pushed picture (p50, p95, max), the server's CPU (in cores, its whole
process tree) and resident memory; then the largest round whose p95 (of
what a student waits for: the picture when one comes, else the reply) is
within :data:`P95_TARGET_MS`, and, for two servers, the ratio of their
capacities.

``--leak N`` instead opens and closes N sessions and prints the server's
threads and resident memory before and after (:func:`session_footprint`).
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import statistics
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from phonglab.bench import load_server
from phonglab.bench.load_student import Student
from phonglab.bench.usage import UsageError, bounded

HELP = "simulated students over WebSockets: latency, updates/s and capacity of one server and of the launcher"

#: a round's 95th percentile of waiting must stay within this for the class size to count
P95_TARGET_MS = 100.0
#: the share of the asked actions per second a round must achieve to count as keeping pace
PACE_SHARE = 0.9
#: the settings students open the lesson with: Gouraud shading, whose pushed picture is the mesh's colours
#: (a per-pixel picture takes a few hundred milliseconds on its own, whatever the class size)
DEFAULT_ADDRESS = "interpolation=gouraud"
#: sessions opened at once in the session-footprint rounds
LEAK_BATCH = 5
#: sessions opened and closed before the start is measured: the first ones fill the server's caches
#: and pools (measured: resident memory rises by about 8 % over the first 15 sessions, then stays)
WARM_UP = 3 * LEAK_BATCH
#: growth allowed after sessions close (threads and resident memory), as a fraction
LEAK_TOLERANCE = 0.05


def add_arguments(parser) -> None:
    parser.add_argument("--clients", type=_positive_int, default=32, metavar="N",
                        help="the largest class tried (rounds of 1, 2, 4, ... up to N; default 32)")
    parser.add_argument("--rate", type=_positive_float, default=4.0, metavar="R",
                        help="actions per second per student (default 4)")
    parser.add_argument("--lesson", default="lessons/04-specular.md", metavar="L",
                        help="the lesson the server serves (default lessons/04-specular.md)")
    parser.add_argument("--url", default=None, metavar="URL",
                        help="bench a server already running at URL instead of starting one (no CPU or memory figures)")
    parser.add_argument("--launcher", action="store_true",
                        help="also start `phonglab serve --launcher` (one process per student) and compare")
    parser.add_argument("--address", default=DEFAULT_ADDRESS, metavar="QUERY",
                        help="the page address's settings each student opens with, as a shared link would "
                             f"(default {DEFAULT_ADDRESS!r}: the mesh's colours are pushed; '' keeps the lesson's own)")
    parser.add_argument("--seconds", type=_positive_float, default=12.0, metavar="S",
                        help="measured seconds per round (default 12)")
    parser.add_argument("--leak", type=_positive_int, default=None, metavar="N",
                        help="open and close N sessions and print the server's threads and memory before and after")


_positive_int = bounded(int, 1, None, "a whole number of at least 1")
_positive_float = bounded(float, 1e-6, 1e6, "a number above 0")


# ---------------------------------------------------------------------------
# one round


@dataclass
class Round:
    """What one round of ``clients`` students measured."""

    clients: int
    asked: float  #: actions per second asked of the whole class
    achieved: float  #: actions per second answered
    reply_ms: tuple  #: (p50, p95, max) send -> reply
    picture_ms: tuple  #: (p50, p95, max) send -> pushed picture (None when none came)
    wait_p95_ms: float  #: p95 of what a student waits for (the picture when one comes, else the reply)
    lost: int  #: actions without a reply, and students that could not open
    cpu_cores: float | None  #: server CPU seconds per second of the round
    pss_mb: float | None  #: the server's memory, pages shared between its processes counted once
    open_s: float  #: the slowest student's opening
    sliders: int = 0  #: answered actions that moved a slider (the rest clicked or turned the view)


def _percentiles(values) -> tuple:
    if not values:
        return (None, None, None)
    ms = sorted(v * 1000 for v in values)
    p95 = ms[min(len(ms) - 1, int(round(0.95 * (len(ms) - 1))))]
    return (statistics.median(ms), p95, ms[-1])


async def run_round(url: str, clients: int, rate: float, seconds: float, *, pid: int | None = None,
                    query: str = "") -> Round:
    """Open ``clients`` students on ``url``, let them act ``rate`` times a second for ``seconds``, close them."""
    students = [Student(url, seed=1000 * clients + i, query=query) for i in range(clients)]
    opened = await asyncio.gather(*(s.open() for s in students), return_exceptions=True)
    live = [s for s, o in zip(students, opened) if not isinstance(o, BaseException)]
    failed = [o for o in opened if isinstance(o, BaseException)]
    for problem in failed[:3]:
        print(f"  a student could not open: {problem}")
    before = load_server.footprint(pid) if pid else None
    started = time.perf_counter()
    deadline = started + seconds

    async def pace(student: Student, phase: float) -> None:
        # a student acts every 1/rate seconds; an action still unanswered skips the next turn
        next_at = started + phase / rate
        while True:
            now = time.perf_counter()
            if next_at > now:
                await asyncio.sleep(next_at - now)
            if time.perf_counter() >= deadline or student.closed.is_set():
                return
            await student.act()
            next_at += 1.0 / rate
            behind = time.perf_counter() - next_at
            if behind > 0:
                next_at += (int(behind * rate) + 1) / rate  # the turns missed while waiting are skipped

    try:
        await asyncio.gather(*(pace(s, i / max(1, len(live))) for i, s in enumerate(live)))
        elapsed = time.perf_counter() - started
        after = load_server.footprint(pid, pss=True) if pid else None
    finally:
        await asyncio.gather(*(s.close() for s in live), return_exceptions=True)
    timings = [t for s in live for t in s.timings]
    replies = [t.reply for t in timings if t.reply is not None]
    pictures = [t.picture for t in timings if t.picture is not None]
    waits = [t.picture if t.picture is not None else t.reply for t in timings if t.reply is not None]
    return Round(
        clients=clients, asked=clients * rate, achieved=len(replies) / elapsed,
        reply_ms=_percentiles(replies), picture_ms=_percentiles(pictures),
        wait_p95_ms=_percentiles(waits)[1] if waits else float("inf"),
        lost=sum(s.lost for s in live) + len(failed),
        cpu_cores=load_server.cpu_between(before, after) / elapsed if pid else None,
        pss_mb=after.pss_mb if pid else None,
        open_s=max((o for o in opened if not isinstance(o, BaseException)), default=float("nan")),
        sliders=sum(1 for t in timings if t.kind == "slider" and t.reply is not None),
    )


def capacity(rounds: list[Round]) -> int:
    """The largest class whose round met the p95 target with nothing lost (0: none did)."""
    good = [r.clients for r in rounds if r.wait_p95_ms <= P95_TARGET_MS and r.lost == 0]
    return max(good, default=0)


def kept_pace(rounds: list[Round]) -> int:
    """The largest class whose round achieved at least :data:`PACE_SHARE` of the actions asked (0: none did)."""
    good = [r.clients for r in rounds if r.achieved >= PACE_SHARE * r.asked and r.lost == 0]
    return max(good, default=0)


def class_sizes(largest: int) -> list[int]:
    """1, 2, 4, ... below ``largest``, then ``largest``."""
    sizes, n = [], 1
    while n < largest:
        sizes.append(n)
        n *= 2
    return sizes + [largest]


# ---------------------------------------------------------------------------
# sessions that leave nothing behind


@dataclass
class SessionFootprint:
    """A server's threads and resident memory before and after ``sessions`` sessions opened and closed."""

    sessions: int
    threads_before: int
    threads_after: int
    rss_before_mb: float
    rss_after_mb: float

    def grown(self) -> tuple[float, float]:
        """Growth of threads and memory, as fractions of their start."""
        return (self.threads_after / self.threads_before - 1, self.rss_after_mb / self.rss_before_mb - 1)

    def __str__(self) -> str:
        threads, rss = self.grown()
        return (f"{self.sessions} sessions opened and closed: threads {self.threads_before} -> {self.threads_after} "
                f"({threads:+.1%}), resident memory {self.rss_before_mb:.0f} -> {self.rss_after_mb:.0f} MB ({rss:+.1%})")


async def open_and_close(url: str, sessions: int, batch: int = LEAK_BATCH) -> None:
    """Open ``sessions`` sessions, ``batch`` at once; each moves a slider once; then they close."""
    for first in range(0, sessions, batch):
        students = [Student(url, seed=first + i) for i in range(min(batch, sessions - first))]
        try:
            await asyncio.gather(*(s.open() for s in students))
            await asyncio.gather(*(s.act() for s in students))
        finally:
            await asyncio.gather(*(s.close() for s in students), return_exceptions=True)


def settled(pid: int, *, timeout: float = 60.0, quiet: float = 2.0, within=None) -> load_server.Footprint:
    """The footprint of ``pid`` once its thread count has not changed for ``quiet`` seconds.

    With ``within=(threads, rss_mb)`` it returns as soon as both are at or
    below those bounds. After ``timeout`` seconds, the footprint as it is.
    """
    deadline = time.monotonic() + timeout
    last, since = None, time.monotonic()
    while True:
        now = load_server.footprint(pid)
        if within is not None and now.threads <= within[0] and now.rss_mb <= within[1]:
            return now
        if last is None or now.threads != last.threads:
            last, since = now, time.monotonic()
        elif time.monotonic() - since >= quiet and within is None:
            return now
        if time.monotonic() >= deadline:
            return now
        time.sleep(0.25)


def session_footprint(url: str, pid: int, sessions: int, *, tolerance: float = LEAK_TOLERANCE) -> SessionFootprint:
    """Open and close ``sessions`` sessions on the server ``pid`` at ``url``; its threads and memory before and after.

    :data:`WARM_UP` sessions warm the server up first (imports, caches, the
    thread pools and the allocator's arenas reaching their size for
    :data:`LEAK_BATCH` tabs at once); the start is measured after them, once
    the threads are steady. After the
    sessions close, the end is the first footprint within ``tolerance`` of
    the start, or the one a minute later.
    """
    asyncio.run(open_and_close(url, WARM_UP))
    start = settled(pid)
    asyncio.run(open_and_close(url, sessions))
    bound = (start.threads * (1 + tolerance), start.rss_mb * (1 + tolerance))
    end = settled(pid, within=bound)
    return SessionFootprint(sessions, start.threads, end.threads, start.rss_mb, end.rss_mb)


# ---------------------------------------------------------------------------
# the command


@contextlib.contextmanager
def _served(lesson: Path, *flags: str):
    """``phonglab serve lesson *flags`` on a free port: ``(url, pid)``; stopped on leaving."""
    from phonglab.bench.ui import free_port, serve_command, start_server, stop_server, wait_until_serving

    with tempfile.TemporaryDirectory(prefix="phonglab-load-") as folder:
        port = free_port()
        log_path = Path(folder) / "serve.log"
        process = start_server(serve_command(lesson, port) + list(flags), log_path=log_path)
        try:
            wait_until_serving(process, port, log_path=log_path, timeout=120)
            yield f"http://127.0.0.1:{port}/", process.pid
        finally:
            stop_server(process)


def _ms(value) -> str:
    return "-" if value is None else f"{value:.0f}"


def print_round(r: Round) -> None:
    cpu = "-" if r.cpu_cores is None else f"{r.cpu_cores:.2f}"
    rss = "-" if r.pss_mb is None else f"{r.pss_mb:.0f}"
    print(f"{r.clients:>7} {r.asked:>7.0f} {r.achieved:>8.1f}   "
          f"{_ms(r.reply_ms[0]):>5} {_ms(r.reply_ms[1]):>5} {_ms(r.reply_ms[2]):>6}   "
          f"{_ms(r.picture_ms[0]):>5} {_ms(r.picture_ms[1]):>5} {_ms(r.picture_ms[2]):>6}   "
          f"{r.lost:>4} {cpu:>6} {rss:>7} {r.open_s:>6.1f} {r.sliders:>7}", flush=True)


HEADER = ("clients   asked achieved   reply ms: p50   p95    max   picture: p50  p95    max   lost  cores  PSS MB  open s"
          " sliders")


def bench_server(name: str, url: str, pid: int | None, args) -> list[Round]:
    print(f"\n{name}: {args.rate:g} actions/s per student, {args.seconds:g} s per round, "
          f"address {args.address!r}")
    print(HEADER)
    rounds = []
    for clients in class_sizes(args.clients):
        result = asyncio.run(run_round(url, clients, args.rate, args.seconds, pid=pid, query=args.address))
        print_round(result)
        rounds.append(result)
        if result.wait_p95_ms > 20 * P95_TARGET_MS:
            print("  (far past the target: larger classes skipped)")
            break
    print(f"{name}: machine load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores at the end")
    print(f"{name}: largest class with p95 <= {P95_TARGET_MS:.0f} ms: {capacity(rounds)} students; "
          f"keeping pace (>= {PACE_SHARE:.0%} of the actions asked): {kept_pace(rounds)} students; "
          f"most actions answered: {max(r.achieved for r in rounds):.1f}/s")
    return rounds


def run(args) -> int:
    lesson = Path(args.lesson)
    if args.url is None and not lesson.exists():
        raise UsageError(f"--lesson: no such lesson file {args.lesson!r}")
    if args.leak is not None:
        if args.url is not None:
            raise UsageError("--leak starts its own server: leave out --url")
        with _served(lesson) as (url, pid):
            print(session_footprint(url, pid, args.leak))
        return 0
    if args.url is not None:
        bench_server(f"server at {args.url}", args.url, None, args)
        return 0
    with _served(lesson) as (url, pid):
        one = bench_server("one process", url, pid, args)
    if not args.launcher:
        return 0
    with _served(lesson, "--launcher") as (url, pid):
        many = bench_server("launcher (a process per student)", url, pid, args)
    print()
    for what, measure in ((f"p95 <= {P95_TARGET_MS:.0f} ms", capacity), ("keeping pace", kept_pace),
                          ("most actions answered per second", lambda rounds: max(r.achieved for r in rounds))):
        first, second = measure(one), measure(many)
        if first:
            ratio = second / first
            print(f"{what}: one process {first:g}, launcher {second:g}: ratio {ratio:.2f} on {os.cpu_count()} cores, "
                  f"{ratio / os.cpu_count():.2f} of one process's figure per core")
        else:
            print(f"{what}: one process {first:g}, launcher {second:g}: no ratio (one process: none)")
    return 0
