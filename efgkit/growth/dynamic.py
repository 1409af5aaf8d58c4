"""Dynamic crack propagation during an explicit run: prescribed speed or a stress criterion.

:func:`run_growing` integrates a dynamic scene (:func:`~efgkit.explicit.integrate.integrate`)
in chunks; between chunks a tip may gain a segment of length ``da`` (about one node
spacing, nodal release: seed 000 Sect. 5.2.2, seed 002 Sect. 3.1):

* :class:`PrescribedSpeed` (seed 002 Fig. 5): from ``start`` on the tip runs at ``V``:
  advance ``k = 1, 2, ...`` happens at ``t_k = start + (k - 1/2) da / V``, so that the
  discrete tip position is the continuous ``a0 + V (t - start)`` rounded to the nearest
  increment; the ``J'`` of the tip is evaluated at speed ``V`` from ``start`` on.
* :class:`PrincipalStress` (seed 000 Sect. 5.2.2, after Batra and Love): a tip gains a
  segment when the maximum principal stress ``sigma_1 = (s_xx + s_yy) / 2 + sqrt(((s_xx -
  s_yy) / 2)^2 + s_xy^2)`` at the material point ``ahead`` ahead of it (on the tip's x1
  axis) reaches ``sigma_c``; the crack runs straight (the tip frame's x1 axis) to that point
  (``ahead = da``), or with ``direction="principal"`` normal to the direction of
  ``sigma_1`` there (the kink ``theta = angle(n_1) + pi/2 - tip angle``, taken into
  [-pi/2, pi/2); for a mode-I field ahead of the tip it is 0). The speed is the
  least-squares slope over 11 advances (:func:`~efgkit.growth.running_tip.speed_fit`);
  the ``J'`` of a tip uses the fit over its last advances (0 before the second one); a
  speed at or above ``c_R`` stops the run.

At each advance the crack gains its segment (:func:`~efgkit.growth.extend.advance`), the
discretisation and the system are rebuilt in full (:func:`~efgkit.explicit.system.dynamics`
and the critical step :func:`~efgkit.explicit.system.stable_step`: their seconds are in
``timings["rebuild"]``), and the state is carried over to the (unmoved) nodes: by
copying the displacement and velocity coefficients node by node
(:func:`~efgkit.growth.running_tip.copy_state`, default) or by re-fitting them to the old
fields at the nodes (:func:`~efgkit.growth.running_tip.transfer_state`), then imposing the supports of the new
system as :func:`~efgkit.explicit.integrate.initial_state` does. The step ``dt`` stays
the one of the first system; a rebuilt system whose critical step falls below it stops
the run.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..explicit import State, dynamics, integrate, stable_step
from ..problem.history import Stepping
from ..problem.material import strain_from_gradient
from .extend import advance
from .running_tip import MovingTipDSIF, check_speed, copy_state, speed_fit, transfer_state

__all__ = ["DynamicGrowth", "PrescribedSpeed", "PrincipalStress", "principal_stress", "run_growing"]


def _positive(name: str, value, allow_none: bool = True):
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class PrescribedSpeed:
    """Run the tips ``tips`` (ids; None: all) at speed ``speed`` from time ``start`` on, by
    increments ``da`` (None: the method's node spacing). ``0 <= speed < c_R`` is checked
    against the scene's material by :func:`run_growing`."""

    speed: float
    start: float = 0.0
    da: float | None = None
    tips: tuple | None = None

    def __post_init__(self):
        _positive("speed", self.speed, allow_none=False)
        if not (isinstance(self.start, (int, float)) and math.isfinite(self.start) and self.start >= 0):
            raise ValueError(f"start must be a finite time >= 0, got {self.start!r}")
        _positive("da", self.da)


@dataclass(frozen=True)
class PrincipalStress:
    """Nodal release when the maximum principal stress ``ahead`` ahead of a tip reaches
    ``sigma_c`` (seed 000 Sect. 5.2.2), checked every ``check_every`` steps; increments
    ``da`` (None: the node spacing); ``ahead`` None: ``da``; ``direction`` "straight"
    (along the tip) or "principal" (normal to the sigma_1 direction at that point)."""

    sigma_c: float
    da: float | None = None
    ahead: float | None = None
    check_every: int = 1
    tips: tuple | None = None
    direction: str = "straight"

    def __post_init__(self):
        if self.direction not in ("straight", "principal"):
            raise ValueError(f"direction must be 'straight' or 'principal', got {self.direction!r}")
        if isinstance(self.sigma_c, bool) or not isinstance(self.sigma_c, (int, float)):
            raise TypeError(f"sigma_c must be a real number, got {self.sigma_c!r}")
        if not (math.isfinite(self.sigma_c) and self.sigma_c > 0):
            raise ValueError(f"sigma_c = {self.sigma_c!r}: the critical principal stress must be "
                             "finite and > 0 (a tensile strength, stress units of the scene)")
        _positive("da", self.da)
        _positive("ahead", self.ahead)
        if isinstance(self.check_every, bool) or not isinstance(self.check_every, int) \
                or self.check_every < 1:
            raise ValueError(f"check_every must be an int >= 1 (steps), got {self.check_every!r}")


def principal_stress(stress: np.ndarray) -> np.ndarray:
    """Maximum principal stress of Voigt stresses ``(n, 3)`` (xx, yy, xy), shape (n,)."""
    s = np.asarray(stress, float)
    c = 0.5 * (s[:, 0] + s[:, 1])
    return c + np.hypot(0.5 * (s[:, 0] - s[:, 1]), s[:, 2])


@dataclass(frozen=True, eq=False)
class DynamicGrowth:
    """Histories of a run with growing cracks (:func:`run_growing`).

    Attributes
    ----------
    history : dict
        At the output instants: ``t (n_out,)``, ``K (n_out, n_tips, 2)`` (K_I, K_II from
        ``J'``), ``J_prime (n_out, n_tips, 2)``, ``length (n_out, n_tips)`` (extension of
        each tip), ``speed (n_out, n_tips)`` (the ``V`` the J' used). At an advance the
        instant appears twice: before (old crack) and after (new crack, transferred state).
    advances : dict
        One row per advance: ``t (k,)``, ``tip`` (k ids), ``extension (k,)``.
    speeds : dict
        ``{tip id: {"t", "extension", "speed"}}``: the least-squares speed at each advance.
    tips : tuple of str
    stop : str
        Why the run ended.
    scene : Scene
        The last scene (cracks as grown).
    state : State
        The final state (coefficients of the last scene's discretisation).
    info, timings : dict
    """

    history: dict
    advances: dict
    speeds: dict
    tips: tuple
    stop: str
    scene: object
    state: object = None
    info: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)


