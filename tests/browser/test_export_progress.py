"""While the page's export is being made, the bar says "Preparing…" and how far it is; then the download comes."""

from __future__ import annotations

import re

#: records every text the export's progress line shows, from the page's first script on
RECORD_PROGRESS = """
(() => {
  window.__exportProgress = [];
  new MutationObserver(() => {
    for (const e of document.querySelectorAll('.phonglab-export-progress')) {
      const text = e.textContent.trim();
      const seen = window.__exportProgress;
      if (text && seen[seen.length - 1] !== text) seen.push(text);
    }
  }).observe(document, { subtree: true, childList: true, characterData: true });
})();
"""


def test_an_export_says_preparing_with_its_progress_until_it_downloads(app_page):
    page = app_page.page
    page.evaluate(RECORD_PROGRESS)
    page.locator(".phonglab-export-more").click()
    with page.expect_download(timeout=180_000) as info:
        page.locator(".phonglab-export-terms").click()
    assert info.value.suggested_filename.endswith(".png")
    seen = page.evaluate("() => window.__exportProgress")
    print("progress shown:", seen)
    assert seen, "no progress was shown while the export was made"
    pattern = (r"Preparing… (starting the figure workers \(\d of \d ready\)|waiting for a free figure worker"
               r"|rendering|view \d of 4), \d+ s")
    assert all(re.fullmatch(pattern, text) for text in seen), seen
    page.wait_for_function("() => !document.querySelector('.phonglab-export-progress')", timeout=30_000)
