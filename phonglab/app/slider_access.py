"""What a slider needs besides its value: a name a screen reader says, and the arrow keys' step.

Vuetify's ``VSlider`` draws its thumb as the ``[role=slider]`` element and
gives it ``aria-label`` from the slider's ``name`` prop, so the name is the
control's plain label (:func:`phonglab.app.wording.spoken_label`: "specular
k_s", "light 1 azimuth"). Its ``aria-valuenow`` is the widget's number
(log10 α for the shininess); ``www/phonglab.js`` gives the thumb the value
text the control shows as ``aria-valuetext`` ("30"), which is what a screen
reader says.

One arrow key moves a Vuetify slider by its ``step``, which is also what a
drag snaps to. A control with a larger :attr:`~phonglab.app.control.Control.key_step`
(the log-scale shininess: 0.01 of log10 α is a 2 % change of α, too little
to see per key press) takes the arrow keys before the thumb does (a keydown
listener in the capture phase on the slider) and moves by ``key_step``,
rounded to the step; Shift and Ctrl multiply it by 3 and 2 as Vuetify's own
keys do. Dragging reaches every step as before; Home, End, Page Up and Page
Down keep Vuetify's behaviour.
"""

from __future__ import annotations

from phonglab.app.control import Control
from phonglab.app.wording import spoken_label

#: the keys a key step applies to, and which of them go up
_ARROWS = "['ArrowRight', 'ArrowUp', 'ArrowLeft', 'ArrowDown']"
_UP = "['ArrowRight', 'ArrowUp']"


def key_step_handler(control: Control) -> str:
    """The template's keydown handler (capture phase) that moves ``control``'s value by its key step.

    Only single quotes: the handler sits in a double-quoted HTML attribute.
    """
    key, step = control.key, control.step
    moved = (f"{key} + ({_UP}.includes($event.key) ? 1 : -1) * {control.key_step!r}"
             " * ($event.shiftKey ? 3 : $event.ctrlKey ? 2 : 1)")
    value = f"Math.min({control.high!r}, Math.max({control.low!r}, Math.round(({moved}) / {step!r}) * {step!r}))"
    return (f"if (!$event.altKey && !$event.metaKey && {_ARROWS}.includes($event.key)) "
            f"{{ $event.preventDefault(); $event.stopPropagation(); {key} = {value}; }}")


def slider_attributes(control: Control) -> dict:
    """Keyword arguments for ``v3.VSlider`` of ``control``: its spoken name, and its key step where it has one."""
    attributes = {"name": spoken_label(control)}
    if control.key_step and control.key_step != control.step:
        attributes["keydown_capture"] = key_step_handler(control)
        attributes["__events"] = [("keydown_capture", "keydown.capture")]
    return attributes
