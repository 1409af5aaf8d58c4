"""Every shipped scene file is solved, and checked against its exact field when it has one."""

from pathlib import Path

import pytest

from efgkit.scenefile import load_study
from efgkit.static import solve

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("*.toml"))

# Relative energy-norm error bounds at the shipped discretisations (measured: kirsch
# 1.5e-2, cantilever 7.8e-3; see docs/verification.md for the convergence studies).
ENERGY_BOUND = {"kirsch": 0.03, "cantilever": 0.02}


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_shipped_scene_runs(path):
    scene, method = load_study(path)
    sol = solve(scene, method)
    assert sol.info["residual"] < 1e-8
    if scene.exact is not None:
        assert sol.errors()["energy"] < ENERGY_BOUND[scene.name]
