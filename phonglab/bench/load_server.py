"""What ``phonglab bench load`` reads of a server from outside: its processes' CPU time, memory and threads.

Linux only (``/proc``). A server is a process and, behind a launcher, the
session processes it started: every figure covers the whole tree.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

#: clock ticks per second of /proc/PID/stat's times
TICKS = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
PAGE = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096


@dataclass(frozen=True)
class Footprint:
    """A process tree at one moment: CPU seconds so far per process, resident memory, threads."""

    cpu: dict  #: pid -> user + system CPU seconds
    rss_mb: float
    threads: int
    processes: int
    pss_mb: float = float("nan")  #: proportional memory: pages shared between the processes counted once


def _stat(pid: int):
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rfind(")") + 2:].split()
    # fields[0] is the state (field 3); ppid is field 4, utime 14, stime 15, threads 20, rss 24
    return {"ppid": int(fields[1]), "cpu": (int(fields[11]) + int(fields[12])) / TICKS,
            "threads": int(fields[17]), "rss": int(fields[21]) * PAGE}


def tree(pid: int) -> list[int]:
    """``pid`` and all its descendants alive now."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            info = _stat(int(entry))
            if info is not None:
                children.setdefault(info["ppid"], []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        current = todo.pop()
        found.append(current)
        todo.extend(children.get(current, ()))
    return found


def _pss_kb(pid: int) -> float:
    try:
        for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
            if line.startswith("Pss:"):
                return float(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return float("nan")


def footprint(pid: int, *, pss: bool = False) -> Footprint:
    """The footprint of ``pid``'s process tree now (with ``pss``, its proportional memory too)."""
    cpu, rss, threads, pss_kb = {}, 0, 0, 0.0
    for member in tree(pid):
        info = _stat(member)
        if info is None:
            continue
        cpu[member] = info["cpu"]
        rss += info["rss"]
        threads += info["threads"]
        if pss:
            pss_kb += _pss_kb(member)
    return Footprint(cpu=cpu, rss_mb=rss / 2**20, threads=threads, processes=len(cpu),
                     pss_mb=pss_kb / 1024 if pss else float("nan"))


def cpu_between(before: Footprint, after: Footprint) -> float:
    """CPU seconds the tree used between two footprints (a process that started meanwhile counts from 0)."""
    return sum(seconds - before.cpu.get(pid, 0.0) for pid, seconds in after.cpu.items())


def thread_names(pid: int) -> dict[str, int]:
    """How many threads of ``pid`` carry each name (``/proc/PID/task/*/comm``)."""
    names: dict[str, int] = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            name = (task / "comm").read_text().strip()
        except OSError:
            continue
        names[name] = names.get(name, 0) + 1
    return names
