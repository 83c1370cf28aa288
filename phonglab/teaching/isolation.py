"""The operating system's walls around a student's code: a bubblewrap sandbox with a seccomp filter.

:class:`phonglab.teaching.sandbox.Sandbox` starts every grading worker with
:func:`command`: ``bwrap`` (bubblewrap, the sandbox tool of Flatpak, packaged
by every major distribution) builds for it

- **its own namespaces**: user (the student's code runs as uid/gid 65534,
  ``nobody``, with no capabilities), PID (it sees only its own sandbox; a
  small init from bwrap is PID 1 and everything in the sandbox dies with
  it), network (no interface but a loopback that is down), IPC, UTS and
  cgroup; ``--die-with-parent`` kills the whole sandbox when the grader
  dies, even by ``kill -9``; ``--new-session`` keeps it off the terminal;
- **its own file system**: an empty tmpfs root holding, read-only, only
  what the worker needs: the Python interpreter, its shared libraries and
  standard library (with ``site-packages`` hidden under an empty tmpfs),
  NumPy, the worker script, the student's helper module
  (:mod:`phonglab.teaching.shade_helpers`) and the student's file (copied
  into the sandbox from memory, never written on the host); a new ``/proc``
  showing its own processes, a minimal ``/dev`` and an empty private
  ``/tmp``. No ``/etc``, no home folders, no phonglab package, no other
  student's file. All of it disappears with the sandbox, whatever ends it;
- **a seccomp filter** (:func:`seccomp_program`, built with libseccomp and
  handed to bwrap as a BPF program) that makes the system calls a ``shade``
  function never needs fail with ``EPERM``: new processes and threads,
  signals, ``ptrace`` and the other process's memory, ``pidfd_*``,
  sockets, mounts and namespaces, keyrings, BPF, ``io_uring``, kernel
  modules and clocks, and creating, renaming or removing files. Calls for
  another architecture's system call table end the process.

The worker then lowers its own resource limits (address space, CPU time,
open files, file size 0, no core dumps) before it reads the student's file;
without capabilities it cannot raise them again.

The interpreter's files are found once per process by :func:`runtime`:
a Python started like the worker imports NumPy and the modules a student may
use, and the shared objects it then maps (``/proc/self/maps``) are what the
sandbox binds, each at its own path, with the symbolic links that lead to
them (the loader's ``PT_INTERP`` path, ``libz.so.1 → libz.so.1.2.13``).

When bwrap or libseccomp is missing, or cannot make a sandbox on this
machine, :func:`check` raises :class:`SandboxUnavailable` with one line
saying what to install: student code never runs unisolated.
"""

from __future__ import annotations

import errno
import functools
import json
import os
import shutil
import stat
import subprocess
import sys
import sysconfig
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

__all__ = ["SandboxUnavailable", "Runtime", "runtime", "seccomp_program", "check", "command",
           "SANDBOX_DIR", "remove_stale_folders", "INSTALL_HINT"]

#: the student's folder inside the sandbox (a read-only file in the sandbox's own tmpfs root)
SANDBOX_DIR = "/sandbox"
#: where the worker, the helper module and NumPy are inside the sandbox
GRADER_DIR = "/grader"
SITE_DIR = GRADER_DIR + "/site"
#: the unprivileged user and group inside the sandbox (``nobody``/``nogroup``)
SANDBOX_UID = 65534
#: the private /tmp (bytes): nothing can be created in it, the size only bounds the mount
TMP_SIZE = 1 << 20

WORKER = Path(__file__).with_name("sandbox_worker.py")
HELPERS = Path(__file__).with_name("shade_helpers.py")

INSTALL_HINT = "install bubblewrap and libseccomp (Debian/Ubuntu: apt-get install bubblewrap libseccomp2)"

#: what the worker and a student may import: their shared objects are bound into the sandbox
PROBE_MODULES = ("numpy", "math", "cmath", "json", "random", "statistics", "fractions", "decimal", "dataclasses",
                 "functools", "itertools", "collections", "typing", "operator", "traceback", "struct", "array",
                 "resource", "signal", "importlib.util")