class _Stress:
    """Stress operator at the points ``ahead`` ahead of each tip of a system."""

    def __init__(self, dyn, ahead: float):
        tips = dyn.disc.scene.tips
        self.ids = [t.id for t in tips]
        x = np.array([t.x + ahead * np.array([math.cos(t.angle), math.sin(t.angle)]) for t in tips])
        self.shape = dyn.disc.shape_at(x, derivatives=True)
        self.angles = np.array([t.angle for t in tips])
        self.D = dyn.disc.scene.material.D

    def sigma1(self, u: np.ndarray) -> tuple[dict, dict]:
        """``({tip id: sigma_1}, {tip id: kink angle normal to the sigma_1 direction})``."""
        s = strain_from_gradient(self.shape.gradient(u)) @ self.D.T
        normal = 0.5 * np.arctan2(2 * s[:, 2], s[:, 0] - s[:, 1]) + 0.5 * np.pi  # crack direction
        kink = (normal - self.angles + 0.5 * np.pi) % np.pi - 0.5 * np.pi  # in [-pi/2, pi/2)
        return (dict(zip(self.ids, principal_stress(s), strict=True)),
                dict(zip(self.ids, kink, strict=True)))


def run_growing(scene, method, rule, stepping: Stepping | None = None, *, radii=None,
                max_advances: int = 1000, transfer: str = "copy") -> DynamicGrowth:
    """Explicit run with cracks that grow by ``rule`` (module docstring).

    Parameters
    ----------
    scene : Scene
        A dynamic scene (``duration``, ``material.rho``) with cracks.
    method : EFG
    rule : PrescribedSpeed or PrincipalStress
    stepping : Stepping, optional
        ``dt`` (default: safety x the critical step of the first system) and the output
        interval (default: 100 instants).
    radii : sequence of float, optional
        J' domain radii (:class:`~efgkit.growth.running_tip.MovingTipDSIF`).
    max_advances : int
        Stop after this many advances (all tips together).
    transfer : {"copy", "refit"}
        How the state crosses a rebuild: copy the coefficients node by node (default,
        :func:`~efgkit.growth.running_tip.copy_state`) or re-fit them to the old fields at
        the nodes (:func:`~efgkit.growth.running_tip.transfer_state`). The re-fit solves
        with the nodal matrix of the new discretisation, whose conditioning near a fresh
        tip can amplify the fields: on the 0.5 mm grid of ``verification/running_crack.py``
        with 0.5 mm increments J' grew about tenfold per advance with it (docs/theory.md).

    Returns
    -------
    DynamicGrowth

    Raises
    ------
    ValueError
        ``rule.speed >= c_R``, an unknown tip id, a static scene; TypeError: a wrong rule.
    """
    if not isinstance(rule, (PrescribedSpeed, PrincipalStress)):
        raise TypeError(f"rule must be a PrescribedSpeed or a PrincipalStress, got {type(rule).__name__}")
    if transfer not in ("refit", "copy"):
        raise ValueError(f"transfer must be 'refit' or 'copy', got {transfer!r}")
    stepping = Stepping() if stepping is None else stepping
    mat = scene.material
    prescribed = isinstance(rule, PrescribedSpeed)
    if prescribed:
        check_speed(rule.speed, mat, "rule.speed")
    ids = [t.id for t in scene.tips]
    active = ids if rule.tips is None else list(rule.tips)
    bad = [k for k in active if k not in ids]
    if bad:
        raise ValueError(f"rule.tips: {bad} are not tips of the scene (tips: {ids})")
    da = float(rule.da or method.spacing)
    t0 = time.perf_counter()
    dyn = dynamics(scene, method)
    crit = stable_step(dyn)
    timings = {"setup": time.perf_counter() - t0, "rebuild": 0.0, "integrate": 0.0, "transfer": 0.0}
    dt = stepping.dt or stepping.safety * crit[0]
    stepping = replace(stepping, dt=dt)
    n_total = math.ceil(scene.duration / dt - 1e-9)
    every = max(1, round((stepping.output_interval or scene.duration / 100) / dt))
    ext = {k: 0.0 for k in ids}
    events = {"t": [], "tip": [], "extension": []}
    hist = {"t": [], "K": [], "J_prime": [], "length": [], "speed": []}
    if prescribed:
        n_start = round(rule.start / dt)
        per = da / rule.speed / dt  # steps per advance
        marks = [n_start] + [round(n_start + (k - 0.5) * per) for k in range(1, max_advances + 1)]
        marks = sorted({m for m in marks if 0 < m < n_total})
    ahead = None if prescribed else float(rule.ahead or da)
    stress = None if prescribed else _Stress(dyn, ahead)
    state, step, stop, n_adv, moved = None, 0, None, 0, False
    hook = MovingTipDSIF(dyn, {}, radii)
    while step < n_total and stop is None:
        if prescribed:
            nxt = next((m for m in marks if m > step), n_total)
            run = {k: rule.speed for k in active} if step >= n_start else {}
        else:
            nxt = min(step + rule.check_every, n_total)
            run = {}
            for k in active:
                mine = [i for i, tip in enumerate(events["tip"]) if tip == k]
                if len(mine) >= 2:
                    sel = mine[-11:]
                    v = float(speed_fit(np.array(events["t"])[sel], np.array(events["extension"])[sel])[-1])
                    if v >= mat.c_rayleigh:
                        stop = f"tip {k}: crack speed {v:.6g} reached c_R = {mat.c_rayleigh:.6g}"
                    run[k] = min(v, 0.999 * mat.c_rayleigh)
            if stop:
                break
        due = prescribed or nxt % every == 0 or nxt == n_total or moved
        hook.set_speeds(run)
        t1 = time.perf_counter()
        sol = integrate(dyn.disc.scene, method,
                        replace(stepping, output_interval=(every if prescribed else nxt - step) * dt),
                        dyn=dyn, state=state, steps=nxt - step, dsif=hook if due else None,
                        critical=crit, progress=False)
        timings["integrate"] += time.perf_counter() - t1
        h = sol.history
        if due:
            keep = np.arange(len(h["t"]))
            if not prescribed:  # the check instants that are output instants, and after a move
                keep = keep[(h["step"] % every == 0) | (h["step"] == n_total)
                            | (moved & (h["step"] == step))]
            if step > 0 and not moved:  # the chunk's first instant closed the previous chunk
                keep = keep[h["step"][keep] > step]
            hist["t"].append(h["t"][keep])
            hist["K"].append(h["sifs"]["J"][keep])
            hist["J_prime"].append(h["sifs"]["J_prime"][keep])
            hist["length"].append(np.tile([ext[k] for k in ids], (len(keep), 1)))
            hist["speed"].append(np.tile([run.get(k, 0.0) for k in ids], (len(keep), 1)))
        moved = False
        state, step = sol.state, nxt
        if step >= n_total:
            break
        if prescribed:
            moves = {k: (da, 0.0) for k in active} if step > n_start else {}
        else:
            s1, kink = stress.sigma1(state.u)
            turn = rule.direction == "principal"
            moves = {k: (da, float(kink[k]) if turn else 0.0) for k in active if s1[k] >= rule.sigma_c}
        if not moves:
            continue
        if n_adv + len(moves) > max_advances:
            stop = f"max_advances = {max_advances} reached"
            break
        adv = advance(dyn.disc.scene, moves, snap=0.0)
        if adv.scene is None or adv.joined:
            stop = adv.stop or "; ".join(adv.events)
            break
        t1 = time.perf_counter()
        new = dynamics(adv.scene, method)
        crit = stable_step(new)
        timings["rebuild"] += time.perf_counter() - t1
        if crit[0] < dt:
            stop = (f"the rebuilt system's critical step {crit[0]:.6g} is below dt = {dt:.6g}: "
                    "give a smaller Stepping.dt")
            break
        t1 = time.perf_counter()
        carry = transfer_state if transfer == "refit" else copy_state
        u, v = carry(dyn.disc, new.disc, state.u, state.v)
        # the supports of the new system at t_n (u) and t_{n-1/2} (the staggered v)
        q1, q0 = new.prescribed(step * dt), new.prescribed(max(step - 1, 0) * dt)
        if new.projection is not None:
            P = new.projection
            u = u - P.correction(u, q1)
            v = v - P.minv_GT @ P.lu.solve(P.G @ v - (q1 - q0) / dt)
        else:
            u[new.fixed] = q1
            v[new.fixed] = (q1 - q0) / dt
        timings["transfer"] += time.perf_counter() - t1
        state = State(state.step, dt, u, v, state.work, None, 0.0, 0.0)
        dyn, moved = new, True
        hook = MovingTipDSIF(dyn, {}, radii)
        if stress is not None:
            stress = _Stress(dyn, ahead)
        for k in moves:
            ext[k] += da
            n_adv += 1
            events["t"].append(step * dt)
            events["tip"].append(k)
            events["extension"].append(ext[k])
    if stop is None:
        stop = f"duration {scene.duration:.6g} reached"
    history = {k: np.concatenate(v) for k, v in hist.items()}
    advances = {"t": np.array(events["t"]), "tip": list(events["tip"]),
                "extension": np.array(events["extension"])}
    speeds = {}
    for k in ids:
        sel = [i for i, tip in enumerate(events["tip"]) if tip == k]
        if len(sel) >= 2:
            t, a = advances["t"][sel], advances["extension"][sel]
            speeds[k] = {"t": t, "extension": a, "speed": speed_fit(t, a)}
    timings["total"] = time.perf_counter() - t0
    info = {"dt": dt, "dt_critical": crit[0], "da": da, "steps": step, "n_advances": n_adv,
            "rebuilds": n_adv if prescribed else len(events["t"]), "c_R": mat.c_rayleigh}
    return DynamicGrowth(history, advances, speeds, tuple(ids), stop, dyn.disc.scene, state, info,
                         timings)
