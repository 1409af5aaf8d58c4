"""The trial weight of explicit MLPG1 runs (``MLPG.explicit_weight``; MLPG1 explicit runs are
opt-in: ``MLPG(explicit_form="petrov_galerkin")``).

MLPG1 pairs the quartic-spline test function of the disc (seed 002 Eq. 8) with the MLS trial
functions. Away from the boundary its ``M^-1 K`` is translation invariant, and its Fourier
symbol (:func:`~efgkit.explicit.spectrum.row_symbol`) carries the product of the transforms
of the test and trial functions: with the Gaussian trial weight (seed 002 Eq. 7,
c = 0.5 r_I) it is negative at the checkerboard (-0.061 lambda_max with k = 2 and the
seed's 1.1 h discs; -0.011 with k = 1, MLPG's static default), so ``M^-1 K``
has negative real eigenvalues, whose modes grow like ``exp(sqrt(-lambda) t)`` at any step
(gamma ~ 1/h). The cubic-spline weight's symbol is non-negative (its minimum is the 0 of
the rigid translations); complex pairs with small imaginary parts remain near the
boundary (docs/theory.md, "Explicit MLPG"). Measured on the 2 x 1 plates of
``verification/stability.py`` (h = 0.125) the growth rate falls 15-200 fold (free: 126 to
0.97); on a thin bar held by the modified MLS, whose growing pair sits at that boundary,
not at all (6.2 and 6.3, ``tests/test_explicit_mlpg.py``). Neither weight makes MLPG1
stable in general: docs/theory.md. Static solves are not concerned (no time stepping):
they keep ``MLPG.weight``.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

from ..methods.mlpg import MLPG

__all__ = ["EXPLICIT_AUTO_WEIGHT", "explicit_mlpg"]

EXPLICIT_AUTO_WEIGHT = "cubic"  # what explicit_weight="auto" puts in place of the Gaussian


def explicit_mlpg(method: MLPG, warn: bool = True) -> MLPG:
    """``method`` with the trial weight of explicit runs (``method.explicit_weight``).

    ``"auto"``: with ``explicit_form="petrov_galerkin"`` (MLPG1) the Gaussian becomes the
    cubic spline (module docstring), with a ``UserWarning`` saying so when ``warn``; the
    quartic and cubic splines stay, and so does every weight with the Galerkin form
    (``explicit_form`` "galerkin" or "auto", :mod:`~efgkit.explicit.galerkin_form`: a
    symmetric K).
    ``"same"``: ``method.weight``. A weight name: that weight.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     explicit_mlpg(MLPG(spacing=0.1, explicit_form="petrov_galerkin")).weight
    'cubic'
    >>> explicit_mlpg(MLPG(spacing=0.1)).weight   # the default Galerkin form keeps it
    'gaussian'
    >>> explicit_mlpg(MLPG(spacing=0.1, explicit_weight="same")).weight
    'gaussian'
    >>> explicit_mlpg(MLPG(spacing=0.1, weight="quartic")).weight
    'quartic'
    """
    if not isinstance(method, MLPG):
        raise TypeError(f"method must be an MLPG description, got {type(method).__name__}")
    choice = method.explicit_weight
    if choice == "same":
        return method
    if choice != "auto":
        return replace(method, weight=choice)
    if method.weight != "gaussian" or method.explicit_form != "petrov_galerkin":
        return method
    if warn:
        warnings.warn(
            "explicit MLPG: the trial weight 'gaussian' is replaced by "
            f"'{EXPLICIT_AUTO_WEIGHT}' for this run (MLPG.explicit_weight='auto'): with the "
            "Gaussian, M^-1 K of MLPG1 has negative real eigenvalues whose modes grow at any "
            "time step (a free 2 x 1 plate at h = 0.125 blows up after 38 steps at 0.98 dt_c, "
            "against 1882 with the cubic spline; docs/theory.md, 'Explicit MLPG'). Static "
            "solves keep 'gaussian'. To step the Gaussian anyway give "
            "MLPG(explicit_weight='same') (scene file: [mlpg] explicit_weight = \"same\"); "
            "for runs stable at any length the Galerkin form (MLPG's default for explicit "
            "runs, explicit_form='auto' or 'galerkin')",
            UserWarning, stacklevel=4)
    return replace(method, weight=EXPLICIT_AUTO_WEIGHT)
