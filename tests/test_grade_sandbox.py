"""The grader's sandbox holds against a student who attacks it.

Student code runs in a bubblewrap sandbox (``phonglab.teaching.isolation``).
Each test here is an attack a student can make on a grader that relies on
Python's audit hooks or on a plain child process: switching the hook off
through ``gc`` and then reading ``/etc/passwd``, the host's
``/proc/1/cmdline`` and another student's folder, damaging a file outside,
running a program, leaving a daemon; killing the grader
(``pidfd_send_signal``, ``kill`` of the parent), from ``phonglab grade``
and from the page; ``kill -9`` of the grader in the middle of a grading;
importing or reloading phonglab for the answers (``tests/test_grade.py``);
and what a machine without the sandbox tool gets: a refusal in one line.
The tests that could kill the process they run in run the grader in a
child process."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.cli import main
from phonglab.teaching import isolation, shade_helpers
from phonglab.teaching.grading import GROUPS, Limits, encode_scene, format_report, grade_file
from phonglab.teaching.sandbox import Sandbox

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "grade"


def processes_with(token: str) -> list[int]:
    """The PIDs of this machine's processes whose command line holds ``token``."""
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            with open(f"/proc/{entry.name}/cmdline", "rb") as f:
                if token.encode() in f.read():
                    found.append(int(entry.name))
        except OSError:
            continue
    return found


def sleeping(pid: int) -> bool:
    """Whether process ``pid`` waits in a sleep call (the kernel's wait channel says so)."""
    try:
        with open(f"/proc/{pid}/wchan") as f:
            return "nanosleep" in f.read()
    except OSError:
        return False


def wait_until(condition, seconds: float, what: str):
    """Poll ``condition`` until it holds (returns its value) or ``seconds`` pass (returns the last value)."""
    deadline = time.monotonic() + seconds
    value = condition()
    while not value and time.monotonic() < deadline:
        time.sleep(0.05)
        value = condition()
    return value


def kill_all(pids) -> None:
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def grader_env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


