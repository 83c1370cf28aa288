"""A shade() that tries to leave the sandbox; the test fills in TARGET (a folder outside it).

The point's x coordinate picks the attempt from ATTEMPTS. Every attempt must
be refused: the case fails with the error, and nothing outside the sandbox is
read, written or started.
"""

import os

TARGET = "@TARGET@"  # a folder outside the sandbox holding "secret.txt"
SECRET = os.path.join(TARGET, "secret.txt")
MADE = os.path.join(TARGET, "made-by-student")

ATTEMPTS = [
    "read", "read-passwd", "read-dotdot", "os-open", "numpy-fromfile", "listdir", "write", "system",
    "subprocess", "posixsubprocess", "fork", "socket", "ctypes", "remove", "memory", "exit",
]


def shade(point, normal, eye, material, lights):
    attempt = ATTEMPTS[int(point[0])]
    if attempt == "read":
        with open(SECRET) as f:
            return [float(len(f.read())), 0.0, 0.0]
    if attempt == "read-passwd":
        with open("/etc/passwd") as f:
            return [float(len(f.read())), 0.0, 0.0]
    if attempt == "read-dotdot":
        with open("../" * 12 + SECRET.lstrip("/")) as f:
            return [float(len(f.read())), 0.0, 0.0]
    if attempt == "os-open":
        os.close(os.open(SECRET, os.O_RDONLY))
    if attempt == "numpy-fromfile":
        import numpy as np

        return [float(np.fromfile(SECRET, dtype=np.uint8).sum()), 0.0, 0.0]
    if attempt == "listdir":
        return [float(len(os.listdir(TARGET))), 0.0, 0.0]
    if attempt == "write":
        with open(MADE, "w") as f:
            f.write("written from the sandbox")
    if attempt == "system":
        os.system(f"touch {MADE}")
    if attempt == "subprocess":
        import subprocess

        subprocess.run(["touch", MADE])
    if attempt == "posixsubprocess":
        import _posixsubprocess  # noqa: F401
    if attempt == "fork":
        if os.fork() == 0:
            open(MADE, "w").close()
            os._exit(0)
    if attempt == "socket":
        import socket

        socket.create_connection(("127.0.0.1", 9), timeout=1)
    if attempt == "ctypes":
        import ctypes

        ctypes.CDLL("libc.so.6").system(f"touch {MADE}".encode())
    if attempt == "remove":
        os.remove(SECRET)
    if attempt == "memory":
        return [float(len(bytearray(3 << 30))), 0.0, 0.0]  # past the 2 GiB address-space limit
    if attempt == "exit":
        os._exit(3)  # ends the worker: this case fails, the next one gets a fresh worker
    return [0.0, 0.0, 0.0]
