"""A shade() that tries to leave the sandbox; the test fills in ACTION and TARGET.

Every attempt must be refused: the case fails with the error, and nothing
outside the sandbox is read, written or started.
"""

import os

ACTION = "@ACTION@"
TARGET = "@TARGET@"


def shade(point, normal, eye, material, lights):
    if ACTION == "read":
        with open(TARGET) as f:
            return [float(len(f.read())), 0.0, 0.0]
    if ACTION == "read-dotdot":
        with open("../" * 12 + TARGET.lstrip("/")) as f:
            return [float(len(f.read())), 0.0, 0.0]
    if ACTION == "os-open":
        os.close(os.open(TARGET, os.O_RDONLY))
    if ACTION == "numpy-fromfile":
        import numpy as np

        return [float(np.fromfile(TARGET, dtype=np.uint8).sum()), 0.0, 0.0]
    if ACTION == "listdir":
        return [float(len(os.listdir(os.path.dirname(TARGET)))), 0.0, 0.0]
    if ACTION == "write":
        with open(TARGET, "w") as f:
            f.write("written from the sandbox")
    if ACTION == "system":
        os.system(f"touch {TARGET}")
    if ACTION == "subprocess":
        import subprocess

        subprocess.run(["touch", TARGET])
    if ACTION == "posixsubprocess":
        import _posixsubprocess  # noqa: F401
    if ACTION == "fork":
        os.fork()
    if ACTION == "socket":
        import socket

        socket.create_connection(("127.0.0.1", 9))
    if ACTION == "ctypes":
        import ctypes

        ctypes.CDLL("libc.so.6").system(f"touch {TARGET}".encode())
    if ACTION == "remove":
        os.remove(TARGET)
    return [0.0, 0.0, 0.0]