@pytest.fixture
def attacks(tmp_path):
    """attacks.py aimed at a folder outside, another student's live folder and the host's init."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.txt").write_text("the answers to the exam")
    (outside / "victim.txt").write_text("a teacher's notes")
    other = Path(tempfile.mkdtemp(prefix="phonglab-student-"))  # where an older grader kept a paste
    (other / "shade.py").write_text("def shade(point, normal, eye, material, lights):  # another student's\n")
    with open("/proc/1/cmdline", "rb") as f:
        host_init = f.read().replace(b"\0", b" ").decode(errors="replace")
    token = "t" + uuid.uuid4().hex[:12]
    text = (DATA / "attacks.py").read_text()
    for marker, value in (("@TARGET@", str(outside)), ("@OTHER@", str(other)), ("@HOST_INIT@", host_init),
                          ("@TOKEN@", token)):
        text = text.replace(marker, value.replace("\\", "\\\\").replace('"', '\\"'))
    source = tmp_path / f"attacks_{token}.py"
    source.write_text(text)
    names = {}
    exec(compile("ATTACKS = " + text.split("ATTACKS = ", 1)[1].split("\n\n", 1)[0], "attacks", "exec"), names)
    yield source, outside, other, token, names["ATTACKS"]
    kill_all(processes_with(token))
    for path in other.iterdir():
        path.unlink()
    other.rmdir()


def test_attacks_with_the_audit_hook_switched_off_meet_the_operating_systems_walls(attacks):
    source, outside, other, token, names = attacks
    scene = encode_scene(pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10), [pl.AmbientLight(intensity=0.2)])
    results = {}
    with Sandbox(source, Limits(time_limit=5.0, total_limit=60.0)) as box:
        for i, attack in enumerate(names):
            if attack == "kill-parent":  # would kill this test's process under a weaker sandbox: see below
                continue
            (results[attack],) = box.evaluate([[i, 0, 0]], [[0, 0, 1]], eye=[0, 0, 5], scene=scene)
    succeeded = {a: o for a, o in results.items() if o.value is not None and np.any(o.value > 0)}
    assert not succeeded, f"attacks that got through: {succeeded}"
    for attack in ("read-passwd", "stat-shadow", "other-student"):  # not there at all
        assert "FileNotFoundError" in results[attack].error, (attack, results[attack])
    for attack in ("daemon", "sqlite-outside"):  # refused system calls (fork; making a file)
        assert results[attack].error, (attack, results[attack])
    assert results["read-init"].value is not None, "the sandbox's own /proc/1/cmdline is readable, not the host's"
    # nothing outside changed, and nothing the student started is left running
    assert sorted(p.name for p in outside.iterdir()) == ["secret.txt", "victim.txt"]
    assert (outside / "victim.txt").read_text() == "a teacher's notes"
    assert (other / "shade.py").exists()
    gone = wait_until(lambda: not processes_with(token), 10, "the sandbox to end")
    assert gone, f"processes of the student's file still running: {processes_with(token)}"


#: attacks.py's hook_off(), the first thing each of its attacks does
HOOK_OFF = "def hook_off" + (DATA / "attacks.py").read_text().split("def hook_off", 1)[1].split("\n\n\n", 1)[0]

KILLERS = {
    "pidfd": "import os, signal\n\ndef shade(point, normal, eye, material, lights):\n"
             "    signal.pidfd_send_signal(os.pidfd_open(os.getppid()), signal.SIGKILL)\n"
             "    return [0.0, 0.0, 0.0]\n",
    # the audit hook (which refused os.kill) switched off first, as attacks.py does
    "kill": "import gc, os, signal\n\n\n" + HOOK_OFF + "\n\n\ndef shade(point, normal, eye, material, lights):\n"
            "    hook_off()\n"
            "    os.kill(os.getppid(), signal.SIGKILL)\n"
            "    return [0.0, 0.0, 0.0]\n",
}


@pytest.mark.parametrize("how", sorted(KILLERS))
def test_student_code_cannot_kill_phonglab_grade(tmp_path, how):
    source = tmp_path / "killer.py"
    source.write_text(KILLERS[how])
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "grade", str(source), "--total-limit", "30"],
                          capture_output=True, text=True, env=grader_env(), timeout=300)
    assert done.returncode == 1, (done.returncode, done.stdout[-2000:], done.stderr[-2000:])
    assert "Total: 0/100" in done.stdout and "refused by the grader's sandbox" in done.stdout, done.stdout[-2000:]


def test_code_pasted_into_the_page_cannot_kill_the_server(tmp_path):
    """The page grades in the server's process: a killer pasted there must fail its cases, not end it."""
    script = ("import sys\nfrom phonglab.app.student_code import grade_code\n"
              "result = grade_code(sys.stdin.read())\nprint('score', result.get('score'), result.get('error'))\n")
    done = subprocess.run([sys.executable, "-c", script], input=KILLERS["pidfd"], capture_output=True, text=True,
                          env=grader_env(), timeout=300)
    assert done.returncode == 0 and "score 0.0 None" in done.stdout, (done.returncode, done.stdout, done.stderr[-2000:])


