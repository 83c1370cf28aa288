"""The readout's worked rows at laptop sizes: every row is seen whole, none cut off at the readout's right edge.

A student at 1366×768 met lesson 13's substituted V row (a fraction whose
denominator, with its numbers put in, is about 640 px wide) cut off in a
541 px readout, with no scroll cue. formulas.js breaks a row too wide for its
box into lines at its operators (each side of an = on its own line), and a
fraction wider than a line has its denominator broken into lines under the
bar. Measured here on the page: each row's formula lies inside its box, and
the box does not scroll. And lesson 14's rows as the page shows them: with the
probe in shadow, each carries the shadow factor S with its 0.
"""

from __future__ import annotations

import pytest
from real_lessons import drawn, lesson_tab, visit

SIZES = [(1366, 768), (1280, 800)]

#: per row: its label, the formula's visible box and its content's extent (the range of its contents)
MEASURE = """() => [...document.querySelectorAll('.phonglab-readout .eq-row')].map((row) => {
  const box = row.querySelector('.math-fit') || row.querySelector('math');
  const math = row.querySelector('math');
  const range = document.createRange();
  range.selectNodeContents(math);
  const content = range.getBoundingClientRect();
  const b = box.getBoundingClientRect();
  const panel = row.closest('.phonglab-readout').getBoundingClientRect();
  return {
    label: (row.querySelector('.eq-label') || {}).textContent,
    text: math.textContent.replace(/\\s+/g, ''),
    lines: math.querySelectorAll('mtr').length,
    // the row's own lines (not those of a fraction's denominator), as text
    texts: [...math.querySelectorAll(':scope > mtable.math-lines > mtr, :scope > mrow > mtable.math-lines > mtr')]
      .map((tr) => tr.textContent.replace(/\\s+/g, '')),
    box: [Math.round(b.left), Math.round(b.right)], content: [Math.round(content.left), Math.round(content.right)],
    panelRight: Math.round(panel.right), scrolls: box.scrollWidth > box.clientWidth + 1,
    scale: box.style ? box.style.getPropertyValue('--math-scale') : '',
  };
})"""


def overflowing(tab) -> list[dict]:
    tab.page.evaluate("() => window.phonglabFitMath && window.phonglabFitMath()")
    tab.page.wait_for_timeout(150)  # the fitting runs in the next animation frame
    rows = tab.page.evaluate(MEASURE)
    assert rows, "no worked rows in the readout"
    return [r for r in rows if r["scrolls"] or r["content"][1] > r["box"][1] + 1 or r["content"][0] < r["box"][0] - 1
            or r["content"][1] > r["panelRight"]]


def sides_mixed(rows: list[dict]) -> list[dict]:
    """Rows broken within a side of an = whose lines also join two sides: "F0+(1−F0)(1−v·h)5=(1.000,0.710,0.290)"
    on one line with the rest of that substitution below reads as if the formula equalled F0."""
    return [r for r in rows if any(t[:1] != "=" for t in r["texts"][1:]) and any("=" in t[1:] for t in r["texts"])]


def apply_experiment(tab, label: str) -> None:
    tab.page.locator(".phonglab-experiment", has_text=label).locator(".phonglab-apply").first.click()
    tab.page.wait_for_timeout(500)
    drawn(tab)


CASES = [("13-physically-based", None), ("13-physically-based", "Gold"), ("14-shadows", None),
         ("05-whole-model", None), ("07-light-sources", None)]


@pytest.mark.parametrize("width, height", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_no_worked_row_is_cut_off_at_laptop_sizes(browser, serve_app, width, height):
    problems = []
    with lesson_tab(browser, serve_app, width, height) as tab:
        for slug, experiment in CASES:
            visit(tab, f"lesson={slug}")
            if experiment:
                apply_experiment(tab, experiment)
            problems += [f"{slug}{' / ' + experiment if experiment else ''}: row {r['label']!r} "
                         f"({r['lines']} lines, scale {r['scale'] or 1}) content x {r['content']} in box x {r['box']}"
                         f"{', scrolls' if r['scrolls'] else ''}: {r['text'][:90]}" for r in overflowing(tab)]
            problems += [f"{slug}{' / ' + experiment if experiment else ''}: row {r['label']!r} joins two sides of "
                         f"an = on a line and breaks a side: {r['texts']}" for r in sides_mixed(tab.page.evaluate(MEASURE))]
    assert not problems, f"at {width}x{height}, worked rows wider than the readout:\n" + "\n".join(problems)


#: the readout's rows as the page shows them (label -> the row's text, spaces dropped)
ROW_TEXTS = """() => Object.fromEntries([...document.querySelectorAll('.phonglab-readout .eq-row')].map((row) =>
  [(row.querySelector('.eq-label') || {}).textContent, row.querySelector('math').textContent.replace(/\\s+/g, '')]))"""


def test_lesson_14s_rows_show_the_shadow_factor_in_the_page(browser, serve_app):
    with lesson_tab(browser, serve_app, 1366, 768) as tab:
        visit(tab, "lesson=14-shadows")
        rows = tab.page.evaluate(ROW_TEXTS)
        # the probe under the ball: the lamp is blocked, n·l = +0.830, S = 0 substituted first
        assert rows.get("model", "").startswith("I=kaIa+Sfkd"), rows
        assert rows.get("diffuse", "").startswith("SfkdId") and "=0·1.000·0.70·1.00·max(0,0.830)=0.000" in rows["diffuse"], rows
        notes = tab.page.locator(".phonglab-readout").inner_text()
        assert "in shadow here (blocked by the ball): S = 0" in notes, notes
