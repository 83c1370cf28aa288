"""The lesson page at the window sizes students have, on every lesson of ``lessons/``.

Sizes: the two commonest laptop screens (1280x800, 1366x768), half a laptop
screen beside notes (800x900), a desktop (1920x1080) and a small laptop or a
projector (1024x768, where the text column is narrowest). On each lesson, at
each size:

* the page never scrolls sideways;
* the 3D view is wholly inside the window's width, at a size one can work with;
* no box that holds text cuts its text off (a box may scroll its content
  sideways only when it shows that it does: a scrollbar or a fade; a formula
  only when the page's fitting could neither scale nor break it to fit);
* every formula is typeset at 90 % of the lesson text's size or more;
* the colour legend of the view does not sit under the view's buttons.

One tab serves the whole file: each lesson is opened once by its address
(``?lesson=<slug>``), and the window is resized around it. Set
``PHONGLAB_LAYOUT_SHOTS`` to a folder to save a screenshot of each case.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from phonglab.bench.ui import log_tail

LESSONS = Path(__file__).resolve().parents[2] / "lessons"
SLUGS = sorted(p.stem for p in LESSONS.glob("*.md") if p.stem[:2].isdigit())
SIZES = [(1280, 800), (1366, 768), (800, 900), (1920, 1080), (1024, 768)]
#: the laptop sizes (and a desktop's) where the view's captions and notices are checked
LAPTOP_SIZES = [(1366, 768), (1280, 800), (1920, 1080)]
#: formulas are at least this fraction of the lesson text's font size
MIN_FORMULA = 0.9
#: the smallest scale formulas.js gives a formula before it breaks it into lines (its MIN_SCALE)
FIT_SCALE = 0.9

#: boxes that hold text, by what they are (a CSS selector each)
TEXT_BOXES = {
    "readout row": ".phonglab-term, .phonglab-dot, .phonglab-dot-term, .phonglab-light-name, .phonglab-readout-head, "
                   ".phonglab-term-wrong",
    "substituted equation": ".phonglab-equation, .phonglab-eq-head, .eq-row, .eq-row .math-fit",
    "lesson list title": ".phonglab-lesson-item .v-list-item-title",
    "notice": ".phonglab-notice, .phonglab-notice .v-alert__content",
    "formula": ".math-block, .math-fit",
    "control": ".phonglab-control-head, .phonglab-color-row, .phonglab-control .v-label, .phonglab-subsection",
    "planner row": ".phonglab-plan-row",
    "view tool": ".phonglab-chip, .phonglab-tools .v-btn__content, .phonglab-hint",
    "lesson text": ".phonglab-h1, .phonglab-goal, .phonglab-body > *, .phonglab-experiment",
    "accuracy figure": ".phonglab-accuracy-number, .phonglab-accuracy-figure figcaption",
    "bar button": ".phonglab-bar .v-btn__content",
}

#: every problem of the page as it is now, as text (lesson and size are added by the test)
MEASURE = """(boxes) => {
  const problems = [];
  const vw = document.documentElement.clientWidth;
  const name = (e) => {
    const cls = typeof e.className === 'string' ? e.className : (e.getAttribute('class') || '');
    return e.tagName.toLowerCase() + (cls ? '.' + cls.trim().split(/\\s+/).join('.') : '');
  };
  const start = (e) => JSON.stringify((e.textContent || '').replace(/\\s+/g, ' ').trim().slice(0, 50));
  const shown = (e) => { const r = e.getBoundingClientRect(); return r.width > 0 && r.height > 0 && getComputedStyle(e).visibility !== 'hidden'; };
  const inDrawer = (e) => !!e.closest('.phonglab-drawer');
  // 1. no sideways scrolling
  const root = document.scrollingElement;
  if (root.scrollWidth > root.clientWidth) problems.push(`the page scrolls sideways: scrollWidth ${root.scrollWidth} > clientWidth ${root.clientWidth}`);
  // 2. the 3D view: inside the window's width, of a workable size
  const view = document.querySelector('.phonglab-view');
  if (!view) problems.push('no 3D view on the page');
  else {
    const r = view.getBoundingClientRect();
    const need = Math.min(320, 0.9 * vw);
    if (r.left < -0.5 || r.right > vw + 0.5) problems.push(`the 3D view is not wholly inside the window: left ${r.left.toFixed(0)}, right ${r.right.toFixed(0)}, window ${vw}`);
    if (r.width < need || r.height < 240) problems.push(`the 3D view is too small: ${r.width.toFixed(0)}x${r.height.toFixed(0)} px (need ${need.toFixed(0)}x240)`);
    if (r.height > window.innerHeight) problems.push(`the 3D view is taller than the window: ${r.height.toFixed(0)} > ${window.innerHeight}`);
    const canvas = view.querySelector('canvas');
    if (canvas) {
      const c = canvas.getBoundingClientRect();
      if (c.left < r.left - 1 || c.right > r.right + 1 || c.top < r.top - 1 || c.bottom > r.bottom + 1)
        problems.push(`the view's canvas sticks out of the view: canvas ${c.left.toFixed(0)}..${c.right.toFixed(0)} x ${c.top.toFixed(0)}..${c.bottom.toFixed(0)}, view ${r.left.toFixed(0)}..${r.right.toFixed(0)} x ${r.top.toFixed(0)}..${r.bottom.toFixed(0)}`);
    }
  }
  // 3. boxes that cut their text: content wider than the box, unless the box visibly scrolls
  for (const [what, selector] of Object.entries(boxes)) {
    for (const e of document.querySelectorAll(selector)) {
      if (!shown(e) && !inDrawer(e)) continue;
      const s = getComputedStyle(e);
      if (s.display.startsWith('inline') && !s.display.includes('block') && !s.display.includes('flex') && !s.display.includes('grid')) continue;
      if (e.scrollWidth > e.clientWidth + 1) {
        const scrolls = s.overflowX === 'auto' || s.overflowX === 'scroll';
        const bar = e.offsetHeight - e.clientHeight - parseFloat(s.borderTopWidth) - parseFloat(s.borderBottomWidth) > 0;
        const fade = e.classList.contains('math-more-right') || e.classList.contains('math-more-left');
        if (!(scrolls && (bar || fade)))
          problems.push(`${what} cuts its text: ${name(e)} ${start(e)}: scrollWidth ${e.scrollWidth} > clientWidth ${e.clientWidth} (overflow-x ${s.overflowX})`);
        else if (e.matches('.math-block, .math-fit') && !e.querySelector('mtable.math-lines')) {
          // a formula may scroll only when the fitting (formulas.js) could not fit it: a formula left
          // whole that would fit at the fitting's smallest scale was measured wrong, and its end is cut
          const scale = e.style.getPropertyValue('--math-scale');
          e.style.setProperty('--math-scale', String(%FIT%));
          const small = e.scrollWidth;
          if (scale) e.style.setProperty('--math-scale', scale); else e.style.removeProperty('--math-scale');
          if (small <= e.clientWidth + 1)
            problems.push(`${what} cuts its text although it fits at ${%FIT%} of its size: ${name(e)} ${start(e)}: scrollWidth ${e.scrollWidth} > clientWidth ${e.clientWidth} at scale ${scale || 1}, ${small} at ${%FIT%}`);
        }
      }
      if (!inDrawer(e)) {
        const r = e.getBoundingClientRect();
        if (r.right > vw + 1 || r.left < -1) problems.push(`${what} is outside the window: ${name(e)} ${start(e)}: ${r.left.toFixed(0)}..${r.right.toFixed(0)}, window ${vw}`);
      }
    }
  }
  // 4. formulas at 90 % of the lesson text's size or more
  const text = document.querySelector('.phonglab-body') || document.body;
  const body = parseFloat(getComputedStyle(text).fontSize);
  for (const m of document.querySelectorAll('math')) {
    if (m.parentElement.closest('math') || inDrawer(m) || !shown(m)) continue;
    const size = parseFloat(getComputedStyle(m).fontSize);
    if (size < %MIN% * body - 0.01)
      problems.push(`a formula is small: ${name(m.parentElement)} > math ${start(m)}: ${size.toFixed(1)} px < ${%MIN%} x ${body.toFixed(1)} px of the lesson text`);
  }
  // 5. the legend's chips are not under the view's buttons
  const tools = [...document.querySelectorAll('.phonglab-tools .v-btn')].filter(shown).map((b) => [b, b.getBoundingClientRect()]);
  for (const chip of document.querySelectorAll('.phonglab-chip')) {
    const c = chip.getBoundingClientRect();
    for (const [b, r] of tools)
      if (c.left < r.right && r.left < c.right && c.top < r.bottom && r.top < c.bottom)
        problems.push(`legend chip ${start(chip)} sits under the view's button ${start(b)}`);
  }
  return problems;
}""".replace("%MIN%", str(MIN_FORMULA)).replace("%FIT%", str(FIT_SCALE))

#: three animation frames: the layout, the formulas' fitting (formulas.js) and their re-layout are done
FRAMES = "() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => requestAnimationFrame(done))))"


@pytest.fixture(scope="module")
def lessons_server(serve_app):
    """``phonglab serve lessons/`` (the real lessons, not the test ones), addressed by its index.html."""
    served = serve_app(LESSONS)
    return {**served, "url": served["url"] + "index.html"}


@pytest.fixture(scope="module")
def tab(browser, lessons_server):
    """One tab for the whole file; fails on JavaScript errors."""
    context = browser.new_context(viewport={"width": SIZES[0][0], "height": SIZES[0][1]})
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        yield page
        assert not errors, f"JavaScript errors on the page: {errors}"
        assert lessons_server["process"].poll() is None, f"the server died:\n{log_tail(lessons_server['log'])}"
    finally:
        context.close()


def open_by_address(page, server, slug):
    """Open ``?lesson=<slug>`` and wait until the page shows that lesson with its readout or panel."""
    query = f"?lesson={slug}"
    shown = page.evaluate("() => window.trame && window.trame.state && window.trame.state.get('url_query')") \
        if page.url.startswith(server["url"]) else None
    # an address for the lesson already open applies its settings over the scene on screen (the page sends
    # its address once, as it loads): a tab left with that lesson's experiment applied loads the page again
    same_lesson = isinstance(shown, str) and shown != query and (shown + "&").startswith(query + "&")
    if page.url.startswith(server["url"]) and not same_lesson:
        # the tab is on the app already: the address changes as a pasted link would change it, without
        # reloading the page (a reload builds a new session: many seconds on a loaded machine)
        page.evaluate("(q) => { history.replaceState(null, '', location.pathname + q); trame.state.set('url_request', q); }", query)
    else:
        page.goto(server["url"] + query)
    page.wait_for_function(
        """(q) => {
          const s = window.trame && window.trame.state;
          if (!s || s.get('url_query') !== q || !document.querySelector('.phonglab-view canvas')) return false;
          if (s.get('lesson_errors').length) return true;
          return !!document.querySelector('.phonglab-h1') && !!(document.querySelector('.phonglab-readout .eq-row, .phonglab-readout math') || s.get('accuracy'));
        }""",
        arg=query, timeout=60_000,
    )


@pytest.mark.parametrize("slug", SLUGS)
def test_lesson_fits_every_window_size(tab, lessons_server, slug):
    assert len(SLUGS) >= 12, f"lessons/ should hold the 12 lessons, found {SLUGS}"
    open_by_address(tab, lessons_server, slug)
    shots = os.environ.get("PHONGLAB_LAYOUT_SHOTS")
    found = []
    for width, height in SIZES:
        tab.set_viewport_size({"width": width, "height": height})
        tab.evaluate(FRAMES)
        tab.wait_for_timeout(100)  # the view's size observer and the formulas' fitting settle
        tab.evaluate(FRAMES)
        if shots:
            tab.screenshot(path=str(Path(shots) / f"{width}x{height}-{slug}.png"))
        problems = tab.evaluate(MEASURE, TEXT_BOXES)
        if problems:  # measured again once the server's last update (a readout, say) is fitted too
            tab.wait_for_timeout(500)
            tab.evaluate(FRAMES)
            problems = tab.evaluate(MEASURE, TEXT_BOXES)
        found += [f"{slug} at {width}x{height}: {p}" for p in problems]
    assert not found, f"{len(found)} layout problems:\n" + "\n".join(found)


def test_notice_does_not_push_the_controls_down(tab, lessons_server):
    """Applying an experiment shows a notice over the page; the controls stay where they were."""
    tab.set_viewport_size({"width": 1366, "height": 768})
    open_by_address(tab, lessons_server, "04-specular")
    controls = ".phonglab-side .phonglab-controls"
    tab.wait_for_selector(controls)
    before = tab.locator(controls).bounding_box()
    tab.locator(".phonglab-apply").first.click()
    tab.wait_for_selector(".phonglab-notice", timeout=20_000)
    tab.evaluate(FRAMES)
    after = tab.locator(controls).bounding_box()
    notice = tab.locator(".phonglab-notice").bounding_box()
    text = tab.locator(".phonglab-notice").inner_text()
    assert abs(after["y"] - before["y"]) < 1, f"the notice {text!r} moved the controls from y={before['y']} to y={after['y']}"
    assert notice["x"] >= 0 and notice["x"] + notice["width"] <= 1366, f"the notice {text!r} is outside the window: {notice}"
    found = tab.evaluate(MEASURE, {"notice": TEXT_BOXES["notice"]})
    assert not found, f"04-specular at 1366x768 with the notice {text!r}:\n" + "\n".join(found)
    problems = notice_at_the_foot_problems(tab)
    assert not problems, "04-specular at 1366x768:\n" + "\n".join(problems)


#: the boxes (left, top, right, bottom) of the notice, the view, and what the notice must leave in sight
FOOT_BOXES_JS = """() => {
  const box = (e) => { const b = e.getBoundingClientRect(); return [b.left, b.top, b.right, b.bottom].map(Math.round); };
  const shown = (e) => { const b = e.getBoundingClientRect(); return b.width > 0 && b.height > 0; };
  const notice = document.querySelector('.phonglab-notice');
  const keep = {};
  for (const [what, selector] of [['hint line', '.phonglab-hint'], ['mistake banner', '.phonglab-wrong-banner'],
                                   ['legend', '.phonglab-legend'], ['view tools', '.phonglab-tools']])
    for (const e of document.querySelectorAll(selector)) if (shown(e)) keep[what] = box(e);
  return { text: notice && notice.innerText.trim(), notice: notice && box(notice),
           view: box(document.querySelector('.phonglab-view')), keep };
}"""


def notice_at_the_foot_problems(tab) -> list[str]:
    """What is wrong with where the notice showing now lies: over the view's hint line, the mistake's banner or
    the legend; outside the view; or more than 12 px above the hint line (over the object the experiment changed)."""
    seen = tab.evaluate(FOOT_BOXES_JS)
    text, notice, view = seen["text"], seen["notice"], seen["view"]
    if notice is None:
        return ["no notice showing"]
    problems = []
    for what, (x0, y0, x1, y1) in seen["keep"].items():
        if notice[0] < x1 and x0 < notice[2] and notice[1] < y1 and y0 < notice[3]:
            problems.append(f"the notice {text!r} {notice} covers the {what} {[x0, y0, x1, y1]} "
                            "(left, top, right, bottom)")
    if notice[0] < view[0] - 1 or notice[2] > view[2] + 1 or notice[1] < view[1] - 1 or notice[3] > view[3] + 1:
        problems.append(f"the notice {text!r} {notice} is not inside the view {view}")
    below = seen["keep"].get("hint line") or seen["keep"].get("mistake banner")
    lowest = below[1] if below else view[3]
    if lowest - notice[3] > 12:
        problems.append(f"the notice {text!r} {notice} ends {lowest - notice[3]} px above the view's foot line "
                        f"(at y = {lowest}): higher up it covers the object the experiment changed")
    return problems


@pytest.mark.parametrize("width, height", LAPTOP_SIZES)
def test_an_applied_experiments_notice_leaves_the_hint_line_in_sight(tab, lessons_server, width, height):
    """"Applied: …" lay over the view's hint line for the 4 s it shows, at every laptop size."""
    tab.set_viewport_size({"width": width, "height": height})
    open_by_address(tab, lessons_server, "04-specular")
    # an earlier notice first goes: the measure is of the one this click brings
    tab.evaluate("() => window.trame.state.set('notice', null)")
    tab.wait_for_selector(".phonglab-notice", state="detached", timeout=20_000)
    tab.locator(".phonglab-apply").first.click()
    tab.wait_for_selector(".phonglab-notice", timeout=20_000)
    tab.evaluate(FRAMES)
    problems = notice_at_the_foot_problems(tab)
    assert not problems, f"04-specular at {width}x{height}, after its first experiment's Apply:\n" + "\n".join(problems)