def test_kill_9_of_the_grader_ends_the_sandbox_and_leaves_no_folder(tmp_path):
    token = "t" + uuid.uuid4().hex[:12]
    source = tmp_path / f"sleeper_{token}.py"
    source.write_text("import time\n\ndef shade(point, normal, eye, material, lights):\n"
                      "    time.sleep(100)\n")
    temp = Path(tempfile.gettempdir())
    before = {p.name for p in temp.iterdir() if p.name.startswith(isolation.STALE_PREFIXES)}
    grader = subprocess.Popen([sys.executable, "-m", "phonglab.cli", "grade", str(source), "--time-limit", "60"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=grader_env())
    try:
        started = wait_until(lambda: [pid for pid in processes_with(token) if pid != grader.pid and sleeping(pid)],
                             120, "the student's shade to sleep")
        assert started, "the grading never reached the student's sleeping shade"
        os.kill(grader.pid, signal.SIGKILL)
        grader.wait()
        gone = wait_until(lambda: not processes_with(token), 20, "the sandbox to die with the grader")
        left = processes_with(token)
        assert gone and not left, f"still running after the grader was killed: {left}"
        after = {p.name for p in temp.iterdir() if p.name.startswith(isolation.STALE_PREFIXES)}
        assert after <= before, f"left behind: {sorted(after - before)}"
    finally:
        if grader.poll() is None:
            grader.kill()
            grader.wait()
        kill_all(processes_with(token))


def test_without_bubblewrap_grading_refuses_in_one_line(monkeypatch, capsys):
    which = isolation.shutil.which
    monkeypatch.setattr(isolation.shutil, "which", lambda name, *a, **k: None if name == "bwrap" else which(name))
    isolation._checked.cache_clear()
    try:
        status = main(["grade", str(DATA / "correct.py")])
        out, err = capsys.readouterr()
        assert status == 2 and out == "", (status, out, err)
        assert err.count("\n") == 1 and "bubblewrap (bwrap) is not installed" in err, err
        assert "apt-get install bubblewrap" in err, err
    finally:
        isolation._checked.cache_clear()


def test_without_bubblewrap_serve_refuses_student_code_in_one_line(monkeypatch, capsys):
    which = isolation.shutil.which
    monkeypatch.setattr(isolation.shutil, "which", lambda name, *a, **k: None if name == "bwrap" else which(name))
    monkeypatch.setattr("phonglab.app.serve", lambda target, **kw: pytest.fail("served without a sandbox"))
    isolation._checked.cache_clear()
    try:
        status = main(["serve", str(ROOT / "lessons"), "--allow-student-code", "--port", "0"])
        _, err = capsys.readouterr()
        assert status == 2 and err.count("\n") == 1, (status, err)
        assert "--allow-student-code" in err and "apt-get install bubblewrap" in err, err
    finally:
        isolation._checked.cache_clear()


def test_serve_start_removes_the_folders_killed_gradings_left(monkeypatch, capsys):
    monkeypatch.setattr("phonglab.app.serve", lambda target, **kw: None)
    stale = Path(tempfile.mkdtemp(prefix="phonglab-grade-"))
    (stale / "shade.py").write_text("a student's code, left by a grader killed mid-run\n")
    fresh = Path(tempfile.mkdtemp(prefix="phonglab-student-"))  # a grading running right now elsewhere
    long_ago = time.time() - 2 * isolation.STALE_AFTER
    os.utime(stale, (long_ago, long_ago))
    try:
        assert main(["serve", str(ROOT / "lessons"), "--port", "0"]) == 0
        _, err = capsys.readouterr()
        assert not stale.exists(), "the stale folder is still there"
        assert fresh.exists(), "a folder in use was removed"
        assert "folder(s) of students' code left by killed gradings" in err, err
    finally:
        for folder in (stale, fresh):
            if folder.exists():
                for path in folder.iterdir():
                    path.unlink()
                folder.rmdir()


def test_the_students_helpers_are_the_cores_vector_functions():
    rng = np.random.default_rng(3)
    vectors = np.concatenate([rng.normal(size=(50, 3)) * rng.choice([1e-200, 1e-3, 1, 1e150], size=(50, 1)),
                              [[0.0, 0.0, 0.0], [3.0, 0.0, 4.0], [0.0, 0.0, 1e-320]]])
    for v in vectors:
        assert np.allclose(shade_helpers.normalize(v), pl.normalize(v), rtol=4e-16, atol=0), v
    for a, b in zip(vectors[:-1], vectors[1:]):
        assert shade_helpers.dot(a, b) == pytest.approx(float(pl.dot(a, b)), rel=1e-15, abs=1e-300), (a, b)
        n = pl.normalize(b)
        assert np.allclose(shade_helpers.reflect(a, n), pl.reflect(a, n), rtol=1e-14, atol=1e-300), (a, b)


def test_a_student_gets_the_helpers_and_read_only_data_not_phonglab(tmp_path):
    source = tmp_path / "helpers.py"
    source.write_text(
        "import numpy as np\nfrom shade_helpers import AmbientLight, Material, normalize, dot, reflect\n\n"
        "def shade(point, normal, eye, material, lights):\n"
        "    assert isinstance(material, Material) and type(material).__module__ == 'shade_helpers'\n"
        "    try:\n"
        "        material.ka = (1, 1, 1)\n"
        "    except AttributeError:\n"
        "        pass\n"
        "    else:\n"
        "        raise AssertionError('the material can be changed')\n"
        "    ia = sum(np.array(lt.ambient_rgb) for lt in lights if isinstance(lt, AmbientLight))\n"
        "    return np.array(material.emission) + np.array(material.ka) * ia\n")
    report = grade_file(source, Limits(time_limit=2.0, total_limit=30.0), groups=GROUPS[:1])
    assert report.score == GROUPS[0].points, format_report(report)
