"""Lesson text for the page: Markdown with its maths typeset as MathML.

Formulas are written ``$...$`` (inline) and ``$$...$$`` (display) in the
lessons. They are cut out before Markdown sees them (so ``_`` and ``*``
inside a formula stay maths), converted to MathML on the server with
latex2mathml, and put back into the HTML. Chromium renders MathML natively,
so the page needs no maths library and nothing from the internet. A formula
latex2mathml cannot read is shown as its source in a highlighted ``<code>``,
never as raw ``$...$``. ``\\$`` writes a literal dollar sign.
"""

from __future__ import annotations

import functools
import html
import re

import markdown
from latex2mathml.converter import convert as _latex_to_mathml

# $$...$$ first, then $...$ that neither starts nor ends with a space
_MATH = re.compile(r"(?<!\\)\$\$(.+?)(?<!\\)\$\$|(?<![\\$])\$(?=\S)(.+?)(?<=\S)(?<!\\)\$(?!\$)", re.DOTALL)
_TOKEN = "PHONGLABMATH{}X"
_TOKEN_RE = re.compile(r"PHONGLABMATH(\d+)X")
#: an inline formula with the brackets and punctuation that touch it: kept on one line with them
_TOUCHING = re.compile(r"([(\[‘“]*)(PHONGLABMATH\d+X)([.,;:!?…)\]’”]*)")


@functools.lru_cache(maxsize=4096)
def mathml(tex: str, *, display: bool = False) -> str:
    """One LaTeX formula as a MathML ``<math>`` element.

    Parameters
    ----------
    tex : str
        The formula, without dollar signs.
    display : bool
        A display (block) formula instead of an inline one.

    Returns
    -------
    str
        ``<math ...>...</math>``; if the formula cannot be converted, a
        ``<code class="math-error">`` holding its source.
    """
    try:
        return _latex_to_mathml(tex.strip(), display="block" if display else "inline")
    except Exception:  # latex2mathml raises assorted errors on bad input
        return f'<code class="math-error" title="this formula could not be typeset">{html.escape(tex)}</code>'


def render_markdown(text: str) -> str:
    """Lesson Markdown as HTML, formulas as MathML.

    Examples
    --------
    >>> "<math" in render_markdown("Diffuse light is $k_d\\\\max(0, n\\\\cdot l)$.")
    True
    """
    formulas: list[str] = []

    def cut(match: re.Match) -> str:
        display = match.group(1) is not None
        tex = match.group(1) if display else match.group(2)
        formulas.append(mathml(tex, display=display))
        token = _TOKEN.format(len(formulas) - 1)
        # a display formula stands in its own paragraph
        return f"\n\n{token}\n\n" if display else token

    protected = _MATH.sub(cut, text)
    body = markdown.markdown(protected, extensions=["extra", "sane_lists"], output_format="html")
    body = body.replace("\\$", "$")

    def paste(match: re.Match) -> str:
        return formulas[int(match.group(1))]

    def touching(match: re.Match) -> str:
        # a browser may break a line on either side of a formula, even before a full stop: not here
        before, token, after = match.groups()
        formula = paste(_TOKEN_RE.match(token))
        return f'<span class="phonglab-nobreak">{before}{formula}{after}</span>' if before or after else formula

    # a display formula alone in a paragraph replaces the paragraph
    body = re.sub(r"<p>\s*(PHONGLABMATH\d+X)\s*</p>", lambda m: '<div class="math-block">' + paste(_TOKEN_RE.match(m.group(1))) + "</div>", body)
    return _TOUCHING.sub(touching, body)


#: a material coefficient written plainly (``k_d``) in a lesson's plain-text field
_PLAIN_SYMBOL = re.compile(r"(?<![\w\\{])k_([adse])(?![\w}])")
#: what :func:`symbols_as_math` leaves alone: the formulas :data:`_MATH` finds, code, a written dollar (``\$``)
_KEPT = re.compile(_MATH.pattern + r"|`[^`]*`|\\\$", re.DOTALL)


def symbols_as_math(text: str) -> str:
    """``k_a``, ``k_d``, ``k_s``, ``k_e`` written plainly, as the formulas ``$k_d$``; formulas and code stay.

    A lesson's front matter (its goal, question, answer, the check's
    choices and feedback) is plain text in TOML, and its authors write k_d
    there as in a sentence; the page sets it as the body's formulas do.

    >>> symbols_as_math("k_d = 0.5, `k_d` and $k_d I_d$; peak_error")
    '$k_d$ = 0.5, `k_d` and $k_d I_d$; peak_error'
    """
    out, at = [], 0
    for kept in _KEPT.finditer(text):
        out += [_PLAIN_SYMBOL.sub(r"$k_\1$", text[at:kept.start()]), kept.group(0)]
        at = kept.end()
    return "".join(out) + _PLAIN_SYMBOL.sub(r"$k_\1$", text[at:])


@functools.lru_cache(maxsize=1024)
def inline(text: str) -> str:
    """A short text (a label, a goal) with ``$...$`` formulas, as HTML without a paragraph.

    A plainly written ``k_d`` is set as a formula (:func:`symbols_as_math`).
    """
    html_text = render_markdown(symbols_as_math(text)).strip()
    if html_text.startswith("<p>") and html_text.endswith("</p>") and html_text.count("<p>") == 1:
        html_text = html_text[3:-4]
    return html_text


def strip_title(body: str, title: str | None = None) -> str:
    """The lesson body without the ``#`` heading that is its title (the page shows the title itself).

    With ``title`` given, the body's first line is dropped only when it is a
    ``#`` heading with exactly that text; any other heading stays and is
    rendered, so no heading is lost. Without ``title`` the first line is
    dropped when it is a ``#`` heading (the title the lesson took from it).
    """
    lines = body.lstrip("\n").splitlines()
    if lines and lines[0].startswith("# "):
        heading = lines[0][2:].strip().rstrip("#").strip()
        if title is None or heading == title.strip():
            lines = lines[1:]
    return "\n".join(lines)
