"""efgkit: meshless Galerkin (EFG, MLPG) fracture mechanics in 2D linear elasticity."""

from importlib.metadata import PackageNotFoundError, version

from .fem import FEM, FEMSolution, solve_fem
from .fracture.sif import TipResult
from .meshless_solution import MeshlessSolution
from .methods import EFG, Rosette, Zone
from .methods.discretize import discretize
from .methods.mlpg import MLPG
from .problem import Crack, Domain, Elastic, Field, Loop, Scene, Support, Traction
from .scenefile import load_scene, load_study
from .solution import Solution
from .static import solve

try:
    __version__ = version("efgkit")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "Crack", "Domain", "EFG", "Elastic", "FEM", "FEMSolution", "Field", "Loop", "MLPG", "MeshlessSolution",
    "Rosette", "Scene", "Solution", "Support", "TipResult", "Traction", "Zone", "__version__",
    "discretize", "load_scene", "load_study", "solve", "solve_fem",
]
