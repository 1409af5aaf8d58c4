"""Linear algebra of the discretised problem, never reading the scene.

``assemble`` (stiffness, load vector and lumped mass from shape operators at weighted
points), ``constraints`` (essential conditions as penalty, Lagrange multipliers, the
modified variational principle or elimination; the linear system they give),
``collocation`` (equations replaced by constraint rows: the modified collocation method),
``linalg`` (direct and preconditioned iterative solves, checked; the CG iteration and
its energy-error bound in ``conjugate_gradient``) and ``auxiliary``
(the auxiliary-space preconditioner on a P1 stiffness of the nodes).
"""

from .collocation import SingularRowsError
from .constraints import RigidBodyModeError
from .linalg import SolverError
from .linear_system import LinearSystem

__all__ = ["LinearSystem", "RigidBodyModeError", "SingularRowsError", "SolverError"]
