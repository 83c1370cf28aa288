"""The render layer's error for options a figure cannot be made from (imports nothing)."""


class FigureError(ValueError):
    """A figure cannot be made from the given options; the message is one line."""
