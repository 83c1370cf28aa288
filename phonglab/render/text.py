"""Fitting matplotlib text to the room it has: shrinking to a width, wrapping into lines.

Widths are in pixels of the figure's canvas, measured with the figure's own
renderer (``fig.canvas.get_renderer()``).
"""

from __future__ import annotations


def fit_width(text, renderer, width: float) -> None:
    """Shrink ``text``'s font until it is at most ``width`` pixels wide."""
    extent = text.get_window_extent(renderer).width
    if extent > width > 0:
        text.set_fontsize(text.get_fontsize() * width / extent * 0.98)


def keep_inside(text, fig, pad: float) -> None:
    """Shrink a centred text (an axes title) until it stays ``pad`` pixels inside the figure's sides."""
    renderer = fig.canvas.get_renderer()
    box = text.get_window_extent(renderer)
    centre = (box.x0 + box.x1) / 2
    width = fig.get_size_inches()[0] * fig.dpi
    fit_width(text, renderer, 2 * min(centre - pad, width - pad - centre))


def wrap(fig, renderer, text: str, width: float, fontsize: float, style) -> list[str]:
    """Split ``text`` into lines at most ``width`` pixels wide.

    A text too wide for one line is broken after a dash ``" — "`` first,
    then at spaces; a single word wider than ``width`` keeps its own line.
    ``style`` holds matplotlib font options (``{"weight": "bold"}``).
    """
    probe = fig.text(0, 0, "", fontsize=fontsize, **style)

    def fits(line: str) -> bool:
        probe.set_text(line)
        return probe.get_window_extent(renderer).width <= width

    try:
        if fits(text):
            return [text]
        parts = text.split(" — ")
        parts = [p + " —" for p in parts[:-1]] + parts[-1:]
        lines = []
        for part in parts:
            current = ""
            for word in part.split():
                candidate = f"{current} {word}" if current else word
                if not current or fits(candidate):
                    current = candidate
                else:
                    lines.append(current)
                    current = word
            lines.append(current)
    finally:
        probe.remove()
    return lines