#: the worker's environment (and the probe's, so that they map the same files)
ENVIRONMENT = {"HOME": SANDBOX_DIR, "TMPDIR": "/tmp", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
               "MKL_NUM_THREADS": "1"}

#: system calls refused with EPERM; names this libseccomp or architecture does not know are skipped
REFUSED_SYSCALLS = (
    # new processes and threads (execve stays: bwrap itself starts the worker with it)
    "fork", "vfork", "clone", "clone3", "execveat",
    # signals to anyone, and reaching into other processes
    "kill", "tkill", "tgkill", "rt_sigqueueinfo", "rt_tgsigqueueinfo", "pidfd_open", "pidfd_send_signal",
    "pidfd_getfd", "ptrace", "process_vm_readv", "process_vm_writev", "process_madvise", "kcmp",
    # namespaces and mounts
    "unshare", "setns", "mount", "umount2", "pivot_root", "chroot", "move_mount", "open_tree", "fsopen",
    "fsconfig", "fsmount", "fspick", "mount_setattr",
    # the network
    "socket", "socketpair",
    # kernel facilities a shading function never needs
    "keyctl", "add_key", "request_key", "bpf", "perf_event_open", "userfaultfd", "io_uring_setup",
    "io_uring_enter", "io_uring_register", "kexec_load", "kexec_file_load", "init_module", "finit_module",
    "delete_module", "reboot", "swapon", "swapoff", "acct", "quotactl", "quotactl_fd", "syslog", "iopl", "ioperm",
    "settimeofday", "clock_settime", "clock_adjtime", "adjtimex", "sethostname", "setdomainname",
    "name_to_handle_at", "open_by_handle_at", "fanotify_init", "lookup_dcookie", "vhangup", "migrate_pages",
    "move_pages",
    # making, renaming or removing files (open with O_CREAT is refused below)
    "creat", "openat2", "mkdir", "mkdirat", "mknod", "mknodat", "link", "linkat", "symlink", "symlinkat",
    "rename", "renameat", "renameat2", "unlink", "unlinkat", "rmdir",
)

#: ``open``'s flags argument: its index in ``open`` and ``openat``
_OPEN_FLAGS = {"open": 1, "openat": 2}
_O_TMPFILE_BIT = 0o20000000  # __O_TMPFILE, without O_DIRECTORY


class SandboxUnavailable(RuntimeError):
    """The sandbox cannot be made here; ``str()`` is one line saying why and what to install."""


# ---------------------------------------------------------------------------
# the seccomp filter


def _libseccomp():
    """libseccomp's Python binding: the official one when installed, else pyseccomp (same API, ctypes)."""
    try:
        import seccomp  # the bindings shipped with libseccomp (e.g. Debian's python3-seccomp)
        return seccomp
    except ImportError:
        pass
    try:
        import pyseccomp
    except ImportError:
        raise SandboxUnavailable("the Python package pyseccomp is missing: pip install pyseccomp") from None
    except (RuntimeError, OSError):  # the package is there, libseccomp.so is not
        raise SandboxUnavailable(f"libseccomp is not installed: {INSTALL_HINT}") from None
    return pyseccomp


@functools.lru_cache(maxsize=1)
def seccomp_program() -> bytes:
    """The filter as a classic BPF program (libseccomp's ``seccomp_export_bpf``), for ``bwrap --seccomp``.

    Every call of :data:`REFUSED_SYSCALLS`, and ``open``/``openat`` with
    ``O_CREAT`` or ``O_TMPFILE``, fails with ``EPERM``; everything else is
    allowed (the namespaces, the read-only file system and the resource
    limits bound it). libseccomp adds the architecture check: a call made
    through another system call table (e.g. 32-bit ``int 0x80``) kills the
    process.
    """
    seccomp = _libseccomp()
    refuse = seccomp.ERRNO(errno.EPERM)
    rules = seccomp.SyscallFilter(defaction=seccomp.ALLOW)
    for name in REFUSED_SYSCALLS:
        try:
            rules.add_rule(refuse, name)
        except (ValueError, OSError, RuntimeError):  # not a system call of this architecture or libseccomp
            continue
    for name, index in _OPEN_FLAGS.items():
        for bit in (os.O_CREAT, _O_TMPFILE_BIT):
            try:
                rules.add_rule(refuse, name, seccomp.Arg(index, seccomp.MASKED_EQ, bit, bit))
            except (ValueError, OSError, RuntimeError):
                continue
    fd = os.memfd_create("phonglab-seccomp")
    try:
        with os.fdopen(os.dup(fd), "wb") as out:
            rules.export_bpf(out)
        os.lseek(fd, 0, os.SEEK_SET)
        with os.fdopen(os.dup(fd), "rb") as back:
            return back.read()
    finally:
        os.close(fd)


