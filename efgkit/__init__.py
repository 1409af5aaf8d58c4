"""efgkit: meshless Galerkin (EFG, MLPG) fracture mechanics in 2D linear elasticity."""

from importlib.metadata import PackageNotFoundError, version

from .analytic import Field
from .crack import Crack
from .discretize import discretize
from .fem import FEM, solve_fem
from .fracture.sif import TipResult
from .geometry import Domain, Loop
from .material import Elastic
from .methods import EFG, Rosette, Zone
from .scene import Scene, Support, Traction
from .scenefile import load_scene, load_study
from .solution import Solution
from .static import solve

try:
    __version__ = version("efgkit")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "Crack", "Domain", "EFG", "Elastic", "FEM", "Field", "Loop", "Rosette", "Scene", "Solution",
    "Support", "TipResult", "Traction", "Zone", "__version__", "discretize", "load_scene",
    "load_study", "solve", "solve_fem",
]
