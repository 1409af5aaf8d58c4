"""Every shipped scene file is solved, and checked against its exact field when it has one."""

from pathlib import Path

import pytest

from efgkit.scenefile import load_study
from efgkit.static import solve

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

EXAMPLES = sorted(p for p in (Path(__file__).resolve().parents[1] / "examples").glob("*.toml")
                  if "parameters" not in tomllib.loads(p.read_text()))  # study files: test_study

# Relative energy-norm error bounds at the shipped discretisations (measured: kirsch
# 1.5e-2, cantilever 7.8e-3; see docs/verification.md for the convergence studies).
ENERGY_BOUND = {"kirsch": 0.03, "cantilever": 0.02}
# Stress intensity factors of the shear edge crack, seed 003 Sect. 5.6.2 (Wilson 1969):
# K_I = 34.0, K_II = 4.55; the shipped discretisation gives 34.03 and 4.537 (measured).
SIF_REFERENCE = {"edge_crack": {"edge:1": (34.0, 4.55)},
                 # K_I = F sigma sqrt(pi a), sigma = 1, a = 0.5, K_II = 0: SENT F(0.5) = 2.827,
                 # CCT F(0.5) = 1.186 (Tada, Paris, Irwin, Handbook, 2nd ed. 1985, pp. 2.11,
                 # 2.2; the SENT's 0.5 % accurate); measured 0.1 % off (both)
                 "sent_tension": {"edge:1": (2.827 * 1.2533141373155001, 0.0)},
                 "cct_tension": {f"centre:{e}": (1.186 * 1.2533141373155001, 0.0) for e in (0, 1)}}
# Relative bounds on K: measured K_I / K_I,ref - 1 = +7.6e-4 and K_II -2.9e-3 (edge_crack,
# Wilson's 3 digits), -1.08e-3 (sent_tension: the bound is the handbook fit's stated 0.5 %,
# below which the reference cannot judge), +1.39e-3 (cct_tension, Tada's fit 0.1 %)
SIF_TOL = {"edge_crack": 0.01, "sent_tension": 0.005, "cct_tension": 0.004}


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_shipped_scene_runs(path):
    scene, method = load_study(path)
    sol = solve(scene, method)
    assert sol.info["residual"] < 1e-8
    if scene.exact is not None:
        assert sol.errors()["energy"] < ENERGY_BOUND[scene.name]
    for tip in sol.sifs() if scene.cracks else ():
        KI, KII = SIF_REFERENCE[scene.name][tip.tip.id]
        tol = SIF_TOL[scene.name]
        assert abs(tip.KI / KI - 1) < tol
        assert abs(tip.KII / KII - 1) < tol if KII else abs(tip.KII) < 1e-3 * abs(KI)
        assert tip.spread < 0.01 and not tip.warnings