#: every animation frame: an image over the view without a picture (a broken image), and the number of frames
WATCH_PICTURE_JS = """() => {
  const seen = (window.__pictureWatch = { frames: 0, broken: [] });
  const frame = () => {
    seen.frames += 1;
    const img = document.querySelector('.phonglab-pixel img');
    if (img && !img.getAttribute('src')) seen.broken.push(seen.frames);
    if (!seen.stop) requestAnimationFrame(frame);
  };
  requestAnimationFrame(frame);
}"""
#: the box of a "picture on its way" note, made for the measurement if none is showing, and the notice's
UPDATING_AND_NOTICE_JS = """() => {
  const box = (e) => { const b = e.getBoundingClientRect(); return [b.left, b.top, b.right, b.bottom]; };
  let note = document.querySelector('.phonglab-pixel-updating'), made = false;
  if (!note) {
    note = document.createElement('div');
    note.className = 'phonglab-pixel-updating';
    note.textContent = 'updating the picture…';
    document.querySelector('.phonglab-pixel').appendChild(note);
    made = true;
  }
  const boxes = { updating: box(note), notice: box(document.querySelector('.phonglab-notice')) };
  if (made) note.remove();
  return boxes;
}"""


def test_turning_per_pixel_shading_on_shows_no_broken_image_and_both_notes(tab, lessons_server):
    """Lesson 8's "Per pixel": until the first picture came, the view showed a broken image with its alt text,
    and the "Applied" notice lay over the "updating the picture…" note."""
    tab.set_viewport_size({"width": 1366, "height": 768})
    open_by_address(tab, lessons_server, "08-interpolation")
    assert not tab.evaluate("() => window.trame.state.get('pixel_mode')"), "lesson 8 should open in Gouraud shading"
    tab.evaluate(WATCH_PICTURE_JS)
    tab.locator(".phonglab-experiment", has_text="Interpolate the normals").locator(".phonglab-apply").click()
    tab.wait_for_selector(".phonglab-notice", timeout=20_000)
    tab.wait_for_function("() => { const s = window.trame.state; return s.get('pixel_mode') && s.get('pixel_src')"
                          " && !s.get('pixel_pending'); }", timeout=60_000)
    boxes = tab.evaluate(UPDATING_AND_NOTICE_JS)
    seen = tab.evaluate("() => { window.__pictureWatch.stop = true; return window.__pictureWatch; }")
    assert seen["frames"] > 0 and not seen["broken"], (
        f"an image without a picture over the view in {len(seen['broken'])} of {seen['frames']} frames")
    a, b = boxes["updating"], boxes["notice"]
    apart = a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]
    assert apart, f"the notice {b} covers the note that a picture is on its way {a} (left, top, right, bottom)"


