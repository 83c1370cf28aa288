"""Display maths in the lesson column: a little smaller, else in lines broken at operators, else scrolled; never cut off.

Lesson 2 of :data:`phonglab.bench.scenes.LESSONS` has a display formula a little wider than
the text column of a 1280 px window (the diffuse and specular terms with a
spotlight and attenuation) and one far wider (the rendering equation plus a
sum over lights). The checks run at 1280 and 1440 px. A formula is never
typeset below 90 % of its size (``MIN_SCALE`` in formulas.js): past that it is
broken into lines before its top-level operators, and only a piece that is
still too wide scrolls sideways, with a fade where it continues.
"""

from __future__ import annotations

import pytest
from real_lessons import lesson_tab, visit

#: the smallest scale formulas.js gives a formula before it breaks it into lines
MIN_SCALE = 0.9
#: what a continuation line may start with: an operator, or the bracket of a factor
BREAKS = "=≈≤≥<>→+−-±·∘×(["

MEASURE = """() => {
  const column = document.querySelector('.phonglab-text');
  const style = getComputedStyle(column);
  const c = column.getBoundingClientRect();
  const inner = { left: c.left + parseFloat(style.paddingLeft), right: c.right - parseFloat(style.paddingRight) };
  const body = parseFloat(getComputedStyle(document.querySelector('.phonglab-body')).fontSize);
  // the formulas as the server sent them, before formulas.js fitted them
  const sent = new DOMParser().parseFromString(window.trame.state.get('lesson_html'), 'text/html');
  const originals = [...sent.querySelectorAll('.math-block math')].map((m) => m.textContent.replace(/\\s+/g, ''));
  return [...document.querySelectorAll('.phonglab-body .math-block')].map((block, i) => {
    const math = block.querySelector(':scope > math');
    const maths = [math];
    // a formula broken into lines stays one <math>: a table of its lines
    const rows = [...math.querySelectorAll(':scope > mtable.math-lines > mtr')];
    const box = (m) => { const r = document.createRange(); r.selectNodeContents(m); return r.getBoundingClientRect(); };
    const b = block.getBoundingClientRect();
    const scale = parseFloat(block.style.getPropertyValue('--math-scale') || '1');
    const startLeft = Math.min(...maths.map((m) => box(m).left));
    block.scrollLeft = block.scrollWidth;
    const endRight = Math.max(...maths.map((m) => box(m).right));
    const scrolled = block.scrollLeft;
    block.scrollLeft = 0;
    const first = (m) => { let e = m; while (e && e.children.length && !['mo', 'mi', 'mn', 'mtext'].includes(e.localName)) e = e.firstElementChild; return e ? e.textContent.trim() : ''; };
    return {
      block: [b.left, b.right], column: [inner.left, inner.right], scale, lines: Math.max(1, rows.length), count: block.querySelectorAll('math').length,
      fontRatio: Math.min(...maths.map((m) => parseFloat(getComputedStyle(m).fontSize))) / body,
      text: math.textContent.replace(/\\s+/g, ''), original: originals[i],
      starts: rows.slice(1).map(first),
      overflowX: getComputedStyle(block).overflowX, scrollable: block.scrollWidth > block.clientWidth + 1,
      startLeft, endRight, scrolled, fade: block.classList.contains('math-more-right'),
    };
  });
}"""


