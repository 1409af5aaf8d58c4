"""How a scene is discretised: the method descriptions and the discretisation itself.

``efg`` holds :class:`EFG` (with its :class:`Zone` and :class:`Rosette`) and the choices
it offers: frozen dataclasses of settings, no arrays. ``discretize`` turns a scene and
a method into nodes, quadrature points and shape functions (a ``Discretization``);
``boundary`` turns the scene's loads and supports into the load vector and the
essential-condition data on it. The MLPG description and its local sub-domains join
here beside EFG.

Only the descriptions are imported with the package: the discretisation sits above
the approximation in the pipeline, which itself reads the descriptions.
"""

from .efg import (
    BASES,
    BC_METHODS,
    CRACK_RULES,
    EFG,
    ENRICHMENTS,
    HOLE_RULES,
    QUADRATURES,
    RAMPS,
    SOLVERS,
    WEIGHTS,
    Rosette,
    Zone,
)

__all__ = ["BASES", "BC_METHODS", "CRACK_RULES", "EFG", "ENRICHMENTS", "HOLE_RULES",
           "QUADRATURES", "RAMPS", "SOLVERS", "WEIGHTS", "Rosette", "Zone"]
