"""Quadrature: where the weak forms are integrated.

``rules`` (the :class:`Points` container, Gauss rules on the line and the triangle),
``cells`` (background cells clipped to the body, or triangles through the nodes),
``cell_rule`` (that rule held per cell, its points written once in the order asked for),
``cut_cells`` (the clipping), ``tip_cells`` (rules of the cells that hold a crack
tip) and ``boundary`` (Gauss rules along edges and crack faces). The local disc and
sector rules of MLPG (seed 002 Eq. 39) belong here too.
"""

from .rules import Points, gauss_legendre, triangle_rule

__all__ = ["Points", "gauss_legendre", "triangle_rule"]
