"""The error for bad command-line input, shared by the benchmarks and the ``phonglab`` command.

It lives here, below :mod:`phonglab.cli`, so that the benchmarks can raise it
without importing the command line; :mod:`phonglab.cli` re-exports it and
turns it into one line on stderr and exit status 2.
"""


class UsageError(Exception):
    """Bad input on the command line: printed as one line, exit status 2."""
