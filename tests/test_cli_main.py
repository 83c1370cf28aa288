"""The phonglab command's dispatcher: help, unknown commands, closed pipes."""

import subprocess
import sys

SCENE = "assets/scenes/spotlight.toml"


def phonglab(*args, **kw):
    return subprocess.run([sys.executable, "-m", "phonglab.cli", *args], capture_output=True, text=True,
                          timeout=120, **kw)


def test_no_command_prints_help_and_exits_2():
    out = phonglab()
    assert out.returncode == 2, out
    for name in ("serve", "export", "check", "plan", "bench"):
        assert name in out.stdout, (name, out.stdout)


def test_unknown_command_is_a_usage_error():
    out = phonglab("render")
    assert out.returncode == 2 and "invalid choice" in out.stderr, out


def test_closed_pipe_ends_quietly():
    # the reader is gone before the command writes anything (like `| head` after its lines)
    import os

    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        out = subprocess.run([sys.executable, "-m", "phonglab.cli", "plan", SCENE], stdout=write_end,
                             stderr=subprocess.PIPE, text=True, timeout=120)
    finally:
        os.close(write_end)
    assert out.returncode == 0 and "Traceback" not in out.stderr and "Exception" not in out.stderr, out
