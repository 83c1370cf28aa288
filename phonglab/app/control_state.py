"""A tab's control values in its trame state, kept in step with the scene at the cost of what changed.

After every new scene each control's widget value must be in the state
(its key, :mod:`phonglab.app.keys`) and each slider's value as the page shows
it in ``control_values``. A slider step changes one or two of a hundred
values, so :class:`ControlState` writes only those: it compares with the
state the values that changed since the last scene (from
:meth:`~phonglab.app.controls.ControlSet.values`) and those a browser wrote
since (which the app may have refused or ignored); every other key holds its
value already.
"""

from __future__ import annotations

from phonglab.app.control import format_value


class ControlState:
    """What one tab last wrote of its controls into its state, and which keys its browser wrote since."""

    def __init__(self):
        self._synced = None  # state key -> value last written (or found in the state)
        self._written: set = set()  # keys a browser wrote since
        self._shown: dict = {}  # the sliders' values as the page shows them (state key -> text)

    def written(self, key: str) -> None:
        """A browser wrote ``key``: it is compared again at the next :meth:`sync`."""
        self._written.add(key)

    def sync(self, state, controls, scene, options) -> dict:
        """Write every control's value for ``scene`` into ``state``; returns them (state key -> value).

        ``controls`` is the tab's :class:`~phonglab.app.controls.ControlSet`,
        fitted to ``scene``. A browser's own value is left where it equals the
        scene's to within half a step: a slider being dragged would otherwise
        jump back to an older position with rounding noise.
        """
        values = controls.values(scene, options)
        last, self._synced = self._synced, values
        written, self._written = self._written, set()
        whole = last is None or last.keys() != values.keys()
        keys = list(values) if whole else [key for key, value in values.items()
                                            if key in written or value != last[key]]
        changed = {key: values[key] for key in keys if not controls.by_key[key].same(state[key], values[key])}
        if changed:
            # the server's own values: no change handler needs to see them
            with state.suppress_change_listeners(*changed):
                state.update(changed)
        # the sliders' values as the page shows them: formatted again only where they changed
        if whole:
            self._shown = {}
        for key in keys:
            control = controls.by_key[key]
            if control.kind == "slider":
                self._shown[key] = format_value(control, values[key])
        if self._shown != state.control_values:
            state.control_values = dict(self._shown)  # a copy: the state compares with what it sent
        return values
