"""The physical problem: what is solved, independent of how.

``geometry`` (the body: loops of named straight and arc edges, holes), ``crack``
(crack polylines, tips and tip frames), ``frames`` (polar coordinates and rotations
in a tip frame), ``material`` (isotropic linear elasticity), ``scene`` (supports,
tractions, body force and cracks on a domain: the frozen :class:`Scene`) and
``exact/`` (closed-form fields: Williams, Griffith, Kirsch, Timoshenko). Nothing here
knows about nodes, points or matrices.
"""

from .crack import Crack, Tip
from .exact.fields import Field
from .expression import Expression, VectorExpression
from .geometry import Domain, Edge, Loop
from .graded import Grading
from .material import Elastic
from .scene import PointSupport, Pressure, Scene, Support, Traction
from .symmetry import Symmetry

__all__ = ["Crack", "Domain", "Edge", "Elastic", "Expression", "Field", "Grading", "Loop", "PointSupport",
           "Pressure",
           "Scene", "Support", "Symmetry", "Tip", "Traction", "VectorExpression"]
