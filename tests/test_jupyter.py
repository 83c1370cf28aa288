"""phonglab in Jupyter: the example notebook runs headless, the view's address works behind JupyterHub,
and the jupyter-server-proxy entry serves the app through a Jupyter server.

These need the ``jupyter`` extra (``pip install -e ".[jupyter,test]"``, as ``.ci/run`` does).
"""

from __future__ import annotations

import asyncio
import re
import sys
import time
import tomllib
import urllib.request
from pathlib import Path
from types import SimpleNamespace

import aiohttp
import msgpack
import pytest

from phonglab.app import protocol
from phonglab.bench.scenes import lesson, red_sphere_tables
from phonglab.bench.ui import free_port, log_tail, start_server, stop_server

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "assets" / "notebooks" / "04-specular.ipynb"
SMALL = lesson('title = "A small sphere"\ncontrols = ["material.ks"]', red_sphere_tables(12), "# A small sphere")


def _need(module: str):
    try:
        return __import__(module)
    except ImportError:
        pytest.fail(f"{module} is missing: install the jupyter extra, pip install -e \".[jupyter]\"", pytrace=False)


@pytest.fixture()
def small_lessons(tmp_path) -> Path:
    folder = tmp_path / "lessons"
    folder.mkdir()
    (folder / "01-sphere.md").write_text(SMALL, encoding="utf-8")
    return folder


# ---------------------------------------------------------------------------
# the example notebook


def _outputs(cell) -> tuple[str, str, set]:
    """A code cell's printed text, its HTML and the kinds of data it showed (``stderr`` among them if it wrote there)."""
    text, html, kinds = "", "", set()
    for output in cell.get("outputs", []):
        text += output.get("text", "")
        if output.get("name") == "stderr":
            kinds.add("stderr")
        data = output.get("data", {})
        text += data.get("text/plain", "")
        html += data.get("text/html", "")
        kinds |= set(data)
    return text, html, kinds


def test_the_example_notebook_runs_headless_and_shows_two_independent_views(tmp_path):
    nbformat = _need("nbformat")
    nbclient = _need("nbclient")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    # run where a teacher's copy of it runs, outside the repository: it finds the lessons beside phonglab
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    cells = [_outputs(c) for c in notebook.cells if c.cell_type == "code"]
    # a warning in a view's cell (IPython's about a bare iframe) reads to a student as an error
    written = [text for text, _, kinds in cells if "stderr" in kinds]
    assert not written, f"cells wrote to stderr: {written}"
    views = [html for _, html, _ in cells if "<iframe" in html]
    ports = [re.search(r'src="http://localhost:(\d+)/index\.html', html) for html in views]
    assert len(views) == 2 and all(ports), f"expected two views, each an iframe on its own port:\n{views}"
    assert ports[0].group(1) != ports[1].group(1), views
    printed = "\n".join(text for text, _, _ in cells)
    assert "α = 150.0" in printed, printed
    assert "first view k_s = (0.6, 0.6, 0.6)   second view k_s = (0.2, 0.2, 0.2)" in printed, printed
    assert "(0.0, 3.0, 3.0)" in printed, printed  # the moved light, read back from view.scene
    assert any("image/png" in kinds for _, _, kinds in cells), "the figure was not shown inline"


# ---------------------------------------------------------------------------
# the view's address behind JupyterHub


def test_behind_jupyterhub_the_view_is_addressed_through_the_hubs_proxy(small_lessons, monkeypatch):
    _need("IPython")
    from phonglab.app.jupyter import show

    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ana/")

    async def make():
        view = show(small_lessons / "01-sphere.md", material__ks=0.25)
        try:
            await view.app.server.ready
            return view.url, view.port, view._repr_html_(), view.scene.material.ks
        finally:
            view.close()

    url, port, html, ks = asyncio.run(make())
    assert url == f"/user/ana/proxy/{port}/index.html?ui=main&reconnect=auto", url
    assert f'src="{url}"' in html, html
    assert ks == (0.25, 0.25, 0.25), ks


def test_a_bad_setting_names_the_field(small_lessons):
    _need("IPython")
    from phonglab.app.jupyter import show
    from phonglab.scene import SceneError

    async def make():
        with pytest.raises(SceneError, match="material.ks"):
            show(small_lessons / "01-sphere.md", material__ks=-3)

    asyncio.run(make())


def test_a_misspelled_lesson_is_named_with_the_lessons_that_come_close(small_lessons):
    _need("IPython")
    from phonglab.app.jupyter import show

    with pytest.raises(FileNotFoundError) as raised:
        show(small_lessons / "01-spere.md")
    message = str(raised.value)
    assert "no such lesson or scene file" in message and "01-spere.md" in message, message
    assert f"did you mean {str(small_lessons / '01-sphere.md')!r}?" in message, message
    assert "\n" not in message and "has errors" not in message, message
    with pytest.raises(FileNotFoundError, match="there is no folder"):
        show(small_lessons / "nowhere" / "01-sphere.md")


# ---------------------------------------------------------------------------
# jupyter-server-proxy


def test_the_package_declares_the_server_proxy_entry():
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["entry-points"]
    assert declared["jupyter_serverproxy_servers"] == {"phonglab": "phonglab.app.jupyter_proxy:setup_phonglab"}


