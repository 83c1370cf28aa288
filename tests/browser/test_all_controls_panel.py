"""The all-controls panel under the lesson's own controls: narrower than they are, and still readable.

Every group of the panel is opened; then for every control in it the label, the
"used by … only" note and the value must lie side by side without covering each
other, and a menu's floating label must show whole (lesson 3 cut its light-type
label to "type (w = 1 point, w = 0 direction…", and "metallic" ran under its note).
"""

from __future__ import annotations

import pytest
from real_lessons import lesson_tab, visit

#: every control of the opened all-controls panel: the overlapping boxes of its head, a cut-off menu label
CHECK_JS = r"""() => {
  const out = { controls: 0, overlaps: [], cut: [] };
  const panel = document.querySelector('.phonglab-all');
  // the text's own extent (a label's text may run past its box)
  const box = (el) => { const r = document.createRange(); r.selectNodeContents(el); return r.getBoundingClientRect(); };
  for (const control of panel.querySelectorAll('.phonglab-control')) {
    out.controls += 1;
    const name = [...control.classList].find((c) => c.startsWith('phonglab-control-') && c !== 'phonglab-control-all');
    const parts = [...control.querySelectorAll('.phonglab-control-head > *, .phonglab-color-row > *')]
      .filter((el) => el.getClientRects().length);
    for (let i = 0; i < parts.length; i++) {
      for (let j = i + 1; j < parts.length; j++) {
        const a = box(parts[i]), b = box(parts[j]);
        const w = Math.min(a.right, b.right) - Math.max(a.left, b.left), h = Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top);
        if (w > 1 && h > 1) out.overlaps.push({ control: name, a: parts[i].textContent.trim(), b: parts[j].textContent.trim() });
      }
    }
    for (const label of control.querySelectorAll('.v-field-label')) {
      if (label.getClientRects().length && label.scrollWidth > label.clientWidth + 1) {
        out.cut.push({ control: name, label: label.textContent.trim(), needs: label.scrollWidth, has: label.clientWidth });
      }
    }
  }
  return out;
}"""


@pytest.mark.parametrize("lesson", ["03-diffuse", "13-physically-based"])
def test_every_control_in_the_all_controls_panel_reads_whole(browser, serve_app, lesson):
    with lesson_tab(browser, serve_app) as tab:
        visit(tab, f"lesson={lesson}")
        page = tab.page
        page.wait_for_selector(".phonglab-all .phonglab-group")
        groups = page.locator(".phonglab-all .phonglab-group > button")
        for i in range(groups.count()):
            groups.nth(i).click()
        page.wait_for_function("() => [...document.querySelectorAll('.phonglab-all .phonglab-group')]"
                               ".every((g) => g.querySelector('.v-expansion-panel-text__wrapper'))")
        page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
        found = page.evaluate(CHECK_JS)
    assert found["controls"] > 10, f"lesson {lesson}: too few controls in the opened panel: {found}"
    assert not found["overlaps"], f"lesson {lesson}: parts of a control's head cover each other: {found['overlaps']}"
    assert not found["cut"], f"lesson {lesson}: a menu's label is cut off: {found['cut']}"
