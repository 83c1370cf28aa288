"""The page in a classroom: figures exported from the page arrive as downloads in the student's browser."""

from __future__ import annotations

import io
import re

from PIL import Image


def _saved_png(download, folder):
    path = folder / download.suggested_filename
    download.save_as(path)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", (download.suggested_filename, data[:16])
    with Image.open(io.BytesIO(data)) as img:
        img.load()
        return img.size


def test_export_arrives_as_a_browser_download(app_page, tmp_path):
    page = app_page.page
    with page.expect_download(timeout=120_000) as info:
        page.locator(".phonglab-export").click()
    download = info.value
    assert re.fullmatch(r"lesson-01-\d{8}-\d{6}\.png", download.suggested_filename), download.suggested_filename
    assert _saved_png(download, tmp_path) == (1200, 900)
    # the per-term figure, from the menu beside the button
    page.locator(".phonglab-export-more").click()
    with page.expect_download(timeout=120_000) as info:
        page.locator(".phonglab-export-terms").click()
    download = info.value
    assert re.fullmatch(r"lesson-01-terms-\d{8}-\d{6}\.png", download.suggested_filename), download.suggested_filename
    assert _saved_png(download, tmp_path) == (1200, 900)
