"""linkwork: kinematics, kinetostatics, balancing and synthesis of machine mechanisms.

Layers (see ``docs/architecture.md``): closed-form models in :mod:`linkwork.models`, the general
planar engine in :mod:`linkwork.planar`, balancing, redundancy, synthesis, files, plots and the
command line. SI units and radians throughout; units only at the edges (:mod:`linkwork.units`).
"""

from linkwork.errors import (
    AssemblyError,
    LinkworkError,
    ParameterError,
)

__version__ = "0.1.0"

__all__ = ["AssemblyError", "LinkworkError", "ParameterError", "__version__"]
