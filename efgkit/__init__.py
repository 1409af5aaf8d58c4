"""efgkit: meshless Galerkin (EFG, MLPG) fracture mechanics in 2D linear elasticity."""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version

# Public names and the modules that define them, imported on first use (PEP 562): a plain
# `efgkit run` never loads the explicit, FEM, growth or MLPG machinery (cold start).
_WHERE = {
    "DynamicSolution": "explicit", "integrate": "explicit",
    "FEM": "fem", "FEMSolution": "fem", "solve_fem": "fem",
    "TipResult": "fracture.sif",
    "Growth": "growth", "GrowthStep": "growth", "grow": "growth",
    "MeshlessSolution": "meshless_solution",
    "EFG": "methods", "Rosette": "methods", "Zone": "methods",
    "discretize": "methods.discretize",
    "MLPG": "methods.mlpg",
    **dict.fromkeys(("Crack", "Domain", "Elastic", "Field", "Loop", "PointSupport", "Pressure",
                     "Scene", "Support", "Traction"), "problem"),
    **dict.fromkeys(("Heaviside", "ImpactPulse", "Linear", "Ramp", "Stepping", "Tabulated"),
                    "problem.history"),
    "Grading": "problem.graded",
    "load_scene": "scenefile", "load_study": "scenefile",
    "Solution": "solution",
    "solve": "static",
}


def __getattr__(name: str):
    """A public name (or a subpackage) imported on first access."""
    if name in _WHERE:
        value = getattr(import_module(f".{_WHERE[name]}", __name__), name)
    else:
        try:
            value = import_module(f".{name}", __name__)
        except ModuleNotFoundError as err:
            if err.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_WHERE))


try:
    __version__ = version("efgkit")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "Crack", "Domain", "DynamicSolution", "EFG", "Elastic", "FEM", "FEMSolution", "Field",
    "Grading", "Growth", "GrowthStep", "Heaviside", "ImpactPulse", "Linear", "Loop", "MLPG",
    "MeshlessSolution", "PointSupport", "Pressure", "Ramp", "Rosette", "Scene", "Solution",
    "Stepping", "Support", "Tabulated", "TipResult", "Traction", "Zone", "__version__",
    "discretize", "grow", "integrate", "load_scene", "load_study", "solve", "solve_fem",
]