@pytest.mark.parametrize("width", [1280, 1440])
def test_display_maths_fits_breaks_or_scrolls_within_the_column(app_page, width):
    page = app_page.page
    page.set_viewport_size({"width": width, "height": 800})
    app_page.open_lesson("A spotlight on a floor")
    page.wait_for_function("() => document.querySelectorAll('.phonglab-body .math-block').length === 2")
    page.wait_for_timeout(300)  # formulas.js fits the formulas on the next animation frame
    blocks = page.evaluate(MEASURE)
    assert len(blocks) == 2, blocks
    for i, b in enumerate(blocks):
        where = f"window {width} px, formula {i + 1}: {b}"
        # the block stays inside the column's text area
        assert b["block"][0] >= b["column"][0] - 0.5 and b["block"][1] <= b["column"][1] + 0.5, where
        # nothing hides to the left, and scrolled to its end the formula ends inside the block
        assert b["startLeft"] >= b["block"][0] - 1, where
        assert b["endRight"] <= b["block"][1] + 1, where
        # readable: never below 90 % of its size, nor of the lesson text's
        assert MIN_SCALE - 1e-6 <= b["scale"] <= 1, where
        assert b["fontRatio"] >= MIN_SCALE - 1e-3, where
        # broken or not, the formula is all there, in order; a continuation line starts with its operator
        assert b["text"] == b["original"], where
        assert all(s and s in BREAKS for s in b["starts"]), where
        assert b["count"] == 1, f"one formula, one <math>: {where}"
        if b["scrollable"]:
            # scrolling only once breaking into lines went as far as it could, with a fade where it continues
            assert b["lines"] > 1 and b["overflowX"] == "auto" and b["fade"], where
        else:
            assert not b["fade"], where
    moderate, wide = blocks
    # the first formula fits at both widths; in the narrower column only once scaled down or broken
    assert not moderate["scrollable"], f"the first formula should fit: {moderate}"
    if width == 1280:
        assert moderate["scale"] < 1 or moderate["lines"] > 1, f"the first formula is wider than the 1280 px column, yet whole: {moderate}"
    # the second one is far too wide for one line: it is broken into lines
    assert wide["lines"] > 1, f"the second formula is too wide for one line: {wide}"


#: every inline formula of the lesson text followed by punctuation, in column widths from 220 to 520 px:
#: the punctuation's line and the formula's last piece's line (a line may break before a formula, never
#: between it and the full stop after it)
PUNCTUATION_LINES = r"""() => {
  const body = document.querySelector('.phonglab-body');
  const found = [];
  const mathsOf = () => [...body.querySelectorAll('math:not([display=block])')]
    .filter((m) => !m.closest('.math-block') && !(m.closest('.math-pieces') && m.nextElementSibling));
  for (let width = 220; width <= 520; width += 4) {
    body.style.width = width + 'px';
    for (const math of mathsOf()) {
      const holder = math.closest('.math-pieces') || math;
      const next = holder.nextSibling;
      if (!next || next.nodeType !== Node.TEXT_NODE || !/^[.,;:!?)]/.test(next.data)) continue;
      const range = document.createRange();
      range.setStart(next, 0);
      range.setEnd(next, 1);
      const p = range.getBoundingClientRect(), f = math.getBoundingClientRect();
      const middle = (p.top + p.bottom) / 2;
      if (middle < f.top || middle > f.bottom) {
        found.push({ width, formula: math.textContent.trim(), after: next.data.slice(0, 12),
                     formulaBox: [f.left, f.top, f.bottom], mark: [p.left, p.top, p.bottom] });
      }
    }
  }
  body.style.width = '';
  return { checked: mathsOf().length, broken: found.slice(0, 8), count: found.length };
}"""


@pytest.mark.parametrize("lesson", ["03-diffuse", "07-light-sources", "11-accuracy"])
def test_a_line_never_breaks_between_a_formula_and_the_punctuation_after_it(browser, serve_app, lesson):
    with lesson_tab(browser, serve_app) as tab:
        visit(tab, f"lesson={lesson}")
        tab.page.wait_for_function("() => document.querySelectorAll('.phonglab-body math').length > 0")
        result = tab.page.evaluate(PUNCTUATION_LINES)
    assert result["checked"] > 5, f"lesson {lesson}: too few inline formulas found to check: {result}"
    assert result["count"] == 0, (f"lesson {lesson}: {result['count']} (width, formula) pairs put the punctuation "
                                  f"after a formula on the next line; the first: {result['broken']}")
