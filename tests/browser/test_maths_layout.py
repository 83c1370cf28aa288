"""Display maths in the lesson column: scaled down to fit, or scrolled within the column; never cut off.

Lesson 2 of :data:`phonglab.bench.scenes.LESSONS` has a display formula a little wider than
the text column of a 1280 px window (the diffuse and specular terms with a
spotlight and attenuation) and one far wider (the rendering equation plus a
sum over lights). The checks run at 1280 and 1440 px.
"""

from __future__ import annotations

import pytest

#: the smallest scale phonglab.js gives a formula before it scrolls instead
MIN_SCALE = 0.8

MEASURE = """() => {
  const column = document.querySelector('.phonglab-text');
  const style = getComputedStyle(column);
  const c = column.getBoundingClientRect();
  const inner = { left: c.left + parseFloat(style.paddingLeft), right: c.right - parseFloat(style.paddingRight) };
  return [...document.querySelectorAll('.phonglab-body .math-block')].map((block) => {
    const math = block.querySelector(':scope > math');
    const content = () => { const r = document.createRange(); r.selectNodeContents(math); return r.getBoundingClientRect(); };
    const b = block.getBoundingClientRect();
    const scale = parseFloat(block.style.getPropertyValue('--math-scale') || '1');
    const start = content();
    block.scrollLeft = block.scrollWidth;
    const end = content();
    const scrolled = block.scrollLeft;
    block.scrollLeft = 0;
    return {
      block: [b.left, b.right], column: [inner.left, inner.right], scale,
      overflowX: getComputedStyle(block).overflowX, scrollable: block.scrollWidth > block.clientWidth + 1,
      startLeft: start.left, endRight: end.right, scrolled, fade: block.classList.contains('math-more-right'),
    };
  });
}"""


@pytest.mark.parametrize("width", [1280, 1440])
def test_display_maths_fits_or_scrolls_within_the_column(app_page, width):
    page = app_page.page
    page.set_viewport_size({"width": width, "height": 800})
    app_page.open_lesson("A spotlight on a floor")
    page.wait_for_function("() => document.querySelectorAll('.phonglab-body .math-block').length === 2")
    page.wait_for_timeout(300)  # phonglab.js fits the formulas on the next animation frame
    blocks = page.evaluate(MEASURE)
    assert len(blocks) == 2, blocks
    for i, b in enumerate(blocks):
        where = f"window {width} px, formula {i + 1}: {b}"
        # the block stays inside the column's text area
        assert b["block"][0] >= b["column"][0] - 0.5 and b["block"][1] <= b["column"][1] + 0.5, where
        # nothing hides to the left, and scrolled to its end the formula ends inside the block
        assert b["startLeft"] >= b["block"][0] - 1, where
        assert b["endRight"] <= b["block"][1] + 1, where
        assert MIN_SCALE - 1e-6 <= b["scale"] <= 1, where
        if b["scrollable"]:
            # scrolling only once scaling went as far as allowed, with a fade where it continues
            assert b["scale"] == pytest.approx(MIN_SCALE) and b["overflowX"] == "auto" and b["fade"], where
        else:
            assert not b["fade"], where
    moderate, wide = blocks
    # the first formula fits at both widths; in the narrower column only once scaled down
    assert not moderate["scrollable"], f"the first formula should fit: {moderate}"
    if width == 1280:
        assert moderate["scale"] < 1, f"the first formula is wider than the 1280 px column, yet not scaled: {moderate}"
    assert wide["scrollable"] and wide["scrolled"] > 0, f"the second formula is too wide to fit: {wide}"
