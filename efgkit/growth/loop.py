"""The crack-growth step loop: solve, SIFs, criterion, extend; quasi-static or fatigue.

Each step (seed 003 Sect. 6):

1. discretise the current scene (:func:`rediscretize`: a full rebuild, or with
   ``Growth.incremental`` an update of only what the new segment touches,
   :mod:`efgkit.growth.incremental`) and solve it
   (:func:`efgkit.solve` for EFG, :func:`efgkit.fem.solve_fem` for the FE reference: the
   same :class:`~efgkit.solution.Solution` contract);
2. K_I, K_II of every active tip (``sol.sifs(error=settings.sif_error)``);
3. the maximum hoop stress criterion (:func:`~efgkit.fracture.criteria.hoop_stress`):
   kink angle and K_eq per tip, closure for K_I < 0; the load factor
   ``K_Ic / max K_eq`` with a toughness;
4. stop tests (each stop names its reason), then every open tip with ``K_eq`` above
   ``K_threshold`` grows by ``da`` along its kink angle
   (:func:`~efgkit.growth.extend.advance`); with the Paris law the leading tip grows
   by ``da`` and the others by ``da`` times their rate over the leader's (the same
   cycles), and the cycles of the increment come from
   :func:`~efgkit.fracture.criteria.paris_cycles` between this step and the next.

The loop is a generator of :class:`GrowthStep`; the last step yielded carries ``stop``.
A :class:`GrowthState` (the cracks and counters after a step; JSON in
:mod:`efgkit.growth.record`) restarts it where it was.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from ..approx.mls import SingularMomentMatrix
from ..fem.model import FEM, solve_fem
from ..fracture.criteria import critical_load_factor, delta_k, hoop_stress, paris_cycles, paris_rate
from ..methods.discretize import discretize
from ..methods.efg import EFG, Zone
from ..methods.mlpg import MLPG
from ..problem.scene import Scene
from ..static import solve
from .extend import advance
from .incremental import Assembled, update
from .path_zones import undiscretisable, with_path_zones
from .settings import Growth

__all__ = ["GrowthState", "GrowthStep", "anchored_zones", "grow", "growth_method", "rediscretize"]


@dataclass(frozen=True)
class GrowthStep:
    """One step of a growth loop.

    Attributes
    ----------
    index : int
        Step number, 0 for the initial scene.
    scene : Scene
        The scene solved in this step.
    solution : Solution
    tips : tuple of TipResult
        SIFs of every active tip (``scene.tips`` order).
    kink : ndarray (n_tips,)
        Kink angle of each tip (radians, tip frame; 0 where closed).
    K_eq : ndarray (n_tips,)
        Equivalent mode-I factor of the hoop stress criterion (0 where closed).
    closed : ndarray (n_tips,) bool
    lengths : dict str -> float
        Length of each crack.
    load_factor : float or None
        ``K_Ic / max K_eq`` with a toughness, else None.
    cycles : float or None
        Paris: cycles from the start to this step's crack; None for quasi-static loops.
    da : dict str -> float
        The increment each tip takes after this step (empty at a stop).
    events : tuple of str
        What happened in the increment into this step (tips that joined the boundary or
        another crack: "tip a:1 joined crack 'b' at [x, y] ...").
    stop : str or None
        Why the loop ends after this step, None while it goes on.
    seconds : dict str -> float
        ``discretize``, ``solve``, ``sifs`` and ``step`` (wall) times of this step.
    state : GrowthState or None
        Where the loop goes on from (restart), None at a stop.
    """

    index: int
    scene: Scene
    solution: object
    tips: tuple
    kink: np.ndarray
    K_eq: np.ndarray
    closed: np.ndarray
    lengths: dict
    load_factor: float | None
    cycles: float | None
    da: dict
    events: tuple[str, ...]
    stop: str | None
    seconds: dict
    state: GrowthState | None = None


@dataclass(frozen=True)
class GrowthState:
    """Where a loop stands before solving step ``index``: enough to restart it.

    Attributes
    ----------
    index : int
        Next step to solve.
    cracks : tuple of Crack
    cycles : float
        Paris cycles up to these cracks (0 for quasi-static loops).
    previous : dict
        Data of the step before: ``load_factor``, ``dK`` (tip id -> range) and ``path``
        (tip id -> path length grown), for the unstable test and the cycle integration;
        and ``da`` (the next increment of an adaptive Paris loop).
    events : tuple of str
        Events of the increment into step ``index``.
    """

    index: int
    cracks: tuple
    cycles: float = 0.0
    previous: dict | None = None
    events: tuple[str, ...] = ()


def rediscretize(scene: Scene, method, previous=None, incremental: bool = False):
    """The discretisation of ``scene`` for a growth step (None for FEM, which remeshes
    inside :func:`solve_fem`, and for MLPG, which :func:`efgkit.solve` rebuilds each step).

    Without ``incremental`` a full rebuild (:func:`efgkit.discretize`); with it an
    :class:`~efgkit.growth.incremental.Assembled` (discretisation, K and f) updated from
    ``previous`` (the last step's) where only the quadrature points whose shape rows the
    new segments, the moved tips and the moved enrichment touch are recomputed
    (:func:`~efgkit.growth.incremental.update`; a full build when the node cloud changes,
    e.g. with automatic tip zones, and for unramped extrinsic fields).
    """
    if not isinstance(method, EFG):
        return None
    if incremental:
        return update(previous if isinstance(previous, Assembled) else None, scene, method)
    return discretize(scene, method)


def growth_method(method, settings: Growth):
    """The method used in every step: an EFG with the automatic enrichment and no
    ``enrich_radius`` gets ``enrich_radius = 2 spacing``, so that its enrichment is ramped
    to zero near the tip (a growing crack kinks at every step, and unramped Williams
    fields over the whole body follow one kink only); the automatic tip zones stay.
    Measured on the edge crack of verification/paris.py (h = 2.5 mm, a = 0.21 W and
    0.51 W): K_I 0.07 % and 0.90 % below Tada's with 2 h, 0.62 % and 1.6 % with 0.5 h
    (the FE reference: 0.13 % and 0.54 %). Other methods are used as given."""
    if isinstance(method, EFG) and method.enrichment == "auto" and method.enrich_radius is None:
        return replace(method, enrich_radius=2.0 * method.spacing)
    return method


def anchored_zones(method, scene: Scene, anchors: dict):
    """``method`` with the automatic tip zones of ``scene`` on lattices anchored at ``anchors``.

    The automatic zones (:meth:`EFG.for_scene`) put a grid centred at every tip. A grown
    tip is off the grid of the tip it came from, so the zone grid moved with it: after a
    kink of -0.256 rad (shear edge crack, h = 0.35) a row of the 0.25 h grid lay 1.5 %
    of its spacing below the old crack face, the face above kept one row in reach
    (d_max = 2) and the moment matrices there were singular (docs/robustness.md). Here
    each zone of a tip keeps its radius and spacing but its centre moves from the tip to
    the nearest point ``anchor + q (i, j)`` with ``q`` the coarsest spacing of the tip's
    zones (a multiple of the finer ones), so every grid keeps the alignment it had when
    the tip started at ``anchor`` (the crack path already grown keeps step 0's nodes);
    the centre stays within ``q / sqrt 2`` of the tip. ``anchors`` maps tip ids to
    positions (n, 2 as lists); a tip without one is anchored where it is now (added to
    ``anchors``). Other methods, given zones, and no automatic zones: ``method`` as is.
    """
    if not isinstance(method, EFG) or method.zones is not None:
        return method
    zones = method.automatic_choices(scene).get("zones", ())
    out = []
    for z in zones:
        c = np.asarray(z.centre)
        tip = next((t for t in scene.tips if np.array_equal(np.asarray(t.x, float), c)), None)
        if tip is not None:
            a = np.asarray(anchors.setdefault(tip.id, [float(v) for v in c]), float)
            q = max(y.spacing for y in zones if y.centre == z.centre)
            c = a + q * np.round((c - a) / q)
        out.append(Zone(tuple(c), z.radius, z.spacing))
    return replace(method, zones=tuple(out))


def _solve(scene, method, disc):
    if isinstance(disc, Assembled):
        return solve(scene, method, disc.disc, K=disc.K, f=disc.f)
    if isinstance(method, (EFG, MLPG)):  # MLPG: efgkit.solve builds its local system
        return solve(scene, method, disc)
    return solve_fem(scene, method)


def _check(scene, method, settings, start):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(method, (EFG, MLPG, FEM)):
        raise TypeError(f"method must be an EFG, MLPG or FEM description, got {type(method).__name__}")
    if not isinstance(settings, Growth):
        raise TypeError(f"settings must be a Growth description, got {type(settings).__name__}")
    if not scene.is_static:
        raise ValueError(f"scene {scene.name!r} has a duration ({scene.duration!r}): the growth "
                         "loops are quasi-static; use a static scene (duration None)")
    if not scene.tips:
        raise ValueError(f"scene {scene.name!r} has no crack tip to grow: add a crack with a tip")
    if settings.path_zones and not isinstance(method, EFG):
        raise ValueError(f"growth path_zones {settings.path_zones!r} refine EFG node clouds, the method "
                         f"is {type(method).__name__}: give its own refinement, or path_zones=()")
    if start is not None and not isinstance(start, GrowthState):
        raise TypeError(f"start must be a GrowthState (efgkit.growth.load_state), got "
                        f"{type(start).__name__}")


def grow(scene: Scene, method, settings: Growth, start: GrowthState | None = None
         ) -> Iterator[GrowthStep]:
    """Grow the cracks of ``scene`` step by step.

    Parameters
    ----------
    scene : Scene
        Static scene with at least one tip; its loads are the reference (maximum) load.
    method : EFG, MLPG or FEM
    settings : Growth
    start : GrowthState, optional
        Restart: the cracks and counters saved after an earlier step
        (:func:`efgkit.growth.record.load_state`); ``scene`` gives everything else.

    Yields
    ------
    GrowthStep, one per solve; the last has ``stop`` set. Stops: the maximum number of
    steps or crack length, every tip closed or at or below ``K_threshold`` (Paris: below
    ``dK_th``), a falling load factor (``stop_unstable`` with K_Ic), cracks that cut a
    piece off the body (:func:`~efgkit.problem.junctions.split_by_cracks`), a crack
    running into itself, every tip joined to the boundary or to another crack. A tip that
    joins the boundary or another crack stops alone (an event of the next step; its
    increment is cut where it meets the boundary or the other crack's face); the others
    grow on. Of tips that arrive in the same increment and together would cut a piece off,
    the later arrivals (by ``s / da``) are held: they do not grow in that increment (an
    event; not in ``da``) and the next step solves with the earlier arrival joined.

    Raises
    ------
    SingularMomentMatrix
        A step's cracks cannot be discretised (too few nodes between close cracks); the
        message names the step and the remedy (``Growth.path_zones``).

    Examples
    --------
    >>> from efgkit import Crack, Domain, Elastic, Support, Traction
    >>> sc = Scene(Domain.rectangle(0, 0, 2, 2), Elastic(1.0, 0.3, "stress"),
    ...            supports=(Support("bottom", uy=0.0), Support("left", ux=0.0)),
    ...            tractions=(Traction("top", (0.0, 1.0)),),
    ...            cracks=(Crack([[2.0, 1.0], [1.4, 1.0]], tips=(False, True)),))
    >>> steps = list(grow(sc, FEM(h=0.2), Growth(da=0.3, max_steps=1)))
    >>> [s.index for s in steps], steps[-1].stop
    ([0, 1], 'maximum number of steps (1) reached')
    >>> round(steps[-1].lengths["crack"], 12)
    0.9
    """
    _check(scene, method, settings, start)
    method = growth_method(method, settings)
    st = start or GrowthState(0, scene.cracks)
    scene = scene.with_cracks(st.cracks)
    index, cycles, prev, events = st.index, st.cycles, st.previous or {}, st.events
    base = method
    anchors = dict(prev.get("anchors", {}))  # tip id -> where its zone grids are anchored
    paris = settings.criterion == "paris"
    disc = None
    while True:
        t0 = time.perf_counter()
        method = with_path_zones(anchored_zones(base, scene, anchors), scene, settings.path_zones)
        try:
            disc = rediscretize(scene, method, disc, settings.incremental)
            t1 = time.perf_counter()
            sol = _solve(scene, method, disc)
        except SingularMomentMatrix as err:
            raise SingularMomentMatrix(undiscretisable(index, events, err, settings)) from err
        t2 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # kept in each TipResult's warnings
            tips = sol.sifs(error=settings.sif_error)
        t3 = time.perf_counter()
        KI = np.array([t.KI for t in tips])
        KII = np.array([t.KII for t in tips])
        h = hoop_stress(KI, KII)
        ids = [t.tip.id for t in tips]
        lf = None
        if settings.K_Ic is not None and not h.closed.all():
            lf = critical_load_factor(h.K_eq, settings.K_Ic)
        lengths = {c.name: c.length for c in scene.cracks}
        path = {i: prev.get("path", {}).get(i, 0.0) for i in ids}
        a_ref = dict(prev.get("a_ref", {}))  # a of a tip = a_ref + path grown (Paris)
        for t in tips:
            c = next(c for c in scene.cracks if c.name == t.tip.crack)
            a_ref.setdefault(t.tip.id, c.length / len(c.tip_list))
        dK = delta_k(h.K_eq, settings.R) if paris else None
        if paris and prev.get("dK"):  # cycles of the increment into this step, by its leader
            cycles += _increment_cycles(settings, prev, ids, dK, a_ref, path)
        stop = _stop_reason(settings, index, h, lengths, lf, prev, dK)
        moves = {}
        if stop is None:
            moves = _moves(settings, ids, h, dK, prev)
            if not moves:
                stop = "no tip grows (every tip closed or below the threshold)"
        nxt = None
        if stop is None:
            adv = advance(scene, {i: (d, float(h.angle[ids.index(i)])) for i, d in moves.items()},
                          settings.snap)
            stop = adv.stop
            moves = {k: v for k, v in moves.items() if k not in adv.held}  # not grown
            if adv.scene is not None and not adv.scene.tips:
                stop = "every tip has joined the boundary or another crack"
            nxt = adv
        state = None
        if stop is None:
            prev = {**_previous(settings, ids, dK, lf, moves, path, a_ref, prev),
                    "anchors": dict(anchors)}
            state = GrowthState(index + 1, nxt.scene.cracks, cycles, prev, nxt.events)
        secs = {"discretize": t1 - t0, "solve": t2 - t1, "sifs": t3 - t2,
                "step": time.perf_counter() - t0}
        yield GrowthStep(index, scene, sol, tuple(tips), h.angle, h.K_eq, h.closed, lengths, lf,
                         cycles if paris else None, moves if stop is None else {}, events, stop,
                         secs, state)
        if stop is not None:
            return
        scene, events, index = nxt.scene, nxt.events, index + 1


def _stop_reason(s: Growth, index, h, lengths, lf, prev, dK) -> str | None:
    if h.closed.all():
        return "every tip is closed (K_I < 0)"
    if not s.criterion == "paris" and float(h.K_eq.max()) <= s.K_threshold:
        return f"K_eq of every tip ({h.K_eq.max():.6g} at most) is at or below K_threshold " \
               f"({s.K_threshold:g})"
    if s.criterion == "paris" and float(dK.max()) <= s.dK_th:
        return f"dK of every tip ({dK.max():.6g} at most) is at or below the threshold dK_th " \
               f"({s.dK_th:g}): no fatigue growth"
    if lf is not None and s.stop_unstable and prev.get("load_factor") is not None \
            and lf < prev["load_factor"]:
        return (f"unstable: the load factor fell from {prev['load_factor']:.6g} to {lf:.6g} (the "
                "crack would run at a falling load under the scene's load control)")
    if s.max_length is not None and max(lengths.values()) >= s.max_length:
        name = max(lengths, key=lengths.get)
        return f"crack {name!r} is {lengths[name]:.6g} long, at least max_length ({s.max_length:g})"
    if index >= s.max_steps:
        return f"maximum number of steps ({s.max_steps}) reached"
    return None


def _moves(s: Growth, ids, h, dK, prev) -> dict:
    if s.criterion != "paris":
        return {i: s.da for i, c, k in zip(ids, h.closed, h.K_eq, strict=True)
                if not c and k > s.K_threshold}
    rate = paris_rate(dK, s.paris_C, s.paris_m, s.dK_th)
    top = float(rate.max())
    da = prev.get("da", s.da)
    return {i: da * float(r) / top for i, r in zip(ids, rate, strict=True) if r > 0}


def _increment_cycles(s: Growth, prev, ids, dK, a_ref, path) -> float:
    """Cycles of the last increment: the Paris law between the leader's dK before and after
    it (:func:`paris_cycles`, a power law in the leader's a), or ``da / rate`` before it
    when the leader has no dK after it (joined the boundary, closed)."""
    lead, da, dK0 = prev["lead"], prev["lead_da"], prev["dK"][prev["lead"]]
    if lead in ids and dK[ids.index(lead)] > 0:
        a1 = a_ref[lead] + path[lead]
        return float(paris_cycles(np.array([a1 - da, a1]), np.array([dK0, dK[ids.index(lead)]]),
                                  s.paris_C, s.paris_m)[-1])
    return da / float(paris_rate(dK0, s.paris_C, s.paris_m))


def _previous(s: Growth, ids, dK, lf, moves, path, a_ref, prev) -> dict:
    out = {"load_factor": lf, "path": {i: path[i] + moves.get(i, 0.0) for i in ids},
           "a_ref": a_ref}
    if s.criterion == "paris":
        lead = max(moves, key=moves.get)
        k = ids.index(lead)
        out.update({"dK": {i: float(v) for i, v in zip(ids, dK, strict=True)}, "lead": lead,
                    "lead_da": moves[lead]})
        da = prev.get("da", s.da)
        if s.adaptive and "dK" in prev and prev.get("lead") == lead and prev["dK"][lead] > 0:
            change = abs(math.log(dK[k] / prev["dK"][lead]))
            da = da * min(2.0, max(0.25, s.dK_change / change)) if change > 0 else 2 * da
            da = min(s.da, max(s.da / 16, da))
        out["da"] = da
    return out
