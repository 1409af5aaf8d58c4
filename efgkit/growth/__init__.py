"""Crack-growth step loops over the static drivers: quasi-static paths and fatigue lives.

:func:`grow` is a generator of :class:`GrowthStep` (seed 003 Sect. 6); :class:`Growth`
holds its settings (a scene file's ``[growth]`` table); :mod:`~efgkit.growth.record`
writes the event log and the restart file, :mod:`~efgkit.growth.figures` the path and
K figures. :func:`~efgkit.growth.dynamic.run_growing` runs cracks in an explicit run at a
prescribed speed or by a principal-stress criterion (nodal release).
"""

from .dynamic import DynamicGrowth, PrescribedSpeed, PrincipalStress, run_growing
from .extend import Advance, advance
from .loop import GrowthState, GrowthStep, grow, rediscretize
from .settings import Growth

__all__ = ["Advance", "DynamicGrowth", "Growth", "GrowthState", "GrowthStep", "PrescribedSpeed",
           "PrincipalStress", "advance", "grow", "rediscretize", "run_growing"]