# ---------------------------------------------------------------------------
# what the worker needs: the runtime's files


@dataclass(frozen=True)
class Runtime:
    """The interpreter and the files the sandbox binds for it.

    Attributes
    ----------
    python : str
        The interpreter's real path (bound at that path: Python finds its
        standard library from it).
    binds : tuple of (source, destination)
        Read-only bind mounts, files or folders.
    symlinks : tuple of (target, link)
        Symbolic links made in the sandbox, as on the host.
    hidden : tuple of str
        Folders covered by an empty read-only tmpfs (``site-packages`` inside
        the standard library's folder).
    """

    python: str
    binds: tuple[tuple[str, str], ...]
    symlinks: tuple[tuple[str, str], ...]
    hidden: tuple[str, ...]


def _numpy_folders() -> list[str]:
    """NumPy's package folder and, beside it, the folder of its bundled libraries (wheels)."""
    import numpy

    package = os.path.realpath(os.path.dirname(numpy.__file__))
    libs = package + ".libs"
    return [package] + ([libs] if os.path.isdir(libs) else [])


_PROBE = """
import json, sys
sys.path.insert(0, {site!r})
for name in {modules!r}:
    __import__(name)
maps = set()
with open("/proc/self/maps") as f:
    for line in f:
        parts = line.split(None, 5)
        if len(parts) == 6 and parts[5].startswith("/"):
            maps.add(parts[5].rstrip("\\n").removesuffix(" (deleted)"))
print(json.dumps(sorted(maps)))
"""


def _interpreter_path(executable: str) -> str | None:
    """The ELF ``PT_INTERP`` of ``executable`` (the dynamic loader it asks for), or None."""
    import struct

    try:
        with open(executable, "rb") as f:
            head = f.read(64)
            if head[:4] != b"\x7fELF" or head[4] != 2 or head[5] != 1:  # 64-bit little-endian only
                return None
            phoff, = struct.unpack_from("<Q", head, 0x20)
            phentsize, phnum = struct.unpack_from("<HH", head, 0x36)
            for i in range(phnum):
                f.seek(phoff + i * phentsize)
                p_type, _, p_offset, _, _, p_filesz = struct.unpack("<IIQQQQ", f.read(40))
                if p_type == 3:  # PT_INTERP
                    f.seek(p_offset)
                    return f.read(p_filesz).rstrip(b"\0").decode()
    except (OSError, struct.error, UnicodeDecodeError):
        return None
    return None


def _links_to(path: str, symlinks: dict) -> str:
    """Record every symbolic link on the way to ``path`` (its folders' and its own); return its real path."""
    parts = Path(path).parts
    current = "/"
    for i, part in enumerate(parts[1:], 1):
        candidate = os.path.join(current, part)
        if os.path.islink(candidate):
            target = os.readlink(candidate)
            symlinks[candidate] = target
            current = _links_to(os.path.normpath(os.path.join(current, target)), symlinks)
        else:
            current = candidate
    return current


