"""Shared test set-up.

The browser tests keep one Playwright instance for the whole session, and
Playwright's synchronous API leaves its event loop marked as running in the
main thread while it lives. Code under test that asks whether a loop runs
(the app defers panel refreshes to a running loop; ``asyncio.run`` refuses
to start inside one) would then behave as if it were inside a server. Every
test outside ``tests/browser`` runs with no loop marked as running, as it
would on its own.
"""

import asyncio
from pathlib import Path

import pytest

BROWSER_DIR = Path(__file__).parent / "browser"


@pytest.fixture(autouse=True)
def _no_event_loop_left_running(request):
    loop = asyncio._get_running_loop()
    if loop is None or BROWSER_DIR in Path(str(request.node.fspath)).parents:
        yield
        return
    asyncio._set_running_loop(None)
    try:
        yield
    finally:
        asyncio._set_running_loop(loop)


@pytest.fixture
def lesson_app(tmp_path):
    """A factory: ``lesson_app(name, text, server_name)`` is :func:`app_support.open_app` on ``tmp_path``.

    Every app it opened is closed when the test ends.
    """
    from app_support import open_app

    opened = []

    def open_one(name: str, text: str, server_name: str):
        opened.append(open_app(tmp_path, name, text, server_name))
        return opened[-1]

    yield open_one
    for application in opened:
        application.close()

# this file is set-up, not a module of tests: keep --doctest-modules from importing it a second time
collect_ignore = ["conftest.py"]
