"""efgkit: meshless Galerkin (EFG, MLPG) fracture mechanics in 2D linear elasticity."""

from importlib.metadata import PackageNotFoundError, version

from .crack import Crack
from .geometry import Domain, Loop
from .material import Elastic
from .methods import EFG, Zone
from .scene import Scene, Support, Traction

try:
    __version__ = version("efgkit")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = sorted(
    ["Crack", "Domain", "EFG", "Elastic", "Loop", "Scene", "Support", "Traction", "Zone"]
)
