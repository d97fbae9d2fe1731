"""Optional dependencies: import one, or fail with a user error that gives the exact install line.

Some features need packages that a plain ``pip install meshmark`` leaves out (extras in
``pyproject.toml``): plots need matplotlib (``meshmark[plot]``), Dask clusters need ``distributed``
(``meshmark[study]``). A missing one is the user's setup, not a bug, so it is a
:class:`MissingDependency` (a :class:`~meshmark.MeshError`: exit 2 at the command line) whose message
names the feature and the command that installs it.
"""
from __future__ import annotations

import importlib

from ._core import MeshError

# module -> (extra, distribution to name in the message)
EXTRAS = {
    "matplotlib": ("plot", "matplotlib"),
    "distributed": ("study", "dask[distributed]"),
    "dask": ("study", "dask[distributed]"),
    "pandas": ("study", "pandas"),
    "auditwheel": ("build", "auditwheel"),
}


class MissingDependency(MeshError):
    """An optional package is not installed; the message gives the pip line that installs it."""


def install_line(module: str) -> str:
    extra, dist = EXTRAS[module]
    return f"pip install 'meshmark[{extra}]'  (or: pip install '{dist}')"


def require(module: str, feature: str):
    """Import and return ``module`` (a key of :data:`EXTRAS`), or raise MissingDependency naming
    ``feature`` (e.g. "--dask") and the install line."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingDependency(f"{feature} needs the optional package '{EXTRAS[module][1]}', which is not "
                                f"installed: {install_line(module)}") from None


def pyplot(feature: str = "plots"):
    """matplotlib.pyplot with the non-interactive Agg backend, or MissingDependency."""
    mpl = require("matplotlib", feature)
    mpl.use("Agg")
    return importlib.import_module("matplotlib.pyplot")