@functools.lru_cache(maxsize=1)
def runtime() -> Runtime:
    """The files of this interpreter that the sandbox binds (probed once per process).

    Raises
    ------
    SandboxUnavailable
        When the probe cannot run Python with NumPy.
    """
    python = os.path.realpath(sys.executable)
    numpy_folders = _numpy_folders()
    env = dict(ENVIRONMENT, HOME=tempfile.gettempdir())
    code = _PROBE.format(site=os.path.dirname(numpy_folders[0]), modules=PROBE_MODULES)
    try:
        done = subprocess.run([python, "-I", "-S", "-B", "-c", code], capture_output=True, env=env, timeout=60,
                              cwd="/")
        mapped = json.loads(done.stdout)
    except (OSError, subprocess.SubprocessError, ValueError):
        raise SandboxUnavailable(f"cannot run {python} with NumPy to find the files the sandbox needs") from None
    stdlib = {os.path.realpath(sysconfig.get_paths()[key]) for key in ("stdlib", "platstdlib")}
    site = {os.path.realpath(sysconfig.get_paths()[key]) for key in ("purelib", "platlib")}

    def under(path, folders):
        return any(path == f or path.startswith(f + os.sep) for f in folders)

    symlinks: dict[str, str] = {}
    files = {python}
    for path in mapped:
        if not under(path, stdlib) and not under(path, numpy_folders) and os.path.isfile(path):
            files.add(os.path.realpath(path))
    loader = _interpreter_path(python)
    if loader:
        files.add(_links_to(loader, symlinks))
    # the names a library is asked for by (libz.so.1 for libz.so.1.2.13): links beside it
    for folder in sorted({os.path.dirname(f) for f in files}):
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for entry in entries:
            if entry.is_symlink() and os.path.realpath(entry.path) in files:
                symlinks[entry.path] = os.readlink(entry.path)
    # top-level links such as /lib -> usr/lib (the loader's search path goes through them)
    for entry in os.scandir("/"):
        if entry.is_symlink():
            symlinks.setdefault(entry.path, os.readlink(entry.path))
    binds = [(f, f) for f in sorted(files)]
    binds += [(folder, folder) for folder in sorted(stdlib)]
    binds += [(folder, f"{SITE_DIR}/{os.path.basename(folder)}") for folder in numpy_folders]
    hidden = tuple(sorted(s for s in site if under(s, stdlib)))
    return Runtime(python, tuple(binds), tuple(sorted((t, link) for link, t in symlinks.items())), hidden)


# ---------------------------------------------------------------------------
# the command


def bwrap() -> str:
    """The bwrap executable, or SandboxUnavailable saying what to install."""
    path = shutil.which("bwrap")
    if path is None:
        raise SandboxUnavailable(f"bubblewrap (bwrap) is not installed: {INSTALL_HINT}")
    return path


def command(student_name: str, worker_args, fds: dict) -> tuple[list[str], list[str]]:
    """bwrap's options (for ``--args``) and the command they run: the worker on the student's file.

    Parameters
    ----------
    student_name : str
        The file's name in the sandbox (``/sandbox/NAME``).
    worker_args : list of str
        The worker's own arguments after the student's file.
    fds : dict
        Open descriptors bwrap reads: ``"seccomp"`` (the BPF program) and
        ``"code"`` (the student's file).
    """
    rt = runtime()
    args = ["--unshare-all", "--die-with-parent", "--new-session", "--uid", str(SANDBOX_UID),
            "--gid", str(SANDBOX_UID), "--hostname", "sandbox", "--clearenv"]
    for key, value in ENVIRONMENT.items():
        args += ["--setenv", key, value]
    for source, destination in rt.binds:
        args += ["--ro-bind", source, destination]
    for folder in rt.hidden:
        args += ["--tmpfs", folder, "--remount-ro", folder]
    for target, link in rt.symlinks:
        args += ["--symlink", target, link]
    args += ["--ro-bind", str(WORKER), f"{GRADER_DIR}/worker.py",
             "--ro-bind", str(HELPERS), f"{GRADER_DIR}/shade_helpers.py",
             "--proc", "/proc", "--dev", "/dev", "--size", str(TMP_SIZE), "--tmpfs", "/tmp",
             "--ro-bind-data", str(fds["code"]), f"{SANDBOX_DIR}/{student_name}",
             "--remount-ro", "/", "--chdir", SANDBOX_DIR, "--seccomp", str(fds["seccomp"])]
    return args, [rt.python, "-I", "-S", "-B", f"{GRADER_DIR}/worker.py", f"{SANDBOX_DIR}/{student_name}",
                  *worker_args]


