"""Loads in time: load factors ``g(t)`` and the settings of an explicit run.

A load with a history is ``g(t) * load(x)``: a :class:`~efgkit.problem.scene.Traction`
or the body force of a :class:`~efgkit.problem.scene.Scene` with ``history=None`` is
constant in time (a static load; in a dynamic run it acts from ``t = 0`` on, i.e. a
Heaviside step at 0). Every history is a frozen dataclass callable as ``g(t)`` on a float
or an array of times, and writes itself to a scene file with :meth:`as_dict`
(``{ kind = ..., ... }``, read back by :func:`history_from_dict`).

:class:`Stepping` holds how a dynamic scene is integrated (the ``[time]`` table of a
scene file, except ``duration``, which belongs to the scene).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

__all__ = ["HISTORIES", "STEPPING_KEYS", "Heaviside", "ImpactPulse", "Linear", "Ramp", "Stepping",
           "Tabulated", "history_from_dict", "stepping_from_dict", "with_time_table"]


def _finite(name: str, v, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a number, got {v!r}")
    if not math.isfinite(v) or (positive and v <= 0):
        raise ValueError(f"{name} must be finite{' and > 0' if positive else ''}, got {v!r}")
    return float(v)


class _History:
    """g(t) on a float (-> float) or on an array of times (-> array of the same shape)."""

    kind = "?"

    def __call__(self, t):
        v = self.values(np.asarray(t, dtype=float))
        return float(v) if np.ndim(v) == 0 else v

    def values(self, t: np.ndarray) -> np.ndarray:  # pragma: no cover - every history defines it
        raise NotImplementedError

    def as_dict(self) -> dict:
        """The scene-file table ``{kind = ..., <fields>}``."""
        out = {"kind": self.kind}
        for f in fields(self):
            v = getattr(self, f.name)
            out[f.name] = list(v) if isinstance(v, tuple) else v
        return out


@dataclass(frozen=True)
class Heaviside(_History):
    """Step ``g(t) = 0`` for ``t < t0``, ``1`` from ``t0`` on.

    Examples
    --------
    >>> Heaviside(1e-6)(0.5e-6), Heaviside(1e-6)(1e-6)
    (0.0, 1.0)
    """

    t0: float = 0.0
    kind = "heaviside"

    def __post_init__(self):
        _finite("Heaviside: t0", self.t0)

    def values(self, t):
        return np.where(t >= self.t0, 1.0, 0.0)


@dataclass(frozen=True)
class Ramp(_History):
    """Linear rise: 0 before ``t0``, ``(t - t0) / (t1 - t0)`` between, 1 after ``t1``.

    Examples
    --------
    >>> Ramp(0.0, 2.0)(0.5)
    0.25
    """

    t0: float = 0.0
    t1: float = 1.0
    kind = "ramp"

    def __post_init__(self):
        _finite("Ramp: t0", self.t0)
        _finite("Ramp: t1", self.t1)
        if not self.t1 > self.t0:
            raise ValueError(f"Ramp: t1 = {self.t1!r} must be after t0 = {self.t0!r}; for a step use "
                             "Heaviside(t0)")

    def values(self, t):
        return np.clip((t - self.t0) / (self.t1 - self.t0), 0.0, 1.0)


@dataclass(frozen=True)
class Tabulated(_History):
    """Piecewise-linear factor through ``(t[k], factor[k])``, constant beyond the ends.

    Examples
    --------
    >>> g = Tabulated((0.0, 1.0, 2.0), (0.0, 1.0, 0.0))
    >>> g(0.5), g(3.0)
    (0.5, 0.0)
    """

    t: tuple[float, ...] = (0.0,)
    factor: tuple[float, ...] = (1.0,)
    kind = "tabulated"

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float)
        g = np.asarray(self.factor, dtype=float)
        if t.ndim != 1 or g.shape != t.shape or len(t) < 1:
            raise ValueError(f"Tabulated: t and factor must be two lists of the same length >= 1, "
                             f"got {len(np.atleast_1d(t))} times and {len(np.atleast_1d(g))} factors")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(g))):
            raise ValueError("Tabulated: t and factor must be finite")
        if np.any(np.diff(t) <= 0):
            k = int(np.flatnonzero(np.diff(t) <= 0)[0])
            raise ValueError(f"Tabulated: times must increase strictly; t[{k}] = {t[k]!r} and "
                             f"t[{k + 1}] = {t[k + 1]!r}")
        object.__setattr__(self, "t", tuple(map(float, t)))
        object.__setattr__(self, "factor", tuple(map(float, g)))

    def values(self, t):
        return np.interp(t, self.t, self.factor)


@dataclass(frozen=True)
class ImpactPulse(_History):
    """The impact pulse of seed 002 Eq. (40), shifted so that it starts from rest.

    Printed: ``p(t) = [1 - 0.5 s^2] exp(-s^2)`` with ``s = (t - centre) / scale``
    (``centre = 2.5 us``, ``scale = 1 us`` in the seed: ``s = 10^6 t - 2.5``). It is
    ``-0.0041`` at ``t = 0`` (seed README), a jump from the rest state the seed assumes.
    Here the pulse is ``g = (p - p_0) / (1 - p_0)`` on ``0 <= t <= 2 centre`` and 0 outside,
    with ``p_0 = p(0) = p(2 centre)``: continuous at both ends, peak 1 at ``t = centre``
    (the printed peak is 1, so the shape differs from the seed's by at most 0.4 % of the
    peak). ``shifted=False`` gives the printed p(t) for ``t >= 0`` unchanged.

    Examples
    --------
    >>> g = ImpactPulse()
    >>> g(0.0), g(2.5e-6), round(ImpactPulse(shifted=False)(0.0), 4)
    (0.0, 1.0, -0.0041)
    """

    centre: float = 2.5e-6
    scale: float = 1e-6
    shifted: bool = True
    kind = "pulse"

    def __post_init__(self):
        _finite("ImpactPulse: centre", self.centre, positive=True)
        _finite("ImpactPulse: scale", self.scale, positive=True)
        if not isinstance(self.shifted, bool):
            raise TypeError(f"ImpactPulse: shifted must be true or false, got {self.shifted!r}")

    def _raw(self, t):
        s = (t - self.centre) / self.scale
        return (1.0 - 0.5 * s * s) * np.exp(-s * s)

    def values(self, t):
        if not self.shifted:
            return np.where(t >= 0.0, self._raw(t), 0.0)
        p0 = float(self._raw(0.0))
        inside = (t >= 0.0) & (t <= 2.0 * self.centre)
        return np.where(inside, (self._raw(t) - p0) / (1.0 - p0), 0.0)


@dataclass(frozen=True)
class Linear(_History):
    """Unbounded linear rise ``g(t) = rate * max(t - t0, 0)``: a prescribed displacement
    ``ubar * g(t)`` moves at the constant velocity ``rate * ubar`` from ``t0`` on (an edge
    pulled at a nominal strain rate: ``Support("top", uy=v0, history=Linear())`` gives
    ``u_y = v0 t``). ``rate`` has units 1/time times those of the factor.

    Examples
    --------
    >>> Linear()(2.0), Linear(rate=3.0, t0=1.0)(0.5), Linear(rate=3.0, t0=1.0)(2.0)
    (2.0, 0.0, 3.0)
    """

    rate: float = 1.0
    t0: float = 0.0
    kind = "linear"

    def __post_init__(self):
        _finite("Linear: rate", self.rate)
        _finite("Linear: t0", self.t0)

    def values(self, t):
        return self.rate * np.maximum(t - self.t0, 0.0)


HISTORIES = {c.kind: c for c in (Heaviside, Ramp, Tabulated, ImpactPulse, Linear)}


def history_from_dict(d, path: str = "history"):
    """A history from its scene-file table ``{kind = "heaviside" | "ramp" | "tabulated" |
    "pulse" | "linear", <fields>}``; errors name ``path``.

    Examples
    --------
    >>> history_from_dict({"kind": "ramp", "t0": 0.0, "t1": 1e-6})
    Ramp(t0=0.0, t1=1e-06)
    """
    if not isinstance(d, dict):
        raise TypeError(f"{path} must be a table {{ kind = ..., ... }}, got {d!r}")
    kind = d.get("kind")
    if kind not in HISTORIES:
        raise ValueError(f"{path}: kind must be one of {sorted(HISTORIES)}, got {kind!r}")
    cls = HISTORIES[kind]
    names = [f.name for f in fields(cls)]
    unknown = sorted(set(d) - set(names) - {"kind"})
    if unknown:
        raise ValueError(f"{path}: unknown key {unknown[0]!r} for kind {kind!r}; valid keys: "
                         f"kind, {', '.join(names)}")
    kw = {k: tuple(v) if isinstance(v, list) else v for k, v in d.items() if k != "kind"}
    try:
        return cls(**kw)
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}: {err}") from err


def _probes(v) -> np.ndarray:
    p = np.asarray(v, dtype=float).reshape(-1, 2) if len(np.ravel(v)) else np.zeros((0, 2))
    return p


@dataclass(frozen=True)
class Stepping:
    """How a dynamic scene is integrated in time (the ``[time]`` table without ``duration``).

    Parameters
    ----------
    dt : float, optional
        Time step. Default: ``safety`` times the critical step ``2 / omega_max`` estimated
        from the assembled matrices (seed 002 Eqs. 29-30). A ``dt`` above the critical step
        is refused unless ``force=True``.
    safety : float
        Fraction of the critical step taken when ``dt`` is not given (0 < safety <= 1).
    output_interval : float, optional
        Time between recorded instants (default: 100 output instants over the duration).
    probes : tuple of (x, y)
        Points where displacement, velocity and stress are recorded.
    force : bool
        Run with a ``dt`` above the estimated critical step (for stability studies).
    vtu : bool
        Write a VTU time series (a ``.pvd`` collection, readable by ParaView).
    snapshots : int
        Number of stress snapshot figures, evenly spread over the output instants.
    """

    dt: float | None = None
    safety: float = 0.9
    output_interval: float | None = None
    probes: tuple = ()
    force: bool = False
    vtu: bool = False
    snapshots: int = 0

    def __post_init__(self):
        if self.dt is not None:
            _finite("dt", self.dt, positive=True)
        s = _finite("safety", self.safety, positive=True)
        if s > 1:
            raise ValueError(f"safety must lie in (0, 1], got {s!r}: a larger step is taken "
                             "by giving dt with force=true")
        if self.output_interval is not None:
            _finite("output_interval", self.output_interval, positive=True)
        try:
            p = _probes(self.probes)
        except (TypeError, ValueError) as err:
            raise ValueError(f"probes must be a list of [x, y] points, got {self.probes!r}") from err
        if not np.all(np.isfinite(p)):
            raise ValueError("probes must be finite")
        object.__setattr__(self, "probes", tuple(map(tuple, p.tolist())))
        for name in ("force", "vtu"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"{name} must be true or false, got {getattr(self, name)!r}")
        if isinstance(self.snapshots, bool) or not isinstance(self.snapshots, int) or self.snapshots < 0:
            raise ValueError(f"snapshots must be an integer >= 0, got {self.snapshots!r}")

    @property
    def probe_points(self) -> np.ndarray:
        """The probes as an array (n_probes, 2)."""
        return _probes(self.probes)


STEPPING_KEYS = ("dt", "safety", "output_interval", "probes", "force", "vtu", "snapshots")


def _time_keys(t, path: str) -> None:
    if not isinstance(t, dict):
        raise TypeError(f"{path} must be a table [time], got {t!r}")
    if "duration" not in t:
        raise ValueError(f"missing required key 'duration' in table {path!r}")
    unknown = sorted(set(t) - set(STEPPING_KEYS) - {"duration"})
    if unknown:
        raise ValueError(f"unknown key {unknown[0]!r} in table {path!r}; valid keys: duration, "
                         f"{', '.join(STEPPING_KEYS)}")


def with_time_table(d: dict) -> dict:
    """A scene-file dict with the ``duration`` of its ``[time]`` table at the top level
    (where :class:`~efgkit.problem.scene.Scene` takes it); unchanged without ``[time]``."""
    if "time" not in d:
        return d
    if "duration" in d:
        raise ValueError("duration is given twice, at the top level and in [time]; keep the one "
                         "in [time]")
    _time_keys(d["time"], "time")
    return {**d, "duration": d["time"]["duration"]}


def stepping_from_dict(d: dict, path: str = "time") -> Stepping:
    """The :class:`Stepping` of a scene file's ``[time]`` table (its ``duration`` belongs to
    the scene: :func:`with_time_table`).

    Examples
    --------
    >>> stepping_from_dict({"duration": 1e-5, "safety": 0.8, "probes": [[0.0, 1.0]]}).probes
    ((0.0, 1.0),)
    """
    _time_keys(d, path)
    try:
        return Stepping(**{k: v for k, v in d.items() if k != "duration"})
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}: {err}") from err
