"""The Galerkin form of explicit MLPG runs (``MLPG.explicit_form="galerkin"``,
:mod:`efgkit.explicit.galerkin_form`): symmetric K, masses adding up to rho * area, the
spectrum of M^-1 K real and non-negative, bounded runs with a conserved energy."""

import warnings

import numpy as np
import pytest

from efgkit import EFG, MLPG, Crack, Domain, Elastic, Scene, Support
from efgkit.explicit import InstabilityError, dense_operator, dynamics, integrate, stable_step
from efgkit.explicit.galerkin_form import galerkin_discretization, resolve_form
from efgkit.methods.discretize import discretize
from efgkit.methods.local import discretize_local
from efgkit.methods.mlpg_file import mlpg_from_dict
from efgkit.problem.history import Stepping

MAT = Elastic(1000.0, 0.3, "stress", rho=2.0)
INIT = dict(initial_displacement=lambda x: np.column_stack([0.01 * x[:, 0] ** 2, 0.005 * x[:, 0] * x[:, 1]]),
            initial_velocity=(0.0, 0.01), duration=1.0)
CLAMP = (Support("left", ux=0.0, uy=0.0),)


@pytest.mark.parametrize("bc", ["free", "modified_mls", "penalty", "collocation"])
def test_spectrum_is_real_and_non_negative_and_runs_stay_bounded(bc):
    # by construction (module docstring): K symmetric positive semi-definite, M positive
    # diagonal, so M^-1 K has real eigenvalues >= 0; the Gaussian weight (the static default,
    # kept: explicit_weight="auto" changes it for the Petrov-Galerkin form only)
    scene = Scene(Domain.rectangle(0, 0, 2, 1), MAT, supports=() if bc == "free" else CLAMP, **INIT)
    method = MLPG(spacing=0.25, explicit_form="galerkin", **({} if bc == "free" else {"bc": bc}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no weight replacement, no warning
        dyn = dynamics(scene, method)
    assert dyn.disc.method.weight == "gaussian" and dyn.disc.test is None
    K = dyn.K.toarray()
    assert np.abs(K - K.T).max() <= 1e-14 * np.abs(K).max()  # round-off: measured 1e-16
    # row sums of the Galerkin consistent mass: rho times the area per component
    assert dyn.m[0::2].sum() == pytest.approx(MAT.rho * 2.0, rel=1e-12)
    dtc, lam = stable_step(dyn)
    free = dyn.minv > 0
    ev = np.linalg.eigvals(dense_operator(dyn)[np.ix_(free, free)])
    assert np.abs(ev.imag).max() <= 1e-10 * lam and ev.real.min() >= -1e-10 * lam
    sol = integrate(scene, method, Stepping(dt=0.98 * dtc), dyn=dyn, steps=300, dsif=None,
                    critical=(dtc, lam))
    # measured drift 1.4e-15 - 5.8e-15 over 300 steps (verification/stability.py: 1e4 steps)
    assert sol.info["steps"] == 300 and sol.info["energy_drift"] < 2e-14
    with pytest.raises(InstabilityError, match="is 1.0200 of the estimated critical step"):
        integrate(scene, method, Stepping(dt=1.02 * dtc, force=True), dyn=dyn, steps=300,
                  dsif=None, critical=(dtc, lam))


def test_crack_face_pressure_loads_the_faces():
    # a pressure p on both faces: the load is self-equilibrated (the nodal shape functions are
    # a partition of unity on each face: exact), and the nodes on each face (split on the crack)
    # are pushed away from it; each face's total p a (2.0) is spread over nodes on both sides
    # near the tip (diffraction, the explicit default), so it is checked on the split nodes' sign only
    p, a = 2.0, 1.0
    scene = Scene(Domain.rectangle(0, -1, 2, 1), MAT, duration=1.0,
                  cracks=(Crack([[0.0, 0.0], [a, 0.0]], tips=(False, True), pressure=p),))
    dyn = dynamics(scene, MLPG(spacing=0.25, explicit_form="galerkin"))
    Fy = dyn.F[1::2, 0]
    assert abs(Fy.sum()) <= 1e-12 * p * a
    x, face = dyn.disc.nodes.x, dyn.disc.nodes.face
    sel = (face != 0) & (x[:, 0] > 0.2) & (x[:, 0] < 0.7)
    assert sel.sum() == 4 and np.all(np.sign(Fy[sel]) == face[sel])


def test_explicit_runs_default_to_the_galerkin_form_and_say_so():
    # explicit_form="auto" (the default): the Galerkin form, with a warning naming the opt-in
    # MLPG1 form; "galerkin" given: silent; "petrov_galerkin": MLPG1 (unsymmetric K)
    scene = Scene(Domain.rectangle(0, 0, 2, 1), MAT, **INIT)
    with pytest.warns(UserWarning, match=r"steps the symmetric Galerkin form of MLPG's trial "
                      r"functions .*explicit_form='galerkin'.* to silence this, or "
                      r"explicit_form='petrov_galerkin' to step MLPG1"):
        dyn = dynamics(scene, MLPG(spacing=0.25))
    assert dyn.form == "galerkin" and dyn.disc.test is None and dyn.disc.method.weight == "gaussian"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        given = dynamics(scene, MLPG(spacing=0.25, explicit_form="galerkin"))
    np.testing.assert_array_equal(given.K.toarray(), dyn.K.toarray())
    with pytest.warns(UserWarning, match="trial weight 'gaussian' is replaced by 'cubic'"):
        pg = dynamics(scene, MLPG(spacing=0.25, explicit_form="petrov_galerkin"))
    assert pg.form == "petrov_galerkin" and pg.disc.test is not None
    sol = integrate(scene, MLPG(spacing=0.25, explicit_form="galerkin"), dyn=given, steps=2,
                    dsif=None)
    assert sol.info["form"] == "galerkin" and "MLPG form galerkin" in sol.summary()
    with pytest.raises(TypeError, match="method must be an MLPG description, got EFG"):
        resolve_form(EFG(spacing=0.25))


def test_enrichment_is_taken_by_the_galerkin_form_only():
    # the Galerkin form's enrichment rows are those of EFG: masses as for EFG (diagonal of the
    # consistent block, or abs row sum); MLPG1's enrichment rows have no sub-domain mass
    scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.3, "strain", rho=2.0),
                  supports=CLAMP, cracks=(Crack([[0.0, 0.5], [1.0, 0.5]], tips=(False, True)),),
                  **INIT)
    method = MLPG(spacing=0.25, explicit_form="galerkin", enrichment="extrinsic_mls",
                  crack_rule="diffraction")
    disc = discretize_local(scene, method)  # once for both masses
    dyn = dynamics(scene, method, disc)
    assert dyn.n_dofs == 2 * dyn.disc.nodes.n + 2 and np.all(dyn.m > 0)
    K = dyn.K.toarray()
    assert np.abs(K - K.T).max() <= 1e-14 * np.abs(K).max()
    row = dynamics(scene, method, disc, enrichment_mass="abs_row_sum")
    np.testing.assert_array_equal(row.m[:-2], dyn.m[:-2])  # nodal masses unchanged
    assert np.all(row.m[-2:] >= dyn.m[-2:])  # |row sum| >= its diagonal entry
    with pytest.raises(ValueError, match=r"explicit MLPG1 \(explicit_form='petrov_galerkin'\) "
                       "runs without tip enrichment only"):
        dynamics(scene, MLPG(spacing=0.25, enrichment="pu", explicit_form="petrov_galerkin"))


