"""Closed-form 2D elasticity fields: the exact solutions and boundary data of the
verification problems. ``fields`` names them for scenes and scene files (:class:`Field`);
``williams`` holds the near-tip (and point-force) fields of a straight crack in its tip
frame, ``griffith`` the Westergaard field of a crack in an infinite plate, ``moving`` the
near-tip field of a crack moving steadily (the reference of the dynamic J').
"""

from .fields import Field, field_errors

__all__ = ["Field", "field_errors"]
