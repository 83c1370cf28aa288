"""phonglab: an interactive teaching app for the Phong illumination model.

The lighting core is re-exported here (``pl.shade``, ``pl.Material``, ...);
``pl.figure`` (rendering, needs PyVista) and ``pl.show`` (the lesson view in a
Jupyter notebook, needs the ``jupyter`` extra) are imported on first use.
"""

from .core import *  # noqa: F401,F403
from .core import __all__ as _core_all

__version__ = "0.1.0"
__all__ = [*_core_all, "figure", "show"]


def __getattr__(name):
    # rendering pulls in VTK: import it only when a script asks for a figure
    if name == "figure":
        from .render import figure

        return figure
    if name == "show":
        from .app.jupyter import show

        return show
    raise AttributeError(f"module 'phonglab' has no attribute {name!r}")