def test_an_experiment_applied_in_one_column_brings_the_view_into_sight(tab, lessons_server):
    """At 800x900 the text comes last, far below the view: Apply there changed a view out of sight."""
    tab.set_viewport_size({"width": 800, "height": 900})
    # (not lesson 4: the tab may be there already, and the same address asked twice is no change of state)
    open_by_address(tab, lessons_server, "07-light-sources")
    apply = tab.locator(".phonglab-apply").first
    apply.scroll_into_view_if_needed()
    seen = "(s) => { const b = document.querySelector(s).getBoundingClientRect(); return b.bottom > 80 && b.top < innerHeight - 80; }"
    assert not tab.evaluate(seen, ".phonglab-view"), "the view should be out of sight from the experiment"
    apply.click()
    tab.wait_for_selector(".phonglab-notice", timeout=20_000)
    tab.wait_for_function(seen, arg=".phonglab-view", timeout=30_000)
    view = tab.locator(".phonglab-view").bounding_box()
    assert view["y"] >= 40, f"the view is under the page's bar: {view}"
    # the view's own bar (legend, terms, probe or light) too: it sat under the page's bar, only slivers shown
    tools, bar = tab.locator(".phonglab-viewbar").bounding_box(), tab.locator(".phonglab-bar").bounding_box()
    assert tools["y"] >= bar["y"] + bar["height"] - 1, f"the view's tools are under the page's bar: {tools}, bar {bar}"
    assert tab.evaluate(seen, ".phonglab-notice"), "the notice over the view's foot should be in sight"


