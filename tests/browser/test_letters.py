"""The letters N, L, R, V, H sit at their own arrow tips, in every lesson, mode and eye.

The page projects the tips with the browser's camera and places each letter about its own tip
(``www/phonglab.js``, ``phonglab-letters``). Here the same projection is made in the page and every
letter drawn is checked against it: within :data:`REACH` pixels of its own tip, and nearer its own tip
than any other arrow's (a reader takes a letter for its nearest tip's). Tips closer together than
:data:`SAME_TIP` are one place, and either letter may be read as either; the letters of arrows whose
tips meet share one label, "N, L, R" (lesson 3), and stand side by side, the outer ones up to half
the label's width further out. About 2 minutes on 2 loaded cores
for all the lessons, one lesson a test.
"""

from __future__ import annotations

import json

import pytest
from real_lessons import LESSONS, drawn, lesson_tab

from phonglab.scene.lessons import catalog

STEMS = [e.path.stem for e in catalog(LESSONS)[0] if e.ok]
#: farthest a letter's centre may be from its tip, in pixels (the third ring of places about it)
REACH = 26.0
#: tips nearer than this (pixels) are one place
SAME_TIP = 3.0

#: every letter drawn: its centre, and its own and the other shown tips (and the arrows' bases) projected
#: with the page's camera
LETTERS_JS = r"""() => {
  const view = window.phonglabView, renderer = view.renderer;
  const canvas = document.querySelector('.phonglab-view canvas');
  const w = canvas.clientWidth, h = canvas.clientHeight, aspect = w / h;
  const screen = (p) => { const d = renderer.worldToNormalizedDisplay(p[0], p[1], p[2], aspect);
    return [canvas.offsetLeft + d[0] * w, canvas.offsetTop + (1 - d[1]) * h]; };
  const tips = {}, bases = {};
  for (const t of (window.trame.state.get('arrow_tips') || [])) {
    if (!t.behind) { tips[t.letter] = screen(t.tip); bases[t.letter] = screen(t.base); }
  }
  const spans = Array.from(document.querySelectorAll('.phonglab-letters > span'))
    .filter((s) => s.parentNode.style.display !== 'none');
  // each label's half width: a letter alone, or the letters of arrows whose tips meet and their joins
  const half = (label) => { const boxes = spans.filter((s) => s.dataset.label === label).map((s) => s.getBoundingClientRect());
    return (Math.max(...boxes.map((b) => b.right)) - Math.min(...boxes.map((b) => b.left))) / 2; };
  return spans.filter((s) => s.classList.contains('phonglab-letter')).map((s) => {
    const r = s.getBoundingClientRect();
    return { letter: s.dataset.letter, at: [parseFloat(s.style.left), parseFloat(s.style.top)], tips, bases,
             label: s.dataset.label, half: half(s.dataset.label), box: [r.left, r.top, r.right, r.bottom] };
  });
}"""


@pytest.fixture(scope="module")
def tab(browser, serve_app):
    with lesson_tab(browser, serve_app) as page:
        yield page


def _settled(tab):
    drawn(tab)
    # the letters follow on the next animation frames (over the core's picture, once its camera is the view's)
    # (or none at all: every tip hidden from the eye, as lesson 14's probe under the ball from behind it)
    tab.page.wait_for_function("() => { const l = document.querySelector('.phonglab-letters');"
                               " const tips = window.trame.state.get('arrow_tips') || [];"
                               " return l && ((l.style.display !== 'none' && l.children.length > 0)"
                               " || (tips.length > 0 && tips.every((t) => t.behind))); }", timeout=60_000)
    tab.page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")


def _misplaced(tab, what) -> list[str]:
    problems = []
    letters = tab.page.evaluate(LETTERS_JS)
    shares = {item["letter"]: item["label"] for item in letters}
    for item in letters:
        x, y = item["at"]
        own = item["tips"][item["letter"]]
        d_own = ((x - own[0]) ** 2 + (y - own[1]) ** 2) ** 0.5
        together = [other for other, label in shares.items() if label == item["label"]]
        # a letter alone is at most a letter wide: half its label's width more only in a shared label
        reach = REACH + (item["half"] if len(together) > 1 else 0.0)
        if d_own > reach:
            problems.append(f"{what}: {item['letter']} is {d_own:.1f} px from its tip (at most {reach:.1f})")
        for other, tip in item["tips"].items():
            apart = ((tip[0] - own[0]) ** 2 + (tip[1] - own[1]) ** 2) ** 0.5
            d_other = ((x - tip[0]) ** 2 + (y - tip[1]) ** 2) ** 0.5
            if other not in together and apart >= SAME_TIP and d_other <= d_own:
                problems.append(f"{what}: {item['letter']} is {d_other:.1f} px from {other}'s tip, "
                                f"{d_own:.1f} px from its own")
    if not letters:  # no letter is right only where the mesh hides every tip from the eye
        tips = tab.state("arrow_tips") or []
        assert tips and all(t["behind"] for t in tips), f"{what}: no letters drawn, tips {tips}"
    return problems


