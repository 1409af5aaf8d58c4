"""A crack on a symmetry line, released node by node during an explicit run (seed 000
Sect. 5.2.1, Fig. 15).

In a symmetric model the crack lies on the symmetry line ``y = y0``: the crack faces are
the stretch of the line that is traction free, the ligament the stretch that carries the
symmetry condition ``u_y = 0`` (an ordinary roller support, imposed by the Lagrange
projection of :mod:`efgkit.explicit.system`). The nodes on the line cut it into segments
``[x_j, x_{j+1}]``; a segment is open (crack face) or bonded (ligament). Propagation
changes only this support: the nodes, K, M and the loads stay, each release rebuilds only
the constraint projection: the line's Lagrange rows (piecewise-linear multiplier hats on the
line's nodes, as :func:`~efgkit.methods.boundary.essential_conditions`) are sums of
per-segment rows computed once, and a release re-factorises only ``G M^-1 G^T``.

Criterion (seed 000 Sect. 5.2.1, after Batra and Love): every ``check_every`` steps the
maximum principal stress ``sigma_1`` is evaluated at each bonded node of the line (a node
whose two segments are bonded); a node where ``sigma_1 >= sigma_c`` is released:

* next to a crack tip (the node beyond it is a tip of an open stretch: seed Fig. 15a), the
  segment between them opens and the released node is the new tip;
* elsewhere (Fig. 15b), both its segments open: a new crack with tips at the two
  neighbours (both sides next to tips: the cracks join).

The criterion applies at every node, so new cracks may start away from the tip; the
nodes are scanned by increasing x and each release is applied before the next node is
tested in the same check. Crack length = the x of the tip of the open stretch that
starts at the line's first node (``x_0``, the centre of the plate); its speed the
least-squares slope over 11 points (:func:`~efgkit.growth.running_tip.speed_fit`, seed 000:
5 before and 5 after). The face gap of the seed (delta = 2e-3 mm between the two copies of
a split particle) has no counterpart here: the two faces of a symmetric model are mirror
images, the released node moves off the line freely.

Release of the support: at once, as the seed (``fracture_energy = 0``, the default), or
softening with the segment's opening, a linear cohesive law that dissipates the fracture
energy G_c per unit of new crack (``fracture_energy > 0``, :mod:`efgkit.growth.cohesive`);
then the traction-free crack (``Released.free``: its supports gone) trails the released
nodes (the front of the cohesive zone), and its tip is the crack tip of the model.

When the criterion was met: sigma_1 at a released node interpolated linearly in time
between the previous check and this one (``interpolate``, default); the release acts at
the check. Without it the growth instants are multiples of the step and the 11-point fit
jumps between h / dt and h / 2 dt (3981 and 1990 m/s on the tungsten plate).

The step is ``safety`` times the critical step of the system without any line constraint
(releasing constraints can only raise omega_max: the bound holds for every crack state)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.sparse import csr_array, vstack

from ..explicit import State, dynamics, integrate, stable_step
from ..explicit.system import Projection
from ..problem.history import Stepping
from .cohesive import Supports, opening_for
from .release_line import ReleaseLine
from .release_rules import release_segments
from .running_tip import speed_fit

__all__ = ["LineRelease", "Released", "run_release"]


@dataclass(frozen=True)
class LineRelease:
    """Release of the symmetry line ``y = y0`` (its nodes' ``u_y = 0`` support) where the
    maximum principal stress reaches ``sigma_c`` (stress units of the scene; a callable
    ``x (m, 2) -> (m,)``: a value per node of the line, e.g. a graded strength), checked
    every ``check_every`` steps; ``a0``: the initial crack, open from the line's first
    node (smallest x, the centre of the body) over ``a0`` (rounded to the nearest node);
    ``cracks``: further initial cracks on the line, ``((x_start, x_end), ...)`` (ends
    rounded to the nearest nodes); nodes within ``tol`` of ``y0`` are on the line;
    ``fracture_energy``: G_c (energy per unit crack area, stress x length: N/mm in mm and
    MPa; a callable ``x (m, 2) -> (m,)`` as sigma_c, the mean of a segment's two nodes
    taken), dissipated by the linear softening of a released segment's support force
    (:mod:`efgkit.growth.cohesive`); 0: released at once, as seed 000;
    ``interpolate``: growth instants at the time sigma_1 crossed sigma_c (linear between
    checks) instead of the check's step."""

    sigma_c: float | Callable
    a0: float
    y0: float = 0.0
    check_every: int = 1
    tol: float = 1e-9
    cracks: tuple = ()
    fracture_energy: float | Callable = 0.0
    interpolate: bool = True

    def __post_init__(self):
        for name in ("a0",) if callable(self.sigma_c) else ("sigma_c", "a0"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        c = np.asarray(self.cracks, float).reshape(-1, 2) if len(self.cracks) else np.zeros((0, 2))
        if not (np.all(np.isfinite(c)) and np.all(c[:, 1] > c[:, 0])):
            raise ValueError(f"cracks must be pairs (x_start, x_end) with x_end > x_start, "
                             f"got {self.cracks!r}")
        object.__setattr__(self, "cracks", tuple(map(tuple, c.tolist())))
        gc = self.fracture_energy
        if not callable(gc) and (isinstance(gc, bool) or not isinstance(gc, (int, float))
                                 or not math.isfinite(gc) or gc < 0):
            raise ValueError(f"fracture_energy must be a finite number >= 0 (stress x length "
                             f"units of the scene; 0: instantaneous release) or a callable, got {gc!r}")
        if isinstance(self.check_every, bool) or not isinstance(self.check_every, int) \
                or self.check_every < 1:
            raise ValueError(f"check_every must be an int >= 1 (steps), got {self.check_every!r}")


@dataclass(frozen=True, eq=False)
class Released:
    """Result of :func:`run_release`.

    Attributes
    ----------
    t, length : ndarray (k,)
        The instants at which the main crack grew and its length after (the initial
        point ``(0, a0)`` first).
    speed : ndarray (k,)
        Least-squares speed over 11 growth points (NaN at the start and with fewer than
        2 growth points).
    releases : dict
        Every release: ``t``, ``x`` (node), ``new_crack`` (bool: away from a tip).
    history : dict
        At the output instants: ``t``, ``length``, ``sigma1_max`` (the largest sigma_1
        over the bonded line nodes), ``ratio_max`` (the largest sigma_1 / sigma_c there),
        ``ratio_ahead`` (the same over the bonded nodes 3 or more segments from any open
        one: away from the tips' fields),
        ``kinetic``, ``work``.
    line_x : ndarray (m,)
        The line's nodes; ``open`` (m - 1,) bool: the final open segments.
    tips : dict
        ``t (k,)`` (0, then every check with a release) and ``x (k, n_cracks, 2)``: the
        left and right ends of the open stretch holding each initial crack (the main
        crack first; stretches that joined share their ends).
    free : dict
        ``t``, ``length``, ``speed``: the same for the traction-free crack (supports gone:
        softened to zero, the tip of a cohesive model; with the seed's release, the same).
    stop : str
    state : State
    info, timings : dict
        ``info["dissipated"]``: the energy the softening supports absorbed (the model's:
        half the body's, ``G_c / 2`` per unit of new crack once the segments are free).
    """

    t: np.ndarray
    length: np.ndarray
    speed: np.ndarray
    releases: dict
    history: dict
    line_x: np.ndarray
    open: np.ndarray
    stop: str
    state: object = None
    info: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    tips: dict = field(default_factory=dict)
    free: dict = field(default_factory=dict)


def run_release(scene, method, rule: LineRelease, stepping: Stepping | None = None, *,
                max_length: float | None = None) -> Released:
    """Explicit run of ``scene`` (EFG, bc="lagrange") whose symmetry line ``y = rule.y0``
    is released by the principal-stress criterion (module docstring). ``scene`` holds
    every other support (the line's rows are added here). Stops at ``scene.duration``, when the
    main crack reaches ``max_length`` or the line's end.
    """
    if not isinstance(rule, LineRelease):
        raise TypeError(f"rule must be a LineRelease, got {type(rule).__name__}")
    stepping = Stepping() if stepping is None else stepping
    t0 = time.perf_counter()
    dyn0 = dynamics(scene, replace(method, bc="lagrange"))
    line = ReleaseLine(dyn0.disc, rule)
    P0 = dyn0.projection
    G0 = P0.G if P0 is not None else csr_array((0, dyn0.n_dofs))
    q0 = P0.q if P0 is not None else np.zeros(0)
    # the line rows scaled like the others (the projection does not depend on row scales;
    # similar scales keep G M^-1 G^T well conditioned for the LU)
    scale = abs(G0).max() / abs(line.B).max() if G0.shape[0] else 1.0

    def system():
        Gl = line.rows()
        G = csr_array(vstack([G0, scale * Gl], format="csr"))
        P = Projection.build(G, np.concatenate([q0, np.zeros(Gl.shape[0])]), dyn0.minv)
        Q = None if dyn0.Q is None else np.vstack([dyn0.Q, np.zeros((Gl.shape[0], dyn0.Q.shape[1]))])
        if not sup.items:
            return replace(dyn0, projection=P, Q=Q)
        return replace(dyn0, projection=P, Q=Q, F=np.column_stack([dyn0.F] + sup.forces),
                       histories=dyn0.histories + sup.histories)

    sup = Supports(line.open.copy())  # released segments still holding (G_c > 0), free instants
    fa, ft = [line.length()], [0.0]  # the traction-free crack: length and instants

    def free_tip():  # the stretch from x_0 whose segments are all free
        k = int(np.argmax(np.r_[np.isnan(sup.free_at), True]))
        if line.x[k] - line.x[0] > fa[-1] + 1e-12:
            ft.append(float(np.max(sup.free_at[np.searchsorted(line.x, line.x[0] + fa[-1] - 1e-12):k])))
            fa.append(float(line.x[k] - line.x[0]))
    e_y = np.zeros(dyn0.n_dofs)  # the coefficients of u = (0, 1): the MLS bases reproduce constants
    e_y[1:2 * dyn0.disc.nodes.n:2] = 1.0
    dyn = system()
    free = stable_step(replace(dyn0, projection=None, Q=None, q_histories=()))
    dt = stepping.dt or stepping.safety * free[0]
    timings = {"setup": time.perf_counter() - t0, "integrate": 0.0, "release": 0.0, "check": 0.0}
    n_total = math.ceil(scene.duration / dt - 1e-9)
    every = max(1, round((stepping.output_interval or scene.duration / 100) / dt))
    step, state, stop = 0, None, None
    s1_prev, t_prev = None, 0.0  # sigma_1 on the line at the previous check
    ta, la = [0.0], [line.length()]
    tip_t, tip_x = [0.0], [line.tips()]
    rel = {"t": [], "x": [], "new_crack": []}
    hist = {"t": [], "length": [], "sigma1_max": [], "ratio_max": [], "ratio_ahead": [], "kinetic": [],
            "work": []}
    lim = line.x[-1] - line.x[0] if max_length is None else max_length
    st = replace(stepping, dt=dt, output_interval=None)
    while step < n_total:
        nxt = min(step + rule.check_every, n_total)
        t1 = time.perf_counter()
        sol = integrate(dyn.disc.scene, method, st, dyn=dyn, state=state, steps=nxt - step,
                        dsif=None, critical=free, progress=False)
        timings["integrate"] += time.perf_counter() - t1
        state, step = sol.state, nxt
        sup.update(state.u, t_prev, step * dt)
        free_tip()
        t1 = time.perf_counter()
        s1 = line.sigma1(state.u)
        bonded = ~np.r_[True, line.open] & ~np.r_[line.open, True]
        if step % every < rule.check_every or step == n_total:
            hist["t"].append(step * dt)
            hist["length"].append(line.length())
            hist["sigma1_max"].append(float(s1[bonded].max()) if bonded.any() else math.nan)
            hist["ratio_max"].append(float((s1 / line.sigma_c)[bonded].max()) if bonded.any() else math.nan)
            far = np.convolve(np.r_[True, line.open, True].astype(float), np.ones(6), "same")[1:] == 0
            hist["ratio_ahead"].append(float((s1 / line.sigma_c)[far].max()) if far.any() else math.nan)
            hist["kinetic"].append(float(sol.history["kinetic"][-1]))
            hist["work"].append(float(sol.history["work"][-1]))
        was_open = line.open.copy()
        idx = release_segments(line.open, s1, line.sigma_c)
        events = [(float(line.x[k]), new) for k, new in idx]
        timings["check"] += time.perf_counter() - t1
        t_check = step * dt
        if not events:
            s1_prev, t_prev = s1, t_check
            continue
        # when the criterion was met: sigma_1 interpolated linearly in time between the
        # previous check and this one (the release itself acts at this step)
        k = np.array([i for i, _ in idx])
        if s1_prev is None or not rule.interpolate:
            t_met = np.full(len(k), t_check)
        else:
            lo, hi = s1_prev[k], s1[k]
            frac = np.clip((line.sigma_c[k] - lo) / np.where(hi > lo, hi - lo, 1.0), 0.0, 1.0)
            t_met = np.where(hi > lo, t_prev + frac * (t_check - t_prev), t_check)
        t_grow = float(t_met.max())
        s1_prev, t_prev = s1, t_check
        t1 = time.perf_counter()
        opened = np.flatnonzero(line.open & ~was_open)
        if np.any(line.gc[opened] > 0):  # the support's force on the opened segments, softening
            Pold, t_now = dyn.projection, step * dt
            lam = Pold.lu.solve(Pold.G @ (dyn.minv * (dyn.force(t_now) - dyn.K @ state.u)))
            fs = line.segment_forces(scale * lam[G0.shape[0]:], opened)
            sup.prune()
            sup.add(opened, fs, fs.T @ e_y, opening_for(line.gc[opened], np.diff(line.x)[opened],
                                                       fs.T @ e_y), t_grow)
        else:
            sup.free_at[opened] = t_grow
        free_tip()
        for x, new in events:
            rel["t"].append(t_grow)
            rel["x"].append(x)
            rel["new_crack"].append(new)
        a = line.length()
        tip_t.append(t_grow)
        tip_x.append(line.tips())
        if a > la[-1]:
            ta.append(t_grow)
            la.append(a)
        dyn = system()
        P = dyn.projection
        q_now, q_before = dyn.prescribed(step * dt), dyn.prescribed((step - 1) * dt)
        u = state.u - P.correction(state.u, q_now)
        v = state.v - P.minv_GT @ P.lu.solve(P.G @ state.v - (q_now - q_before) / dt)
        state = State(step, dt, u, v, state.work, None, 0.0, 0.0)
        timings["release"] += time.perf_counter() - t1
        if a >= lim - 1e-12:
            stop = f"crack length {a:.6g} reached {lim:.6g}"
            break
    if stop is None:
        stop = f"duration {scene.duration:.6g} reached"
    t, a = np.array(ta), np.array(la)
    speed = np.full(len(t), math.nan)  # the fit over the growth instants (not the start)
    if len(t) >= 3:
        speed[1:] = speed_fit(t[1:], a[1:])
    timings["total"] = time.perf_counter() - t0
    info = {"dt": dt, "dt_critical_free": free[0], "steps": step, "n_nodes": dyn.disc.nodes.n,
            "line_nodes": len(line.x), "releases": len(rel["t"]),
            "dissipated": sup.dissipated}
    tips = {"t": np.array(tip_t), "x": np.array(tip_x)}
    ft, fa = np.array(ft), np.array(fa)
    fv = np.full(len(ft), math.nan)
    if len(ft) >= 3:
        fv[1:] = speed_fit(ft[1:], fa[1:])
    return Released(t, a, speed, {k: np.array(v) for k, v in rel.items()},
                    {k: np.array(v) for k, v in hist.items()}, line.x, line.open.copy(), stop,
                    state, info, timings, tips, {"t": ft, "length": fa, "speed": fv})