def test_the_readouts_colour_dots_stay_round_beside_long_numbers(tab, lessons_server):
    """Lesson 13's lake gives rows of 92.217: their dots were squeezed into slivers by the numbers."""
    tab.set_viewport_size({"width": 1280, "height": 800})
    open_by_address(tab, lessons_server, "13-physically-based")
    tab.locator(".phonglab-experiment", has_text="Lake at sunset").locator(".phonglab-apply").click()
    tab.wait_for_function("() => [...document.querySelectorAll('.phonglab-readout')].some(e => e.innerText.includes('92.'))",
                          timeout=30_000)
    dots = tab.evaluate("""() => [...document.querySelectorAll('.phonglab-readout .phonglab-swatch')]
        .map(e => { const b = e.getBoundingClientRect(); return [b.width, b.height, e.parentElement.innerText.slice(0, 60)]; })
        .filter(([w, h]) => w + h > 0)""")
    assert dots, "no colour dots in the readout"
    squeezed = [d for d in dots if abs(d[0] - d[1]) > 1]
    assert not squeezed, f"dots not round (width, height, row): {squeezed}"



@pytest.mark.parametrize("slug", ["01-light-and-surfaces", "13-physically-based"])
def test_at_1280x800_the_page_fits_the_window_and_the_view_knows_its_size(tab, lessons_server, slug):
    """The observer of the view's size sat below the view, as tall as it: the whole page scrolled by 18-45 px."""
    tab.set_viewport_size({"width": 1280, "height": 800})
    open_by_address(tab, lessons_server, slug)
    tall = tab.evaluate("() => [document.scrollingElement.scrollHeight, innerHeight]")
    assert tall[0] <= tall[1], f"{slug}: the page is {tall[0]} px tall in a window of {tall[1]}"
    box = tab.locator(".phonglab-view").bounding_box()
    tab.wait_for_function("(b) => { const s = window.trame.state.get('view_size'); const z = s && (s.size || s);"
                          " return z && Math.abs(z.width - b.width) <= 1 && Math.abs(z.height - b.height) <= 1; }",
                          arg=box, timeout=30_000)


