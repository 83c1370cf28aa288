"""The error for bad command-line input, shared by the benchmarks and the ``phonglab`` command.

It lives here, below :mod:`phonglab.cli`, so that the benchmarks can raise it
without importing the command line; :mod:`phonglab.cli` re-exports it and
turns it into one line on stderr and exit status 2.
"""


class UsageError(Exception):
    """Bad input on the command line: printed as one line, exit status 2."""


def bounded(kind, low, high, allowed: str):
    """An ``argparse`` type: ``kind(text)`` within ``[low, high]`` (None: no bound), else "must be ALLOWED, got TEXT".

    Examples
    --------
    >>> bounded(int, 1, None, "a whole number of at least 1")("3")
    3
    """
    import argparse
    import math

    def convert(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {allowed}, got {text!r}") from None
        if (isinstance(value, float) and not math.isfinite(value)) or (low is not None and value < low) \
                or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"must be {allowed}, got {text!r}")
        return value

    return convert