def start(options, argv, fds, **popen) -> subprocess.Popen:
    """Start ``bwrap --args FD -- argv`` with ``options`` read from an in-memory file, passing ``fds``.

    The options (every bind mount) are not on bwrap's command line, so the
    sandbox's ``/proc/1/cmdline`` shows only the worker's command.
    """
    program = bwrap()
    fd = memory_file("phonglab-bwrap-args", "\0".join(options).encode() + b"\0")
    try:
        return subprocess.Popen([program, "--args", str(fd), "--", *argv], pass_fds=(fd, *fds), **popen)
    finally:
        os.close(fd)


def memory_file(name: str, data: bytes) -> int:
    """An anonymous in-memory file holding ``data``, read from its start (for bwrap's descriptors)."""
    fd = os.memfd_create(name)
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]
    os.lseek(fd, 0, os.SEEK_SET)
    return fd


@functools.lru_cache(maxsize=1)
def _checked() -> bool:
    """Run ``python -c 'import numpy'`` in the sandbox once; SandboxUnavailable with bwrap's reason if it fails."""
    bwrap()
    opened = [memory_file("phonglab-seccomp", seccomp_program()), memory_file("phonglab-code", b"")]
    options, _ = command("check.py", [], {"seccomp": opened[0], "code": opened[1]})
    # the same sandbox, with the worker replaced by a one-line check
    argv = [runtime().python, "-I", "-S", "-B", "-c", f"import sys; sys.path.insert(0, {SITE_DIR!r}); import numpy"]
    try:
        with start(options, argv, opened, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                   stderr=subprocess.PIPE, start_new_session=True) as process:
            try:
                _, stderr = process.communicate(timeout=60)
            except subprocess.TimeoutExpired:
                process.kill()
                raise
    except (OSError, subprocess.SubprocessError) as exc:
        raise SandboxUnavailable(f"bubblewrap could not start: {exc}; {INSTALL_HINT}") from None
    finally:
        for fd in opened:
            os.close(fd)
    if process.returncode != 0:
        lines = [line for line in stderr.decode(errors="replace").splitlines() if line.strip()]
        reason = lines[-1].strip() if lines else f"exit status {process.returncode}"
        raise SandboxUnavailable(f"bubblewrap cannot make the grader's sandbox here: {reason[:200]}")
    return True


def check() -> None:
    """Raise :class:`SandboxUnavailable` (one line: why, and what to install) unless the sandbox works here."""
    _checked()


# ---------------------------------------------------------------------------
# leftovers of earlier versions


#: the folders graders before this sandbox made on the host for students' files
STALE_PREFIXES = ("phonglab-grade-", "phonglab-student-")
#: seconds after which such a folder is stale: every grading ends within its limits, far sooner
STALE_AFTER = 15 * 60


def remove_stale_folders(folder=None) -> list[str]:
    """Remove the students' folders that killed gradings of earlier versions left in the temporary folder.

    The sandbox keeps a student's file in its own tmpfs, which disappears
    with it; a grader that was killed before this sandbox existed left its
    copy in ``phonglab-grade-*`` or ``phonglab-student-*``. Only folders
    owned by this user and untouched for :data:`STALE_AFTER` seconds are
    removed (a grader of such a version may still be running). Returns
    their names.
    """
    folder = Path(folder or tempfile.gettempdir())
    removed = []
    for path in (p for prefix in STALE_PREFIXES for p in folder.glob(prefix + "*")):
        try:
            info = path.lstat()
        except OSError:  # removed meanwhile
            continue
        mine = stat.S_ISDIR(info.st_mode) and info.st_uid == os.geteuid()
        if mine and time.time() - info.st_mtime > STALE_AFTER:
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path.name)
    return sorted(removed)