@pytest.mark.parametrize("stem", STEMS)  # one lesson a test, so the lessons share the workers
def test_every_lessons_letters_sit_at_their_own_tips(tab, stem):
    tab.page.goto(f"{tab.server['url']}?lesson={stem}")
    _settled(tab)
    problems = _misplaced(tab, f"{stem} as it opens")
    other = "gouraud" if tab.state("interpolation") == "pixel" else "pixel"
    tab.set_state("interpolation", repr(other))
    tab.page.wait_for_function("(p) => window.trame.state.get('pixel_mode') === p", arg=other == "pixel",
                               timeout=60_000)
    _settled(tab)
    problems += _misplaced(tab, f"{stem} in {other} mode")
    azimuth, before = tab.state("camera__azimuth"), tab.state("arrow_camera")
    tab.set_state("camera__azimuth", str(((azimuth + 215) % 360) - 180))  # the eye 35° round
    tab.page.wait_for_function("(b) => JSON.stringify(window.trame.state.get('arrow_camera')) !== b",
                               arg=json.dumps(before, separators=(",", ":")), timeout=60_000)
    _settled(tab)
    problems += _misplaced(tab, f"{stem} in {other} mode, the eye 35° round")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("probe", ["0.1,0.1,0", "0.3,-0.3,0"])
def test_crowded_tips_keep_their_letters(tab, probe):
    # the floor under lesson 7's spot: N, L and R nearly (0.1, 0.1) or exactly (0.3, -0.3) along one line
    tab.page.goto(f"{tab.server['url']}?lesson=07-light-sources&probe={probe}")
    _settled(tab)
    problems = _misplaced(tab, f"lesson 7, probe at {probe}")
    assert not problems, "\n".join(problems)


def test_the_letters_meet_the_pictures_arrows_after_a_new_marker_widens_the_view(tab):
    # lesson 7's sun: a directional light's marker far out widens the server's view angle; the page's camera
    # must follow, or the letters (projected with it) miss the arrows of the core's picture
    tab.page.goto(f"{tab.server['url']}?lesson=07-light-sources")
    _settled(tab)
    tab.page.locator(".phonglab-apply").nth(2).click()
    tab.page.wait_for_function("() => window.trame.state.get('lights_2__type') === 'directional'", timeout=60_000)
    _settled(tab)
    picture = tab.state("arrow_camera")
    browser = tab.page.evaluate("() => { const c = window.phonglabView.renderer.getActiveCamera();"
                                " return { position: c.getPosition(), view_angle: c.getViewAngle() }; }")
    assert browser["view_angle"] == pytest.approx(picture["view_angle"], rel=1e-6), (browser, picture)
    assert browser["position"] == pytest.approx(picture["position"], rel=1e-6), (browser, picture)
    problems = _misplaced(tab, "lesson 7, the sun")
    assert not problems, "\n".join(problems)


#: half a letter's box on the page (LETTER_BOX / 2 in www/phonglab.js)
HALF_BOX = 8.5


def _to_segment(p, a, b):
    ux, uy = b[0] - a[0], b[1] - a[1]
    uu = ux * ux + uy * uy
    t = min(1.0, max(0.0, ((p[0] - a[0]) * ux + (p[1] - a[1]) * uy) / uu)) if uu else 0.0
    return ((p[0] - a[0] - t * ux) ** 2 + (p[1] - a[1] - t * uy) ** 2) ** 0.5


def test_no_letter_sits_on_another_arrow_in_lesson_4_as_it_opens(tab):
    # lesson 4 as it opens: H was drawn over L's shaft, though free places about H's tip were left
    tab.page.goto(f"{tab.server['url']}?lesson=04-specular")
    _settled(tab)
    letters = tab.page.evaluate(LETTERS_JS)
    assert letters, "no letters drawn in lesson 4"
    arrows = {letter: (letters[0]["bases"][letter], tip) for letter, tip in letters[0]["tips"].items()}
    on = []
    for item in letters:
        own = arrows[item["letter"]][1]
        for other, (base, tip) in arrows.items():
            apart = ((tip[0] - own[0]) ** 2 + (tip[1] - own[1]) ** 2) ** 0.5 >= SAME_TIP
            if other != item["letter"] and apart and _to_segment(item["at"], base, tip) < HALF_BOX - 0.5:
                on.append(f"{item['letter']} at {item['at']} lies on {other} ({base} to {tip})")
    assert not on, f"{on}; arrows {arrows}"


def test_lesson_3s_meeting_arrows_share_one_label_and_no_letters_cover_each_other(tab):
    # lesson 3's probe is 1.9° from the light's mirror direction: N, L and R end within a few pixels, and
    # their letters, each placed about its own tip, scattered about that point as any of the three
    tab.page.goto(f"{tab.server['url']}?lesson=03-diffuse")
    _settled(tab)
    letters = tab.page.evaluate(LETTERS_JS)
    tips = {letter: [round(c, 1) for c in tip] for letter, tip in (letters[0]["tips"] if letters else {}).items()}
    where = (f"lesson 3 as it opens: tips {tips}, letters (centre, label, box) "
             f"{ {i['letter']: (i['at'], i['label'], [round(c, 1) for c in i['box']]) for i in letters} }")
    boxes = {item["letter"]: item["box"] for item in letters}
    labels = {item["letter"]: item["label"] for item in letters}
    assert set(boxes) == set("NLRVH"), where
    covered = [f"{a} {boxes[a]} and {b} {boxes[b]}" for a in boxes for b in boxes
               if a < b and boxes[a][0] < boxes[b][2] and boxes[b][0] < boxes[a][2]
               and boxes[a][1] < boxes[b][3] and boxes[b][1] < boxes[a][3]]
    assert not covered, f"letters cover each other: {covered}; {where}"
    assert labels["N"] == labels["L"] == labels["R"] and len(set(labels.values())) == 3, (
        f"N, L and R should share one label, V and H have their own: {labels}; {where}")
    row = sorted("NLR", key=lambda letter: boxes[letter][0])
    assert row == list("NLR"), f"the shared label reads {', '.join(row)}, not N, L, R; {where}"
    problems = _misplaced(tab, "lesson 3 as it opens")
    assert not problems, "\n".join(problems)
