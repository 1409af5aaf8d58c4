"""efgkit: meshless Galerkin (EFG, MLPG) fracture mechanics in 2D linear elasticity."""

from importlib.metadata import PackageNotFoundError, version

from .explicit import DynamicSolution, integrate
from .fem import FEM, FEMSolution, solve_fem
from .fracture.sif import TipResult
from .growth import Growth, GrowthStep, grow
from .meshless_solution import MeshlessSolution
from .methods import EFG, Rosette, Zone
from .methods.discretize import discretize
from .methods.mlpg import MLPG
from .problem import Crack, Domain, Elastic, Field, Loop, PointSupport, Pressure, Scene, Support, Traction
from .problem.graded import Grading
from .problem.history import Heaviside, ImpactPulse, Linear, Ramp, Stepping, Tabulated
from .scenefile import load_scene, load_study
from .solution import Solution
from .static import solve

try:
    __version__ = version("efgkit")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "Crack", "Domain", "DynamicSolution", "EFG", "Elastic", "FEM", "FEMSolution", "Field", "Growth",
    "Grading", "GrowthStep", "Heaviside", "ImpactPulse", "Linear", "Loop", "MLPG", "MeshlessSolution",
    "PointSupport",
    "Pressure", "Ramp", "Rosette", "Scene", "Solution", "Stepping", "Support", "Tabulated", "TipResult",
    "Traction", "Zone", "__version__", "discretize", "grow", "integrate", "load_scene", "load_study",
    "solve", "solve_fem",
]
