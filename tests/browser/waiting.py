"""Polling for the browser tests: the page updates asynchronously."""

import time

import pytest


def wait_for(predicate, what, timeout=20.0):
    """Poll ``predicate()`` until it is truthy; fail naming ``what`` and the last value."""
    deadline = time.monotonic() + timeout
    value = None
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    pytest.fail(f"timed out after {timeout:.0f} s waiting for {what}; last value: {value!r}")
