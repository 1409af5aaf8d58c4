"""Load cases with one factorisation: the same coefficients, SIFs and reactions as separate
solves, superposition, and the cases must share the body."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from efgkit import EFG, Elastic, Support, Traction, solve
from efgkit.gallery import sent_seed001, shear_edge_crack
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
    (dict(supports=(Support("bottom", ux=0.0),)), "supported edges and components"),
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


SENT = sent_seed001()
D = 0.0253882  # seed 001: the grips' displacement


def _grips(left, right):
    return (Support("left", ux=left, uy=0.0), Support("right", ux=right, uy=0.0))


@pytest.mark.filterwarnings("ignore:bc='modified_mls'")
@pytest.mark.parametrize("bc", ["lagrange", "penalty", "variational", "modified_mls"])
def test_support_values_per_case_equal_separate_solves(bc):
    # same supported edges and components, other prescribed values: one factorisation, each
    # case's own right-hand side; K, J and the grip reaction against separate solves (measured:
    # 0 with lagrange, K and J <= 3.1e-14, reaction <= 7.1e-12 with penalty) and linear in the
    # values (doubled grips: twice K, measured exactly)
    cases = {"pull": SENT, "pull twice": replace(SENT, supports=_grips(-2 * D, 2 * D)),
             "one grip": replace(SENT, supports=_grips(0.0, D)),
             "pull and shear": replace(SENT, supports=_grips(-D, D),
                                       tractions=(Traction("top", (1.0, 0.0)),))}
    m = EFG(spacing=2.0, bc=bc, enrichment="none")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = solve_cases(cases, m)
        for n in ("pull twice", "one grip", "pull and shear"):
            ref = solve(cases[n], m)
            a, r = sols[n].sifs(error=False)[0], ref.sifs(error=False)[0]
            assert abs(a.KI / r.KI - 1) < 1e-12 and abs(a.J / r.J - 1) < 1e-12
            fa, fr = sols[n].reaction("right"), ref.reaction("right")
            assert np.abs(fa - fr).max() < 3e-11 * np.abs(fr).max()
        k = {n: s.sifs(error=False)[0].KI for n, s in sols.items()}
    assert all(s.info["factorised_once"] for s in sols.values())
    assert abs(k["pull twice"] / k["pull"] - 2) < 1e-12


def test_support_values_per_case_of_a_half_model():
    # EFG half model (image nodes): the pulled grip's value per case, against separate solves
    # (measured equal, 0, and exactly twice K)
    half = sent_seed001(model="half")
    twice = replace(half, supports=(Support("ligament", ux=0.0), Support("right", ux=2 * D, uy=0.0)))
    m = EFG(spacing=2.0, enrichment="none")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = solve_cases({"pull": half, "twice": twice}, m)
        k = {n: s.sifs(error=False)[0].KI for n, s in sols.items()}
        for n, sc in (("pull", half), ("twice", twice)):
            assert abs(k[n] / solve(sc, m).sifs(error=False)[0].KI - 1) < 1e-12
    assert abs(k["twice"] / k["pull"] - 2) < 1e-12


def test_other_supported_edges_are_refused():
    other = replace(SENT, supports=(Support("left", ux=-D), Support("right", ux=D, uy=0.0)))
    with pytest.raises(ValueError, match="supported edges and components.*solve a case with other"):
        solve_cases({"pull": SENT, "other": other}, EFG(spacing=2.0))


def test_support_values_per_case_in_a_scene_file():
    # [[load_cases]] with their own supports: read, solved like the Python cases, written back
    from efgkit.scenefile import cases_from_dict, cases_to_list, scene_to_dict

    d = {"material": {"E": 1000.0, "nu": 0.3}, "domain": {"outer": {"rectangle": [0, 0, 2, 1]}},
         "supports": [{"edge": "left", "ux": 0.0}, {"edge": "bottom", "uy": 0.0},
                      {"edge": "right", "ux": 0.001}],
         "load_cases": [{"name": "stretch"},
                        {"name": "stretch more", "supports": [{"edge": "left", "ux": 0.0},
                                                              {"edge": "bottom", "uy": 0.0},
                                                              {"edge": "right", "ux": 0.003}]}]}
    cases = cases_from_dict(d)
    assert cases["stretch more"].supports[2].ux == 0.003 and cases["stretch"].supports[2].ux == 0.001
    assert cases_to_list(cases) == d["load_cases"]
    back = cases_from_dict({**scene_to_dict(cases["stretch"]), "load_cases": cases_to_list(cases)})
    assert [c.supports for c in back.values()] == [c.supports for c in cases.values()]
    sols = solve_cases(cases, EFG(spacing=0.25, bc="lagrange"))
    # uniform stretch, u_x = the grip's value at x = 2 (closed form): measured 2.9e-8 relative
    # (EFG's background-cell integration error of the patch test)
    u = {n: s.displacement([[2.0, 0.5]])[0, 0] for n, s in sols.items()}
    assert u["stretch"] == pytest.approx(0.001, rel=1e-7)
    assert u["stretch more"] == pytest.approx(0.003, rel=1e-7)
    bad = {**d, "load_cases": [{"name": "a", "supports": [{"edge": "right", "ux": [1.0, 2.0]}]}]}
    with pytest.raises((TypeError, ValueError), match=r"load_cases\[0\]\.supports\[0\]\.ux"):
        cases_from_dict(bad)
