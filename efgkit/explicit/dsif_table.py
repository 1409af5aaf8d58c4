"""The ``[dsif]`` table of a scene file: the dynamic-SIF settings of an explicit run.

Keys (docs/scenes.md, "``[dsif]``"):

* ``enrichment_mass``: the lumped mass of the enrichment unknowns (EFG, MLPG's Galerkin form),
  :func:`~efgkit.explicit.system.dynamics` ``enrichment_mass`` (``"diagonal"`` or
  ``"abs_row_sum"``, :mod:`efgkit.system.mass`); default ``"diagonal"``;
* ``mass_iterations``: Jacobi steps of the acceleration recovery of the inertia term of
  ``J'`` (:class:`~efgkit.explicit.dsif.DynamicDSIF`); default 4;
* ``decomposition``: also the K_I, K_II of the decomposition method
  (:class:`~efgkit.explicit.dsif.DynamicDSIF`); default false;
* ``q``: the q-function of the ``J'`` domains, one of :data:`Q_KINDS` (``"plateau_fit"``
  goes with ``face_fit``, :class:`~efgkit.explicit.dsif.DynamicDSIF`); default
  ``"wendland_c2"``;
* ``face_fit``: the near-tip face ``W`` of ``J'_2`` from the fitted face displacement
  (:mod:`efgkit.fracture.face_fit`); default true.

The settings docs/theory.md recommends for ``J'`` path independence with PU enrichment on
coarse grids are ``enrichment_mass = "abs_row_sum"`` and ``mass_iterations = 16``. A
``[dsif]`` table needs a dynamic scene (a ``[time]`` table).

Examples
--------
>>> s = dsif_from_dict({"enrichment_mass": "abs_row_sum", "mass_iterations": 16})
>>> s.enrichment_mass, s.dsif.mass_iterations, s.dsif.decomposition
('abs_row_sum', 16, False)
>>> dsif_from_dict({"mass_iteration": 16})
Traceback (most recent call last):
...
ValueError: unknown key 'mass_iteration' in table 'dsif'; did you mean 'mass_iterations'?
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..fracture.qfunctions import KINDS
from ..system.mass import ENRICHMENT_MASSES
from ..tables import check_known_keys
from .dsif import PLATEAU_FIT, DynamicDSIF, dynamic_dsif

__all__ = ["DSIF_KEYS", "Q_KINDS", "DSIFSettings", "dsif_from_dict", "load_dsif"]

DSIF_KEYS = ("enrichment_mass", "mass_iterations", "decomposition", "q", "face_fit")
Q_KINDS = (*(k for k in KINDS if k != "power"), PLATEAU_FIT)  # "power" needs its exponent


@dataclass(frozen=True)
class DSIFSettings:
    """What a ``[dsif]`` table sets: the enrichment mass of :func:`dynamics` and the hook.

    Parameters
    ----------
    enrichment_mass : str
        ``dynamics(..., enrichment_mass=...)``: one of ``ENRICHMENT_MASSES``.
    dsif : DynamicDSIF
        ``integrate(..., dsif=...)``.
    """

    enrichment_mass: str = "diagonal"
    dsif: DynamicDSIF = field(default_factory=lambda: dynamic_dsif)

    def __post_init__(self):
        if self.enrichment_mass not in ENRICHMENT_MASSES:
            raise ValueError(f"enrichment_mass must be one of {', '.join(map(repr, ENRICHMENT_MASSES))}, "
                             f"got {self.enrichment_mass!r}")
        if not isinstance(self.dsif, DynamicDSIF):
            raise TypeError(f"dsif must be a DynamicDSIF, got {type(self.dsif).__name__}")


def dsif_from_dict(d, path: str = "dsif") -> DSIFSettings:
    """The :class:`DSIFSettings` of a scene file's ``[dsif]`` table (module docstring).

    Raises
    ------
    ValueError, TypeError
        An unknown key (with the nearest valid one), a value of the wrong type or out of
        range; the message names the key path (``dsif.mass_iterations``).
    """
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table [dsif], got {d!r}")
    check_known_keys(d, DSIF_KEYS, f"table {path!r}")
    em = d.get("enrichment_mass", "diagonal")
    if not isinstance(em, str):
        raise TypeError(f"{path}.enrichment_mass must be a string, one of "
                        f"{', '.join(map(repr, ENRICHMENT_MASSES))}; got {em!r}")
    if em not in ENRICHMENT_MASSES:
        raise ValueError(f"{path}.enrichment_mass = {em!r}; expected one of "
                         f"{', '.join(map(repr, ENRICHMENT_MASSES))}")
    k = d.get("mass_iterations", DynamicDSIF.mass_iterations)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
        raise TypeError(f"{path}.mass_iterations must be an integer in 0..100, got {k!r}")
    dec = d.get("decomposition", False)
    if not isinstance(dec, bool):
        raise TypeError(f"{path}.decomposition must be true or false, got {dec!r}")
    fit = d.get("face_fit", True)
    if not isinstance(fit, bool):
        raise TypeError(f"{path}.face_fit must be true or false, got {fit!r}")
    q = d.get("q", DynamicDSIF.q)
    if q not in Q_KINDS:
        raise ValueError(f"{path}.q = {q!r}; expected one of {', '.join(map(repr, Q_KINDS))}")
    try:
        hook = DynamicDSIF(mass_iterations=int(k), decomposition=dec, q=q, face_fit=fit)
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}.mass_iterations: {err}") from err
    return DSIFSettings(em, hook)


def load_dsif(path) -> DSIFSettings:
    """The ``[dsif]`` settings of a scene file; the defaults when it has no ``[dsif]`` table.

    Raises
    ------
    ValueError
        A ``[dsif]`` table in a static scene (no ``[time]`` table), or a bad key (prefixed
        with the file path).
    """
    import tomllib

    with open(path, "rb") as fh:
        d = tomllib.load(fh)
    if "dsif" not in d:
        return DSIFSettings()
    try:
        if "time" not in d and "duration" not in d:
            raise ValueError("a [dsif] table sets the dynamic SIFs of an explicit run: add a "
                             "[time] table or remove [dsif]")
        return dsif_from_dict(d["dsif"])
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}: {err}") from err
