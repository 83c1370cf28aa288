"""``phonglab serve --export-dir DIR`` removes what a killed export left in DIR when it starts, before any tab exports."""

from __future__ import annotations

import os
import time

from app_support import serving

from phonglab.bench.ui import log_tail
from phonglab.render._files import STALE_AFTER, temp_name

LESSON = """+++
title = "A sphere"

[geometry]
kind = "sphere"
resolution = 12

[[lights]]
type = "point"
position = [2, 2, 3]
+++

# A sphere
"""


def test_serve_start_removes_stale_export_temporaries(tmp_path):
    (tmp_path / "01-sphere.md").write_text(LESSON, encoding="utf-8")
    exports = tmp_path / "exports"
    exports.mkdir()
    figure = exports / "lesson-01-20260101-120000.png"
    stale = exports / temp_name(figure)  # what kill -9 during a write leaves: empty, hidden
    fresh = exports / temp_name(figure)  # a write in progress elsewhere right now
    kept = [figure, fresh, exports / ".notes.txt"]
    for path in [stale, *kept]:
        path.write_bytes(b"" if path != figure else b"\x89PNG")
    long_ago = time.time() - 10 * STALE_AFTER
    os.utime(stale, (long_ago, long_ago))
    os.utime(figure, (long_ago, long_ago))

    log = tmp_path / "serve.log"
    with serving(tmp_path, "--export-dir", str(exports), log_path=log):
        left = sorted(p.name for p in exports.iterdir())
        shown = f"left in the export folder: {left}\nserver log:\n{log_tail(log)}"
        assert not stale.exists(), f"the stale temporary {stale.name} is still there at start\n{shown}"
        assert all(p.exists() for p in kept), f"a file that is not a stale temporary was removed\n{shown}"
        assert f"removed 1 temporary file(s) an interrupted export left in {exports}" in log_tail(log), shown