@pytest.mark.parametrize("slug", ["04-specular", "06-blinn-phong", "13-physically-based"])
def test_on_a_laptop_the_view_bar_is_one_row_and_its_buttons_keep_their_names(tab, lessons_server, slug):
    """At 1366x768 and 1280x800 "Compare models" wrapped the bar onto two rows: 28 px less view on a short screen.

    Where the words do not fit, a button shows its icon alone; it keeps its name (aria-label) and a tooltip.
    """
    open_by_address(tab, lessons_server, slug)
    found = []
    for width, height in [(1366, 768), (1280, 800), (1920, 1080)]:
        tab.set_viewport_size({"width": width, "height": height})
        tab.evaluate(FRAMES)
        bar = tab.evaluate("""() => {
          const box = (s) => { const e = document.querySelector(s); return e && e.getBoundingClientRect(); };
          const legend = box('.phonglab-legend'), tools = box('.phonglab-tools');
          const buttons = [...document.querySelectorAll('.phonglab-tools .v-btn')].map(b => ({
            words: (b.querySelector('.v-btn__content') || b).innerText.trim(),
            shown: !!(b.querySelector('.v-btn__content') || b).getClientRects().length,
            name: b.getAttribute('aria-label') || (b.querySelector('.v-btn__content') || b).innerText.trim(),
            title: b.getAttribute('title') || '' }));
          return {oneRow: tools.top < legend.bottom && legend.top < tools.bottom,
                  rows: [Math.round(legend.top), Math.round(tools.top)], buttons};
        }""")
        if not bar["oneRow"]:
            found.append(f"{width}x{height}: legend and tools on two rows (tops {bar['rows']})")
        for b in bar["buttons"]:
            if not b["name"]:
                found.append(f"{width}x{height}: a button without a name: {b}")
            if not b["shown"] and not b["title"]:
                found.append(f"{width}x{height}: {b['name']!r} shows its icon alone but has no tooltip")
        if width == 1920:  # room for every word
            hidden = [b["name"] for b in bar["buttons"] if not b["shown"]]
            if hidden:
                found.append(f"{width}x{height}: words hidden though there is room: {hidden}")
    assert not found, f"{slug}:\n" + "\n".join(found)