def test_bad_input():
    with pytest.raises(ValueError, match=r"explicit_form must be one of \('auto', "
                       r"'petrov_galerkin', 'galerkin'\), got 'bubnov'"):
        MLPG(spacing=0.25, explicit_form="bubnov")
    efg = discretize(Scene(Domain.rectangle(0, 0, 1, 1), MAT), EFG(spacing=0.5))
    with pytest.raises(ValueError, match="disc must be an MLPG discretisation"):
        galerkin_discretization(efg)


def test_galerkin_runs_take_the_explicit_trial_functions():
    # explicit_crack_rule / explicit_weight_k = "auto": the Galerkin form takes diffraction and
    # the seed's k = 2 (seed 002 Eq. 7) in place of visibility and k = 1 (Freund's K_I(t),
    # docs/theory.md "Explicit MLPG"), named in the one warning of explicit_form="auto";
    # static solves and MLPG1 keep the static fields; "same" keeps them too
    crack = (Crack([[0.0, 0.5], [1.0, 0.5]], tips=(False, True)),)
    cracked = Scene(Domain.rectangle(0, 0, 2, 1), MAT, cracks=crack, **INIT)
    with pytest.warns(UserWarning, match=r"Its trial functions take crack_rule='diffraction' in "
                      r"place of 'visibility' and the Gaussian exponent k = 2 in place of 1 ") as rec:
        dyn = dynamics(cracked, MLPG(spacing=0.25))
    assert len(rec) == 1  # one warning, not two
    assert (dyn.disc.method.crack_rule, dyn.disc.method.weight_k) == ("diffraction", 2)
    assert (MLPG(spacing=0.25).crack_rule, MLPG(spacing=0.25).weight_k) == ("visibility", 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        given = dynamics(cracked, MLPG(spacing=0.25, explicit_form="galerkin"))
        same = dynamics(cracked, MLPG(spacing=0.25, explicit_form="galerkin",
                                      explicit_crack_rule="same", explicit_weight_k="same"))
        named = resolve_form(MLPG(spacing=0.25, explicit_form="petrov_galerkin",
                                  explicit_crack_rule="transparency", explicit_weight_k=3))
    np.testing.assert_array_equal(given.K.toarray(), dyn.K.toarray())
    assert (same.disc.method.crack_rule, same.disc.method.weight_k) == ("visibility", 1)
    assert (named.crack_rule, named.weight_k) == ("transparency", 3)  # named: any form
    pg = resolve_form(MLPG(spacing=0.25, explicit_form="petrov_galerkin"))
    assert (pg.crack_rule, pg.weight_k) == ("visibility", 1)
    # without cracks the warning names the exponent only; other user values stay
    with pytest.warns(UserWarning, match=r"take the Gaussian exponent k = 2 in place of 1 "):
        resolve_form(MLPG(spacing=0.25), cracked=False)
    kept = resolve_form(MLPG(spacing=0.25, weight_k=3, crack_rule="see_through"), warn=False)
    assert (kept.crack_rule, kept.weight_k) == ("see_through", 3)
    assert resolve_form(MLPG(spacing=0.25), warn=False, trial=False).weight_k == 1


def test_explicit_trial_fields_bad_input():
    with pytest.raises(ValueError, match=r"explicit_crack_rule must be one of \('auto', 'same', "
                       r"'visibility', .*got 'difraction': give 'auto'"):
        MLPG(spacing=0.25, explicit_crack_rule="difraction")
    with pytest.raises(ValueError, match=r"explicit_crack_rule='transparency' needs rule_power "
                       r">= 2 \(seed 003 Eq. 32\), got rule_power=1.0: give rule_power=2"):
        MLPG(spacing=0.25, explicit_crack_rule="transparency", rule_power=1.0)
    for bad, err in ((0, ValueError), ("two", ValueError), (2.0, TypeError), (True, TypeError)):
        with pytest.raises(err, match=rf"explicit_weight_k must be 'auto', 'same' or an integer "
                           rf"> 0, got {bad!r}: give 'auto'"):
            MLPG(spacing=0.25, explicit_weight_k=bad)
    # scene files: [mlpg] keys (efgkit.methods.mlpg_file), checked by MLPG itself
    m = mlpg_from_dict({"spacing": 0.25, "explicit_crack_rule": "same", "explicit_weight_k": 3})
    assert (m.explicit_crack_rule, m.explicit_weight_k) == ("same", 3)
    with pytest.raises(ValueError, match="mlpg: explicit_weight_k must be 'auto', 'same' or an "
                       "integer > 0, got -1"):
        mlpg_from_dict({"spacing": 0.25, "explicit_weight_k": -1})
