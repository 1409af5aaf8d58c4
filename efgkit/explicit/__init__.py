"""Explicit time integration: ``M u'' + K u = f(t)`` by central differences.

``system`` assembles the semi-discrete system once (stiffness, lumped mass, loads per
history, essential conditions) and estimates the critical step; ``integrate`` runs the
loop of sparse products; ``output`` records probes, energies, SIFs and VTU series at the
output instants; ``dsif`` computes the dynamic SIFs (J', interaction with inertia, near-tip
stresses); ``result`` holds the histories (:class:`DynamicSolution`); ``mlpg_weight``
chooses the trial weight of explicit MLPG runs.
"""

from .dsif import DynamicDSIF, dynamic_dsif, quasi_static_dsif
from .integrate import BLOWUP_FACTOR, InstabilityError, State, initial_state, integrate, load_stepping
from .mlpg_weight import explicit_mlpg
from .result import DynamicSolution
from .spectrum import dense_operator, growth_rate, modal_energy, phase_speeds, row_symbol, stable_step
from .system import Dynamics, dynamics, fit_coefficients

__all__ = ["BLOWUP_FACTOR", "DynamicDSIF", "DynamicSolution", "Dynamics", "InstabilityError", "State",
           "dense_operator", "dynamic_dsif", "dynamics", "explicit_mlpg", "fit_coefficients", "growth_rate",
           "initial_state", "integrate", "load_stepping", "modal_energy", "phase_speeds", "quasi_static_dsif",
           "row_symbol", "stable_step"]