#: the least height of a caption's letters as displayed (its font size, CSS px)
MIN_CAPTION_PX = 11
#: how each compare panel's caption begins (render/captions.py, model_label)
CAPTION_STARTS = ("Phong: α = ", "Cook–Torrance: roughness ")
#: each caption's text as the page shows it (its font size and box), found by its words in the compare view,
#: and the pictures' sizes there: natural and displayed
CAPTIONS_JS = """(starts) => {
  const panel = document.querySelector('.phonglab-compare');
  const walker = document.createTreeWalker(panel, NodeFilter.SHOW_TEXT);
  const found = {};
  for (let node = walker.nextNode(); node; node = walker.nextNode()) {
    const start = starts.find((s) => node.textContent.trim().startsWith(s));
    if (!start || found[start]) continue;
    const range = document.createRange();
    range.selectNodeContents(node);
    const r = range.getBoundingClientRect();
    found[start] = { text: node.textContent.trim(), fontPx: parseFloat(getComputedStyle(node.parentElement).fontSize),
                     box: [r.left, r.top, r.right, r.bottom].map(Math.round) };
  }
  const p = panel.getBoundingClientRect();
  const pictures = [...panel.querySelectorAll('img')].map((i) => {
    const b = i.getBoundingClientRect();
    return { natural: [i.naturalWidth, i.naturalHeight], shown: [Math.round(b.width), Math.round(b.height)] };
  });
  return { captions: found, panel: [p.left, p.top, p.right, p.bottom].map(Math.round), pictures };
}"""