@pytest.fixture()
def jupyter_server(small_lessons, tmp_path):
    """A Jupyter server under ``/user/ana/`` (as JupyterHub runs one per student) with phonglab's proxy entry."""
    _need("jupyter_server_proxy")
    port, token, base = free_port(), "phonglab-test-token", "/user/ana/"
    config = tmp_path / "jupyter_server_config.py"
    config.write_text("from phonglab.app.jupyter_proxy import setup_phonglab\n"
                      "c.ServerProxy.servers = {'phonglab': setup_phonglab()}\n", encoding="utf-8")
    log_path = tmp_path / "jupyter.log"
    command = [sys.executable, "-m", "jupyter_server", "--no-browser", f"--port={port}", "--ip=127.0.0.1",
               f"--ServerApp.token={token}", f"--ServerApp.base_url={base}", f"--ServerApp.root_dir={tmp_path}",
               f"--config={config}", "--allow-root"]
    process = start_server(command, log_path=log_path, env={"PHONGLAB_LESSONS": str(small_lessons),
                                                            "JUPYTER_CONFIG_DIR": str(tmp_path / "config")})
    try:
        yield SimpleNamespace(port=port, base=base, origin=f"http://127.0.0.1:{port}", process=process,
                              log=log_path, auth={"Authorization": f"token {token}"})
    finally:
        stop_server(process)


def test_the_server_proxy_entry_starts_phonglab_and_the_page_works_through_it(jupyter_server):
    from phonglab.app.jupyter_proxy import setup_phonglab

    hub = jupyter_server
    assert setup_phonglab()["command"][-2:] == ["--url-prefix", "{base_url}phonglab/"]
    app = f"{hub.origin}{hub.base}phonglab/"
    page = _get_when_up(f"{app}index.html", hub.auth, hub.process, hub.log)
    assert "<html" in page.lower() and "phonglab" in page.lower(), page[:300]

    async def session():
        async with aiohttp.ClientSession(headers=hub.auth) as http:
            async with http.post(f"{app}paraview/", json={}, headers={"Origin": hub.origin}) as answer:
                assert answer.status == 200, (answer.status, await answer.text())
                launch = await answer.json()
            async with http.post(f"{app}paraview/", json={}, headers={"Origin": "http://evil.example"}) as refused:
                foreign = refused.status
            ws_url = launch["sessionURL"].replace("USE_HOST", f"127.0.0.1:{hub.port}").replace("ws://", "http://")
            title = await _lesson_title(http, ws_url, hub.origin, launch["secret"])
            return launch["sessionURL"], foreign, title

    session_url, foreign, title = asyncio.run(asyncio.wait_for(session(), 180))
    assert session_url == f"ws://USE_HOST{hub.base}phonglab/ws", session_url
    assert foreign == 403, foreign
    assert title == "A small sphere", title


def test_a_notebook_view_works_through_the_hubs_proxy_address(jupyter_server, small_lessons, monkeypatch):
    # the kernel's view, addressed as the cell's iframe addresses it inside JupyterHub
    _need("IPython")
    from phonglab.app.jupyter import show

    hub = jupyter_server
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", hub.base)

    def through_the_hub(view) -> tuple[str, str]:
        # in a thread, while the view's trame server runs in the main thread's loop (as in a kernel)
        url = view.url
        page = _get_when_up(hub.origin + url, hub.auth, hub.process, hub.log)
        assert "<html" in page.lower(), page[:300]
        # the trame client's own WebSocket address: the page's folder + "ws", with trame's default secret
        ws_url = hub.origin + url.split("index.html")[0] + "ws"

        async def session():
            async with aiohttp.ClientSession(headers=hub.auth) as http:
                return await _lesson_title(http, ws_url, hub.origin, "wslink-secret")

        return url, asyncio.run(asyncio.wait_for(session(), 120))

    async def kernel():
        view = show(small_lessons / "01-sphere.md")
        try:
            await view.app.server.ready
            return view.port, await asyncio.to_thread(through_the_hub, view)
        finally:
            view.close()

    port, (url, title) = asyncio.run(asyncio.wait_for(kernel(), 300))
    assert url.startswith(f"{hub.base}proxy/{port}/index.html"), url
    assert title == "A small sphere", title


async def _lesson_title(http, ws_url: str, origin: str, secret: str):
    """Log in over ``ws_url`` with ``secret`` and read the page's state: the open lesson's title."""
    async with http.ws_connect(ws_url, headers={"Origin": origin}, max_msg_size=0) as ws:
        for rpc_id, method, args in [(protocol.HELLO_ID, "wslink.hello", [{"secret": secret}]),
                                     ("rpc:c1:1", "trame.state.get", [])]:
            await ws.send_bytes(protocol.chunk(msgpack.packb(
                {"wslink": "1.0", "id": rpc_id, "method": method, "args": args, "kwargs": {}})))
            answer = await _reply(ws, rpc_id)
            assert answer and "result" in answer, (method, answer)
        return answer["result"]["state"].get("lesson_title")


def _get_when_up(url: str, headers: dict, process, log_path, timeout: float = 180.0) -> str:
    """GET ``url`` once it answers 200 (jupyter-server-proxy starts phonglab on the first request)."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        assert process.poll() is None, f"the Jupyter server exited:\n{log_tail(log_path)}"
        try:
            with urllib.request.urlopen(urllib.request.Request(url, headers=headers), timeout=60) as answer:
                if answer.status == 200:
                    return answer.read().decode("utf-8", "replace")
        except OSError as exc:
            last = exc
        time.sleep(0.5)
    pytest.fail(f"{url} did not answer within {timeout:.0f} s ({last}):\n{log_tail(log_path)}")


async def _reply(ws, rpc_id, timeout: float = 120.0):
    pending = {}
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        message = await ws.receive(timeout=max(0.1, deadline - time.monotonic()))
        if message.type != aiohttp.WSMsgType.BINARY:
            return None
        key, _, size = protocol.HEADER.unpack_from(message.data)
        pending[key] = pending.get(key, b"") + message.data[protocol.HEADER.size:]
        if len(pending[key]) >= size:
            answer = msgpack.unpackb(pending.pop(key), strict_map_key=False)
            if answer.get("id") == rpc_id:
                return answer
    return None
