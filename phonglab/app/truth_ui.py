"""Page parts that keep the picture honest: the "deliberately wrong" banner and the readout's mistaken terms.

Drawn inside the page's layout by :mod:`phonglab.app.page` (each function adds
its widgets where it is called) and bound to state keys the app fills:

* the banner lies over the 3D view whenever the lesson's common mistake is
  shown (``view__mistake``, ``mistake``), so a student who scrolled the
  switch away still sees that the picture is wrong;
* under the terms, each term the mistake changes (``readout.terms[i].correct``)
  is shown with the mistaken value that made the picture, the correct value,
  and the wrong line of code beside the right one;
* one line says that the numbers are linear light and the picture is
  encoded for the display (``readout.display_note``).
"""

from __future__ import annotations

from trame.widgets import html

#: what the banner says before the mistake's title
BANNER_TEXT = "Deliberately wrong: "


def wrong_banner() -> None:
    """The banner over the view while a common mistake is shown."""
    html.Div(BANNER_TEXT + "{{ mistake.title }}", v_if="view__mistake && mistake && mistake.available",
             classes="phonglab-wrong-banner", role="status")


def mistaken_terms() -> None:
    """For each term the mistake changes: mistaken value, correct value, wrong and right code."""
    with html.Div(v_for="t in readout.terms.filter(x => x.correct)", key="t.name",
                  classes="phonglab-term-wrong", data_wrong=("t.name",), __properties=[("data_wrong", "data-wrong-term")]):
        with html.Div(classes="phonglab-term-pair"):
            html.Span("{{ t.name }}", classes="phonglab-term-name")
            html.Span("", classes="phonglab-swatch", style=("{background: t.hex}",))
            html.Span("{{ t.value }}", classes="phonglab-mono phonglab-term-mistaken", title="the mistaken code")
            html.Span("correct", classes="phonglab-code-tag phonglab-code-right")
            html.Span("", classes="phonglab-swatch", style=("{background: t.correct_hex}",))
            html.Span("{{ t.correct }}", classes="phonglab-mono phonglab-term-correct")
        with html.Div(classes="phonglab-code"):
            html.Div("wrong", classes="phonglab-code-tag phonglab-code-wrong")
            html.Code("{{ t.wrong }}")
            html.Div("right", classes="phonglab-code-tag phonglab-code-right")
            html.Code("{{ t.right }}")


def display_note() -> None:
    """Once, beside the numbers: they are linear light; the picture is encoded for the screen."""
    html.Div("{{ readout.display_note }}", v_if="readout.display_note", classes="phonglab-note phonglab-display-note")