@pytest.mark.parametrize("slug", ["06-blinn-phong", "13-physically-based"])
def test_compare_captions_are_readable_at_laptop_and_desktop_sizes(tab, lessons_server, slug):
    """The compare view's captions (the model and its lobe's parameters) were drawn into its picture, which the
    page scaled down: about 7 px tall at 1366x768. They are page text at the page's own size. (Lesson 13's
    Cook–Torrance caption, the longer, wraps onto two lines at 1280x800.)"""
    open_by_address(tab, lessons_server, slug)
    found = []
    try:
        tab.locator(".phonglab-compare-toggle").click()
        for width, height in LAPTOP_SIZES:
            tab.set_viewport_size({"width": width, "height": height})
            tab.evaluate(FRAMES)
            # pictures shown (the last size's, maybe, while this size's are made: the captions' size is the
            # page's either way, and the pictures are fitted into their boxes)
            tab.wait_for_function("() => { const c = window.trame.state.get('compare_png'); "
                                  "return c && c.status === 'ready'; }", timeout=120_000)
            tab.wait_for_function("() => [...document.querySelectorAll('.phonglab-compare img')]"
                                  ".every((i) => i.complete && i.naturalWidth > 0)", timeout=30_000)
            tab.evaluate(FRAMES)
            seen = tab.evaluate(CAPTIONS_JS, list(CAPTION_STARTS))
            where = f"{slug} at {width}x{height}"
            for start in CAPTION_STARTS:
                caption = seen["captions"].get(start)
                if caption is None:
                    found.append(f"{where}: no caption {start!r}… as page text in the compare view; its pictures "
                                 f"(natural -> displayed px): {seen['pictures']}")
                    continue
                if caption["fontPx"] < MIN_CAPTION_PX:
                    found.append(f"{where}: caption {caption['text']!r} is {caption['fontPx']:.1f} px tall "
                                 f"(font size), under {MIN_CAPTION_PX} px")
                x0, y0, x1, y1 = caption["box"]
                px0, py0, px1, py1 = seen["panel"]
                if x0 < px0 - 1 or x1 > px1 + 1 or y0 < py0 - 1 or y1 > py1 + 1:
                    found.append(f"{where}: caption {caption['text']!r} at {caption['box']} is outside the compare "
                                 f"view {seen['panel']}")
            small = [p for p in seen["pictures"] if min(p["shown"]) < 120]
            if small:
                found.append(f"{where}: a picture is shown smaller than 120 px: {seen['pictures']}")
            # side by side, both models at one scale (a caption on two lines once shrank its picture)
            scales = [min(p["shown"][0] / p["natural"][0], p["shown"][1] / p["natural"][1]) for p in seen["pictures"]]
            if len(scales) > 1 and max(scales) - min(scales) > 0.01:
                found.append(f"{where}: the pictures are shown at different scales {[round(x, 3) for x in scales]}: "
                             f"{seen['pictures']}")
    finally:
        tab.evaluate("() => window.trame.state.set('view__compare', false)")
        tab.wait_for_selector(".phonglab-compare", state="detached", timeout=30_000)
    assert not found, "compare view captions:\n" + "\n".join(found)
