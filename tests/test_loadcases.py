"""Load cases with one factorisation: the same coefficients, SIFs and reactions as separate
solves, superposition, and the cases must share the body."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from efgkit import EFG, Elastic, Support, Traction, solve
from efgkit.gallery import shear_edge_crack
from efgkit.loadcases import solve_cases

BASE = shear_edge_crack()
CASES = {"shear": BASE, "tension": replace(BASE, tractions=(Traction("top", (0.0, 1.0)),)),
         "both": replace(BASE, tractions=(Traction("top", (1.0, 1.0)),)),
         "pressure": replace(BASE, tractions=(), cracks=(replace(BASE.cracks[0], pressure=1.0),))}


@pytest.mark.filterwarnings("ignore:bc='modified_mls'")
@pytest.mark.parametrize("bc", ["lagrange", "variational", "modified_mls"])  # the three embeddings
def test_cases_equal_separate_solves(bc):
    m = EFG(spacing=1.0, bc=bc, enrichment="none")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = solve_cases(CASES, m)
        k = {n: s.sifs(error=False)[0] for n, s in sols.items()}
        for n in ("tension", "pressure"):  # measured 5e-12 apart (K ~ 30)
            ref = solve(CASES[n], m)
            r = ref.sifs(error=False)[0]
            assert abs(k[n].KI - r.KI) < 1e-9 * abs(r.KI) and abs(k[n].KII - r.KII) < 1e-9 * abs(r.KI)
            dr = sols[n].reaction("bottom", about=(0, 0)) - ref.reaction("bottom", about=(0, 0))
            assert np.abs(dr).max() < 1e-9
    assert list(sols) == list(CASES) and all(s.info["factorised_once"] for s in sols.values())
    # linear: the combined load's K is the sum of its parts' (measured 7e-14)
    assert abs(k["both"].KI - k["shear"].KI - k["tension"].KI) < 1e-10 * abs(k["both"].KI)
    # each case's reactions balance its own load: (-1, -1) of traction over the 7-wide top
    assert np.allclose(sols["both"].reaction("bottom"), [-7.0, -7.0], rtol=0, atol=1e-9)


@pytest.mark.parametrize("change, match", [
    (dict(supports=(Support("bottom", ux=0.0),)), "supports"),
    (dict(material=Elastic(1.0, 0.3)), "material"),
    (dict(cracks=()), "cracks"),
])
def test_cases_share_the_body(change, match):
    with pytest.raises(ValueError, match=f"differs from 'shear' in its {match}"):
        solve_cases({"shear": BASE, "other": replace(BASE, **change)}, EFG(spacing=0.7))


def test_bad_cases():
    with pytest.raises(ValueError, match="non-empty mapping"):
        solve_cases({}, EFG(spacing=0.7))
    with pytest.raises(TypeError, match="must be a Scene"):
        solve_cases({"a": BASE, "b": "scene"}, EFG(spacing=0.7))
