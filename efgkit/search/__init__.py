"""Neighbour search (seed 000 Sect. 4): which nodes' supports cover each point.

:func:`find_neighbours` (padded lists) and :func:`neighbour_lists` (CSR) by a uniform
or a nonuniform box grid (:class:`BoxGrid`) or cKDTree; :func:`research_interval` for
moving nodes.
"""

from .boxes import KINDS, BoxGrid
from .moving import Research, research_interval
from .neighbours import METHODS, Neighbours, choose_method, find_neighbours, neighbour_lists

__all__ = ["BoxGrid", "KINDS", "METHODS", "Neighbours", "Research", "choose_method",
           "find_neighbours", "neighbour_lists", "research_interval"]
