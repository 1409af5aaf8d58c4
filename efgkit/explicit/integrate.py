"""Central differences on ``M u'' + K u = f(t)``, seed 002 Eq. (28).

With staggered velocities ``v^{n+1/2}`` (M the lumped mass, diagonal):

    a^n = M^-1 (f(t_n) - K u^n)
    v^{n+1/2} = v^{n-1/2} + dt a^n
    u^{n+1} = u^n + dt v^{n+1/2}          (then the constraint projection, if any)

Each step is one sparse product ``K u``, the load factors, two compiled passes over the
unknowns (the update, then the energies) and, with Lagrange constraints, a product with the
few constraint rows: no assembly, no search, no Python loop over nodes.

Energy. For the unforced scheme the modified energy

    E~^{n+1/2} = 1/2 v^{n+1/2} . M v^{n+1/2} + 1/2 u^{n+1} . K u^n

is conserved exactly (in exact arithmetic; proof in docs/theory.md), and with loads
``E~^{n+1/2} - E~^{n-1/2} = f^n . (u^{n+1} - u^{n-1}) / 2``: the time-centred work
``W``. The balance ``E~ - W`` is constant up to round-off; its drift relative to the
largest of ``|E~|`` and ``|W|`` over the run is reported. Instability is detected by the
kinetic energy outgrowing the energy put in, ``|E~^{1/2} - W^{1/2}| + |W|``, 1e3-fold (E~
itself stays constant even in an unstable run, where it is indefinite; with the
unsymmetric K of MLPG a growing mode drags E~ along, so the running scale would not do).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..methods.efg import EFG
from ..methods.mlpg import MLPG
from ..problem.graded import refuse_grading
from ..problem.history import Stepping
from ..problem.scene import Scene
from ..timing import watch_compiles
from .dsif import dynamic_dsif
from .output import Recorder
from .result import DynamicSolution
from .spectrum import stable_step
from .system import Dynamics, dynamics, fit_coefficients

__all__ = ["BLOWUP_FACTOR", "InstabilityError", "State", "integrate", "initial_state", "load_stepping"]

watch_compiles()  # before anything here compiles

BLOWUP_FACTOR = 1e3  # kinetic energy over the energy put in that means instability
_MLPG_REMEDY = ("the unsymmetric MLPG1 K has modes that grow at any step "
                "(efgkit.explicit.growth_rate gives their rate): a shorter run, "
                "MLPG(explicit_weight='cubic') if the Gaussian was stepped (no negative real "
                "eigenvalues: slower growth), the Galerkin form (MLPG's default for explicit "
                "runs: explicit_form='auto' or 'galerkin'; the symmetric form of the same trial "
                "functions: stable), or EFG (docs/theory.md, "
                "'Explicit MLPG')")


class InstabilityError(ArithmeticError):
    """The time integration blew up (step above the critical step, growing modes of an
    unsymmetric K, or broken matrices).

    Attributes ``step`` and ``t``: where it was detected; ``ratio``: kinetic energy over
    the energy put in (initial energy + work done)."""

    def __init__(self, message: str, step: int, t: float, ratio: float):
        super().__init__(message)
        self.step, self.t, self.ratio = step, t, ratio


@dataclass(frozen=True, eq=False)
class State:
    """Where a run stands before step ``step``: ``u = u^n (n_dofs,)``, ``v = v^{n-1/2}``,
    the time-centred work ``work`` so far, the energy balance of the first step
    ``balance0`` (None before it) and the energy ``scale``; ``dt`` the step it was made with.
    A run restarted from a State reproduces the original bit for bit."""

    step: int
    dt: float
    u: np.ndarray
    v: np.ndarray
    work: float = 0.0
    balance0: float | None = None
    scale: float = 0.0
    drift: float = 0.0

    @property
    def t(self) -> float:
        return self.step * self.dt

    def save(self, path) -> None:
        """Write the state as ``.npz``."""
        np.savez(path, step=self.step, dt=self.dt, u=self.u, v=self.v, work=self.work,
                 balance0=np.nan if self.balance0 is None else self.balance0,
                 scale=self.scale, drift=self.drift)

    @classmethod
    def load(cls, path) -> State:
        d = np.load(path)
        b0 = float(d["balance0"])
        return cls(int(d["step"]), float(d["dt"]), d["u"].copy(), d["v"].copy(), float(d["work"]),
                   None if math.isnan(b0) else b0, float(d["scale"]), float(d["drift"]))


@njit(cache=True)
def _advance(u, v, Ku, f, minv, dt):
    """v <- v + dt M^-1 (f - K u); u <- u + dt v, in place; returns f . v_old."""
    w = 0.0
    for i in range(u.shape[0]):
        vi = v[i]
        w += f[i] * vi
        vi = vi + dt * (minv[i] * (f[i] - Ku[i]))
        v[i] = vi
        u[i] += dt * vi
    return w


@njit(cache=True)
def _energies(u, v, Ku, f, m):
    """(1/2 v.Mv, 1/2 u.Ku_old, f.v) in one pass."""
    kin = 0.0
    uk = 0.0
    w = 0.0
    for i in range(u.shape[0]):
        kin += m[i] * v[i] * v[i]
        uk += u[i] * Ku[i]
        w += f[i] * v[i]
    return 0.5 * kin, 0.5 * uk, w


def initial_state(dyn: Dynamics, dt: float) -> State:
    """State before step 0 from the scene's initial fields (zero when not given):
    ``v^{-1/2} = v^0 - dt/2 a^0``; with Lagrange constraints ``u^0`` and ``v^0`` are first
    projected onto the admissible motions (``G u^0 = q(0)``, ``G v^0 = 0``: a moving
    support starts from rest), with modified MLS the fixed coefficients set."""
    scene = dyn.disc.scene
    n = dyn.n_dofs
    u, v = (np.zeros(n) if g is None else fit_coefficients(dyn.disc, g)
            for g in (scene.initial_displacement, scene.initial_velocity))
    if dyn.projection is not None:
        P = dyn.projection
        u = u - P.correction(u, dyn.prescribed(0.0))
        v = v - P.minv_GT @ P.lu.solve(P.G @ v)
    else:
        u[dyn.fixed] = dyn.prescribed(0.0)
    v[dyn.fixed] = 0.0
    a = dyn.minv * (dyn.force(0.0) - dyn.K @ u)
    return State(0, dt, u, v - 0.5 * dt * a)


def load_stepping(path) -> Stepping | None:
    """The ``[time]`` table of a scene file (:func:`~efgkit.problem.history.stepping_from_dict`),
    or None when the file has none (a static scene). Errors are prefixed with the path."""
    import tomllib

    from ..problem.history import stepping_from_dict

    with open(path, "rb") as fh:
        d = tomllib.load(fh)
    if "time" not in d:
        return None
    try:
        return stepping_from_dict(d["time"])
    except (TypeError, ValueError) as err:
        raise type(err)(f"{path}: {err}") from err


def _progress(enabled: bool, total: int):
    state = {"last": -1}

    def show(k):
        if not enabled:
            return
        pct = int(100 * k / max(total, 1))
        if pct != state["last"]:
            state["last"] = pct
            bar = "#" * (pct // 4)
            sys.stderr.write(f"\r[{bar:<25}] {pct:3d} % step {k}/{total}")
            if k >= total:
                sys.stderr.write("\n")
            sys.stderr.flush()
    return show


def integrate(scene: Scene, method: EFG | MLPG, stepping: Stepping | None = None, *,
              dyn: Dynamics | None = None, state: State | None = None, steps: int | None = None,
              dsif=dynamic_dsif, out=None, progress: bool | None = None,
              critical: tuple[float, float] | None = None) -> DynamicSolution:
    """Integrate a dynamic scene in time by central differences (module docstring).

    Parameters
    ----------
    scene : Scene
        With ``duration`` and ``material.rho``; loads with histories, initial fields.
    method : EFG or MLPG
    stepping : Stepping, optional
        Step, safety factor, output interval, probes (default ``Stepping()``).
    dyn : Dynamics, optional
        The assembled system (:func:`~efgkit.explicit.system.dynamics`), to reuse.
    state : State, optional
        Restart from a saved state (same scene, method and dt): the history continues
        exactly as the original run.
    steps : int, optional
        Number of steps to take (default: up to ``scene.duration``).
    dsif : callable or None
        The dynamic SIF hook, called at every output instant as
        ``dsif(dyn, u, v, a, t) -> {estimate: ndarray (n_tips, 2)}`` with the coefficients
        of displacement, velocity and acceleration at ``t``
        (default :data:`~efgkit.explicit.dsif.dynamic_dsif`: J', interaction with inertia,
        near-tip stresses); None: no SIFs.
    out : path, optional
        Directory for the VTU time series (``stepping.vtu``).
    progress : bool, optional
        Progress bar on stderr (default: only when stderr is a terminal).
    critical : (dt_critical, lambda_max), optional
        The result of :func:`~efgkit.explicit.spectrum.stable_step` for ``dyn``, to reuse.

    Returns
    -------
    DynamicSolution

    Raises
    ------
    ValueError
        A static scene, no density, or ``dt`` above the critical step without ``force``.
    InstabilityError
        The kinetic energy outgrew the energy scale of the run (blow-up).
    """
    stepping = Stepping() if stepping is None else stepping
    if not isinstance(stepping, Stepping):
        raise TypeError(f"stepping must be a Stepping, got {type(stepping).__name__}")
    if dsif is not None and scene.tips:
        refuse_grading(scene, "the dynamic SIFs (J', dsif)")
    t_all = time.perf_counter()
    dyn = dynamics(scene, method) if dyn is None else dyn
    t0 = time.perf_counter()
    dt_crit, lam = stable_step(dyn) if critical is None else critical
    t_stable = time.perf_counter() - t0
    dt = stepping.safety * dt_crit if stepping.dt is None else stepping.dt
    if state is not None:
        if not math.isclose(state.dt, dt, rel_tol=0, abs_tol=0) and stepping.dt is not None:
            raise ValueError(f"state: saved with dt = {state.dt!r}, the run asks for dt = {dt!r}; "
                             "a restart continues with the step it was saved with")
        dt = state.dt
    if dt > dt_crit and not stepping.force:
        raise ValueError(
            f"dt = {dt:.6g} exceeds the critical step {dt_crit:.6g} (2 / omega_max, omega_max^2 = "
            f"{lam:.6g} from K x = lambda M x, seed 002 Eqs. 29-30) by {dt / dt_crit - 1:.2%}: the "
            f"central differences would blow up. Remedy: dt <= {dt_crit:.6g} (or leave dt unset "
            f"for safety x critical), or force=true to run anyway")
    n0 = 0 if state is None else state.step
    n_total = max(0, math.ceil(scene.duration / dt - 1e-9) - n0) if steps is None else int(steps)
    every = max(1, round((stepping.output_interval or scene.duration / 100) / dt))
    st = initial_state(dyn, dt) if state is None else state
    u, v = st.u.copy(), st.v.copy()
    work, bal0, scale, drift = st.work, st.balance0, st.scale, st.drift
    K, m, minv, P = dyn.K, dyn.m, dyn.minv, dyn.projection
    rows = minv_rows = None
    if P is not None:  # only the rows M^-1 G^T touches change
        rows = np.flatnonzero(np.diff(P.minv_GT.indptr))
        minv_rows = P.minv_GT[rows]
    moving = dyn.moving_supports  # constraint values q(t) (efgkit.explicit.moving)
    if moving and P is None:  # moving fixed coefficients (modified MLS)
        rows = dyn.fixed
    f_const = None if dyn.time_dependent else dyn.force(0.0)
    rec = Recorder(dyn, stepping, dt, dsif, out, n_out=-(-n_total // every) + 1)
    show = _progress(sys.stderr.isatty() if progress is None else progress, n_total)
    t_loop = time.perf_counter()
    for n in range(n0, n0 + n_total):
        t = n * dt
        Ku = K @ u
        f = f_const if f_const is not None else dyn.force(t)
        if (n - n0) % every == 0:
            rec.record(n, t, u, v, Ku, f, work, drift)
        if moving:
            v_rows = v[rows]
        w_old = _advance(u, v, Ku, f, minv, dt)
        if P is not None:
            du = minv_rows @ P.lu.solve(P.G @ u - (dyn.prescribed((n + 1) * dt) if moving else P.q))
            u[rows] -= du
            v[rows] -= du / dt
        elif moving:  # prescribed kinematics of the fixed coefficients
            q1 = dyn.prescribed((n + 1) * dt)
            v[rows] = v_rows + (q1 - u[rows]) / dt  # u[rows] moved by dt v_rows already
            u[rows] = q1
        kin, uk, w_new = _energies(u, v, Ku, f, m)
        work += 0.5 * dt * (w_old + w_new)
        if moving:  # work of the support reactions r^n = M (v^{n+1/2} - v~^{n+1/2}) / dt
            r = m[rows] * (v[rows] - v_rows) / dt - (f[rows] - Ku[rows]) if P is None \
                else -m[rows] * du / dt ** 2
            work += 0.5 * dt * float(r @ (v_rows + v[rows]))
        modified = kin + uk
        bal = modified - work
        if bal0 is None:
            bal0 = bal
        scale = max(scale, abs(modified), abs(work))
        if scale > 0:
            drift = max(drift, abs(bal - bal0) / scale)
        # the energy put in (initial energy + work done) bounds a stable run's kinetic energy;
        # not the running scale, which an unsymmetric K's (MLPG) growing mode drags along
        ref = abs(bal0) + abs(work)
        if not (kin <= BLOWUP_FACTOR * ref):  # also catches NaN
            ratio = kin / ref if ref > 0 else math.inf
            raise InstabilityError(
                f"the integration blew up at step {n + 1} (t = {(n + 1) * dt:.6g}): the kinetic "
                f"energy is {ratio:.3g} times the energy put in (initial energy + work done); "
                f"dt = {dt:.6g} is "
                f"{dt / dt_crit:.4f} of the estimated critical step {dt_crit:.6g}. Remedy: "
                + (_MLPG_REMEDY if getattr(dyn.disc, "test", None) is not None and dt <= dt_crit
                   else "a smaller dt (leave it unset for safety x critical)"),
                n + 1, (n + 1) * dt, ratio)
        if (n - n0) % 64 == 0:
            show(n - n0)
    show(n_total)
    n_end = n0 + n_total
    Ku = K @ u
    rec.record(n_end, n_end * dt, u, v, Ku, f_const if f_const is not None else dyn.force(n_end * dt),
               work, drift)
    t_end = time.perf_counter()
    final = State(n_end, dt, u, v, work, bal0, scale, drift)
    timings = {**dyn.disc.timings, **dyn.timings, "stable_step": t_stable,
               "loop": t_end - t_loop, "output": rec.seconds,
               "total": t_end - t_all + sum(dyn.disc.timings.values())}
    info = {"dt": dt, "dt_critical": dt_crit, "lambda_max": lam, "dt_ratio": dt / dt_crit,
            "steps": n_total, "first_step": n0, "output_every": every, "energy_drift": drift,
            "energy_scale": scale, "bc": dyn.bc, "form": dyn.form,
            "steps_per_second": n_total / max(t_end - t_loop - rec.seconds, 1e-300)}
    return DynamicSolution(dyn, rec.arrays(), final, info, timings)
