"""Settings of a crack-growth loop: a frozen description, the ``[growth]`` table of scene files.

Seed 003 Sect. 6 grows cracks by a fixed increment per step along the direction of the
maximum hoop stress (Erdogan and Sih 1963; :mod:`efgkit.fracture.criteria`). With
``criterion="paris"`` the same loop integrates the Paris law for the cycles of each
increment (fatigue).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from ..tables import check_known_keys
from .path_zones import check_path_zones

__all__ = ["CRITERIA", "Growth"]

CRITERIA = ("hoop_stress", "paris")


def _positive(name, v, allow_none=False, integer=False):
    if v is None and allow_none:
        return
    kinds = (int,) if integer else (int, float)
    if isinstance(v, bool) or not isinstance(v, kinds) or not math.isfinite(v) or v <= 0:
        what = "an integer" if integer else "a finite number"
        raise ValueError(f"growth {name} must be {what} > 0{' or None' if allow_none else ''}, "
                         f"got {v!r}")


@dataclass(frozen=True)
class Growth:
    """How cracks grow, step by step.

    Parameters
    ----------
    da : float
        Increment of the leading tip per step (length unit). Seed 003 Sect. 6.2 uses 5 mm in
        the 300 mm DCB; the path converges as da shrinks.
    max_steps : int
        Growth steps at most (solves: ``max_steps + 1``).
    max_length : float, optional
        Stop when a crack is at least this long (total polyline length).
    criterion : {"hoop_stress", "paris"}
        Maximum hoop stress direction with quasi-static load factors, or the same direction
        with Paris-law cycles (fatigue).
    K_Ic : float, optional
        Toughness: each step reports the load factor that brings the most critical tip to
        K_Ic (:func:`~efgkit.fracture.criteria.critical_load_factor`).
    K_threshold : float
        A tip whose K_eq (at the scene's loads) is at or below it does not grow; the loop
        stops when every tip's is (default 0: only closed tips stay).
    stop_unstable : bool
        With K_Ic: stop when the load factor falls from one step to the next (the crack
        would run at a falling load: unstable under the scene's load control).
    paris_C, paris_m : float, optional
        Paris law ``da/dN = C dK^m`` (needed with ``criterion="paris"``).
    R : float
        Load ratio K_min / K_max in [0, 1); the scene's loads are the maximum load.
    dK_th : float
        Threshold range: no growth at or below it.
    adaptive : bool
        Paris: shrink the next increment (down to ``da / 16``) where dK changes by more
        than ``dK_change`` (relative) per step; never above ``da``.
    dK_change : float
        Target relative change of dK per increment for ``adaptive``.
    snap : float
        A tip whose next increment would end within ``snap * da`` of the boundary (an
        outer edge or a hole) runs on to it: that end becomes a mouth.
    sif_error : bool
        Estimate the error of every K (one coarser solve per step,
        :meth:`efgkit.solution.Solution.sifs`); off by default (25 % more per step).
    incremental : bool
        EFG: update K and f from the previous step where the new segment, the moved tip and
        the moved enrichment touch (:mod:`efgkit.growth.incremental`) instead of rebuilding;
        it applies when the node cloud stays (fixed ``zones``, e.g. ``zones=()``, no
        rosette) and the enrichment is ramped or PU, and falls back to a full rebuild
        otherwise. Same K (to rounding), so the same path and SIFs.
    path_zones : sequence of (radius, spacing)
        EFG: node zones along every crack path, re-placed each step
        (:func:`~efgkit.growth.path_zones.path_zones`: discs of that radius and nodal
        spacing every radius / 2 along each crack and at its ends, added to the method's
        zones): refinement that follows the tips and stays where they passed, for cracks
        that pass close to each other or run into a hole beside another crack. Resolve
        the gaps the paths leave: a spacing a few times below the narrowest gap and
        ``da``. Default none.

    Examples
    --------
    >>> Growth(da=5.0, max_steps=10).criterion
    'hoop_stress'
    """

    da: float
    max_steps: int = 20
    max_length: float | None = None
    criterion: str = "hoop_stress"
    K_Ic: float | None = None
    K_threshold: float = 0.0
    stop_unstable: bool = True
    paris_C: float | None = None
    paris_m: float | None = None
    R: float = 0.0
    dK_th: float = 0.0
    adaptive: bool = False
    dK_change: float = 0.05
    snap: float = 0.5
    sif_error: bool = False
    incremental: bool = False
    path_zones: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "path_zones", check_path_zones(self.path_zones))
        _positive("da", self.da)
        _positive("max_steps", self.max_steps, integer=True)
        _positive("max_length", self.max_length, allow_none=True)
        _positive("K_Ic", self.K_Ic, allow_none=True)
        _positive("dK_change", self.dK_change)
        if self.criterion not in CRITERIA:
            raise ValueError(f"growth criterion must be one of {CRITERIA}, got {self.criterion!r}")
        for name in ("K_threshold", "dK_th", "snap"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise ValueError(f"growth {name} must be a finite number >= 0, got {v!r}")
        if isinstance(self.R, bool) or not isinstance(self.R, (int, float)) or not 0 <= self.R < 1:
            raise ValueError(f"growth R (load ratio K_min / K_max) must lie in [0, 1), got {self.R!r}")
        if self.criterion == "paris":
            if self.paris_C is None or self.paris_m is None:
                raise ValueError("growth criterion 'paris' needs paris_C and paris_m "
                                 "(da/dN = C dK^m), got "
                                 f"paris_C={self.paris_C!r}, paris_m={self.paris_m!r}")
            _positive("paris_C", self.paris_C)
            _positive("paris_m", self.paris_m)
        for name in ("stop_unstable", "adaptive", "sif_error", "incremental"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"growth {name} must be a bool, got {getattr(self, name)!r}")

    @classmethod
    def from_dict(cls, d: dict, path: str = "growth") -> Growth:
        """Build from a scene file's ``[growth]`` table: keys are the fields (``da``
        required); errors name ``growth.<key>``.

        Examples
        --------
        >>> Growth.from_dict({"da": 5.0, "max_steps": 3}).max_steps
        3
        """
        if not isinstance(d, dict):
            raise TypeError(f"{path} must be a table, got {d!r}")
        check_known_keys(d, cls.keys(), f"table '{path}'")
        if "da" not in d:
            raise ValueError(f"missing required key 'da' in table '{path}' (the growth increment)")
        types = {f.name: f.type for f in fields(cls)}
        for k, v in d.items():
            want = types[k]
            ok = (isinstance(v, (list, tuple)) if want == "tuple"
                  else isinstance(v, str) if "str" in want else isinstance(v, bool) if "bool" in want
                  else isinstance(v, int) and not isinstance(v, bool) if want == "int"
                  else isinstance(v, (int, float)) and not isinstance(v, bool))
            if not ok:
                raise TypeError(f"{path}.{k} must be {want.replace(' | None', '')}, got {v!r}")
        try:
            return cls(**{k: float(v) if types[k].startswith("float") else v for k, v in d.items()})
        except (ValueError, TypeError) as err:
            raise type(err)(f"{path}: {err}") from err

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        """The field names: the keys of a scene file's ``[growth]`` table."""
        return tuple(f.name for f in fields(cls))
