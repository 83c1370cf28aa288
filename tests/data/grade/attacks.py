"""A shade() that attacks the grader the way a student could; the test fills in the @...@ markers.

The point's x coordinate picks the attack from ATTACKS. Each attack first
switches off any Python audit hook the grader may rely on (a student can:
the hook is a function reachable through gc, and one that guards against
recursion with a ``busy`` list in its closure returns early once that list
is not empty), then tries to leave the sandbox. An attack that succeeds
returns a colour that says so (a positive red channel, or the secret's
length); a refused one fails the case with its error."""

import gc
import os
import signal
import time

TARGET = "@TARGET@"  # a folder outside the sandbox: secret.txt to read, victim.txt to damage
OTHER = "@OTHER@"  # another student's live folder, holding their shade.py
HOST_INIT = "@HOST_INIT@"  # the host's /proc/1/cmdline, NUL bytes as spaces
TOKEN = "@TOKEN@"  # in this file's name: how the test finds processes left behind

ATTACKS = ["read-passwd", "read-init", "other-student", "damage", "run-id", "daemon", "stat-shadow",
           "sqlite-outside", "kill-parent"]


def hook_off():
    """Make every audit hook installed by a closure holding a list named ``busy`` return early."""
    for obj in gc.get_objects():
        code = getattr(obj, "__code__", None)
        if code is None or "busy" not in code.co_freevars or not obj.__closure__:
            continue
        cell = obj.__closure__[code.co_freevars.index("busy")]
        try:
            if isinstance(cell.cell_contents, list):
                cell.cell_contents.append(1)
        except ValueError:  # an empty cell
            pass


def shade(point, normal, eye, material, lights):
    hook_off()
    attack = ATTACKS[int(point[0])]
    if attack == "read-passwd":
        with open("/etc/passwd") as f:
            return [float(len(f.read())), 0.0, 0.0]
    if attack == "read-init":
        with open("/proc/1/cmdline", "rb") as f:
            seen = f.read().replace(b"\0", b" ").decode(errors="replace").strip()
        return [1.0 if seen == HOST_INIT.strip() else 0.0, 0.0, 0.0]
    if attack == "other-student":
        folder = os.path.dirname(OTHER)
        visible = [name for name in os.listdir(folder) if name == os.path.basename(OTHER)]
        with open(os.path.join(OTHER, "shade.py")) as f:
            return [float(len(visible)), float(len(f.read())), 0.0]
    if attack == "damage":
        with open(os.path.join(TARGET, "victim.txt"), "r+") as f:
            f.truncate(0)
        os.rename(os.path.join(TARGET, "victim.txt"), os.path.join(TARGET, "renamed.txt"))
        return [1.0, 0.0, 0.0]
    if attack == "run-id":
        return [1.0 if os.system("id > /dev/null") == 0 else 0.0, 0.0, 0.0]  # 127 << 8: no shell was started
    if attack == "daemon":
        if os.fork() == 0:  # the child: a new session, then a grandchild that outlives the grader
            os.setsid()
            if os.fork() == 0:
                time.sleep(600)
            os._exit(0)
        return [1.0, 0.0, 0.0]
    if attack == "stat-shadow":
        return [float(os.stat("/etc/shadow").st_size) + 1.0, 0.0, 0.0]
    if attack == "sqlite-outside":
        import sqlite3

        sqlite3.connect(os.path.join(TARGET, "made.db")).execute("create table t (x)")
        return [1.0, 0.0, 0.0]
    if attack == "kill-parent":
        os.kill(os.getppid(), signal.SIGKILL)
        signal.pidfd_send_signal(os.pidfd_open(os.getppid()), signal.SIGKILL)
        return [1.0, 0.0, 0.0]
    return [0.0, 0.0, 0.0]
