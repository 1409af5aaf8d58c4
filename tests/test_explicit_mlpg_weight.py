"""The trial weight of explicit MLPG runs (``MLPG.explicit_weight``,
:func:`efgkit.explicit.explicit_mlpg`; docs/theory.md, "Explicit MLPG")."""

import warnings

import pytest

from efgkit import MLPG, Domain, Elastic, Scene
from efgkit.explicit import dynamics, explicit_mlpg, growth_rate
from efgkit.methods.mlpg_file import mlpg_from_dict

SCENE = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.3, "stress", rho=1.0), duration=1.0)
# seed 002 Sect. 4 discs (1.1 h), where the growth rates below were measured; with the static
# default's 1.5 h discs the cubic weight's rate is 4.4 (docs/theory.md, "Explicit MLPG")
SEED_DISCS = dict(weight_k=2, test_radius=1.1)
PG = dict(explicit_form="petrov_galerkin")  # the weight of MLPG1 runs (opt-in)


def test_auto_steps_the_cubic_spline_in_place_of_the_gaussian_and_says_so():
    with pytest.warns(UserWarning, match="trial weight 'gaussian' is replaced by 'cubic'.*"
                      "explicit_weight='same'"):
        dyn = dynamics(SCENE, MLPG(spacing=0.25, **SEED_DISCS, **PG))
    assert dyn.disc.method.weight == "cubic"
    # the Gaussian's fastest mode is a negative real eigenvalue (gamma measured 33.3 on this
    # plate), the cubic weight's a complex pair (gamma 1.0): tests/test_explicit_mlpg_spectrum.py
    assert growth_rate(dyn)[0] < 2.0


def test_same_and_named_weights_are_kept_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert explicit_mlpg(MLPG(spacing=0.25, explicit_weight="same")).weight == "gaussian"
        assert explicit_mlpg(MLPG(spacing=0.25, weight="quartic")).weight == "quartic"
        assert explicit_mlpg(MLPG(spacing=0.25, explicit_weight="quartic")).weight == "quartic"
        m = MLPG(spacing=0.25, explicit_weight="same", **PG)
        assert dynamics(SCENE, m).disc.method.weight == "gaussian"


def test_static_weight_is_untouched():
    # only explicit runs change the weight: the description itself keeps the static default
    m = MLPG(spacing=0.25)
    assert m.weight == "gaussian" and m.explicit_weight == "auto"


def test_bad_explicit_weight_is_refused_with_the_choices():
    with pytest.raises(ValueError, match=r"explicit_weight must be one of \('auto', 'same', "
                       r"'quartic', 'gaussian', 'cubic'\), got 'cubik'"):
        MLPG(spacing=0.25, explicit_weight="cubik")
    with pytest.raises(TypeError, match="method must be an MLPG description, got str"):
        explicit_mlpg("mlpg")


def test_scene_file_key():
    assert mlpg_from_dict({"spacing": 0.25, "explicit_weight": "same"}).explicit_weight == "same"
    with pytest.raises(ValueError, match="mlpg: explicit_weight must be one of"):
        mlpg_from_dict({"spacing": 0.25, "explicit_weight": "spline"})
