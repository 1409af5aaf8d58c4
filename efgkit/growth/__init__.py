"""Crack-growth step loops over the static drivers: quasi-static paths and fatigue lives.

:func:`grow` is a generator of :class:`GrowthStep` (seed 003 Sect. 6); :class:`Growth`
holds its settings (a scene file's ``[growth]`` table); :mod:`~efgkit.growth.record`
writes the event log and the restart file, :mod:`~efgkit.growth.figures` the path and
K figures.
"""

from .extend import Advance, advance
from .loop import GrowthState, GrowthStep, grow, rediscretize
from .settings import Growth

__all__ = ["Advance", "Growth", "GrowthState", "GrowthStep", "advance", "grow", "rediscretize"]
