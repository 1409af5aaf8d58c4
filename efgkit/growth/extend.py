"""Extend the tips of a scene's cracks by one growth increment.

Growing a crack is adding a segment at its tip (seed 003 Sect. 2, Fig. 2). A tip whose
increment reaches the boundary (an outer edge or a hole) stops there: its end becomes a
mouth and the tip is no longer active (the crack joins the boundary). A tip whose increment
reaches another crack's face (seed 003 Sect. 6.1: cracks that "curve around and meet each
other behind the tip"; Sect. 6.5) joins that crack: the new segment is cut where it meets
the face, and its end becomes a junction (not a tip; :mod:`efgkit.problem.junctions`). An
increment that would end within ``snap da`` of the boundary runs on to it; one that would
end within ``JOIN_SNAP da`` of another crack's face joins it (smaller: cracks that pass
close by, as in seed 003 Sect. 6.1 at 15 and 5 degrees, must not be pulled together).
Other tips go on growing; the loop stops only when the cracks cut a piece off the body
(:func:`~efgkit.problem.junctions.split_by_cracks`, a rigid-body mode) or a tip runs into
its own crack. Tips that arrive in the same increment arrive in the order of ``s / da``
(the tips grow together over an increment): a later arrival that would cut a piece off
together with an earlier one is held for the next solve (:func:`advance`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..problem.junctions import split_by_cracks

__all__ = ["JOIN_SNAP", "Advance", "advance", "ray_hits"]

JOIN_SNAP = 0.1  # an increment ending within this fraction of da of another crack joins it
TIE = 1e-9  # arrivals within this fraction of da of each other are simultaneous (none held)


def ray_hits(origin: np.ndarray, direction: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distances along the ray ``origin + s direction`` (s > 0, ``direction`` unit, (2,))
    to the segments ``(m, 2, 2)`` it meets, inf where it misses, shape (m,)."""
    if len(segments) == 0:
        return np.zeros(0)
    a, e = segments[:, 0], segments[:, 1] - segments[:, 0]
    w = a - origin
    den = direction[0] * e[:, 1] - direction[1] * e[:, 0]
    par = np.abs(den) <= 1e-14 * np.linalg.norm(e, axis=1)
    den = np.where(par, 1.0, den)
    s = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / den
    u = (w[:, 0] * direction[1] - w[:, 1] * direction[0]) / den
    hit = ~par & (s > 0) & (u >= -1e-12) & (u <= 1 + 1e-12)
    return np.where(hit, s, np.inf)


@dataclass(frozen=True)
class Advance:
    """The result of one increment.

    Attributes
    ----------
    scene : Scene or None
        The scene with the extended cracks; None when the increment cannot be made
        (``stop`` says why).
    events : tuple of str
        What happened to tips (joined the boundary), for the event log.
    joined : tuple of str
        Ids of the tips that reached the boundary or another crack in this increment.
    stop : str or None
        Why the loop cannot go on (the cracks cut a piece off, a crack runs into itself).
    held : tuple of str
        Ids of tips whose increment was not made because, together with a tip that arrived
        earlier in the same increment, it would cut a piece off (they grow again from the
        next solve, which sees the earlier arrival).
    """

    scene: object
    events: tuple[str, ...] = ()
    joined: tuple[str, ...] = ()
    stop: str | None = None
    held: tuple[str, ...] = ()


def advance(scene, moves: dict, snap: float = 0.5) -> Advance:
    """Extend tips of ``scene`` by ``moves = {tip id: (da, kink angle)}``.

    Tips that reach the boundary or another crack in the same increment arrive in the
    order of ``s / da``, the fraction of its increment each has grown when it arrives (the
    tips grow together over the increment). When their arrivals together cut a piece off
    the body but the earlier ones alone do not (two cracks from two holes that each reach
    the other's hole, seed 003 Sect. 6.1), the later tips are held: they do not move in
    this increment (an event says so, ``Advance.held`` names them), and the next solve,
    with the earlier arrivals joined, gives them their K and kink. Arrivals within ``TIE``
    da of each other are simultaneous (both ends of a centre crack reaching the two edges
    of a symmetric plate): none is held. Only when the first arrival itself cuts a piece
    off (or holding cannot avoid the cut) does the increment stop, naming every arrival.

    Parameters
    ----------
    scene : Scene
    moves : dict str -> (float, float)
        Increment length (> 0) and kink angle (radians, tip frame) per tip id; tips not
        listed stay.
    snap : float
        An increment that would end within ``snap * da`` of the boundary runs on to it
        (within ``JOIN_SNAP * da`` of another crack: it joins that crack).

    Returns
    -------
    Advance
    """
    adv, arrival, cut = _extend(scene, moves, snap)
    if not cut or len(arrival) < 2:
        return adv
    order = sorted(arrival, key=lambda k: arrival[k][0])  # first arrival first
    for n_keep in range(len(order) - 1, 0, -1):
        if arrival[order[n_keep]][0] <= arrival[order[n_keep - 1]][0] + TIE:
            continue  # arriving together (a symmetric scene): no order to hold one by
        held = order[n_keep:]
        trial, _, _ = _extend(scene, {k: v for k, v in moves.items() if k not in held}, snap)
        if trial.stop is None:
            first = ", ".join(order[:n_keep])
            notes = tuple(f"tip {k} held: its increment would reach {arrival[k][1]} after "
                          f"{arrival[k][0]:.4g} da, and with tip {first} (arrived after "
                          f"{arrival[order[0]][0]:.4g} da) cut a piece off the body; it grows "
                          "from the next solve" for k in held)
            return replace(trial, events=trial.events + notes, held=tuple(held))
    return adv


def _extend(scene, moves: dict, snap: float):
    """:func:`advance` without holding tips: the Advance and, per tip that arrived,
    ``(s / da, what it reached)`` (dict), and whether the cracks cut a piece off."""
    arrival = {}
    bnd = scene.domain.boundary_segments()
    cracks = list(scene.cracks)
    events, joined = [], []
    for k, c in enumerate(cracks):
        new = c
        for tip in c.tip_list:
            if tip.id not in moves:
                continue
            da, angle = moves[tip.id]
            d = np.array([math.cos(tip.angle + angle), math.sin(tip.angle + angle)])
            own = new.segments[:-1] if tip.end == 1 else new.segments[1:]
            reach = da * (1.0 + snap)
            s_b = ray_hits(tip.x, d, bnd).min(initial=np.inf)
            s_own = ray_hits(tip.x, d, own).min(initial=np.inf)
            hits = [(ray_hits(tip.x, d, o.segments).min(initial=np.inf), j)
                    for j, o in enumerate(cracks) if j != k]
            s_c, j = min(hits, default=(np.inf, -1))
            first = min(s_own, s_c)  # a crack in the way comes before the boundary snap
            if first < s_b and first <= da * (1.0 + JOIN_SNAP):
                if s_own <= s_c:
                    hit = tip.x + s_own * d
                    return Advance(None, tuple(events), tuple(joined),
                                   f"tip {tip.id} runs into its own crack at "
                                   f"{np.round(hit, 12).tolist()}: a crack closing on itself is "
                                   "not supported"), arrival, False
                s_end, onto = s_c, True
            elif s_b <= reach and s_b < first:
                s_end, onto = s_b, False
            else:
                new = new.extended(float(da), float(angle), end=tip.end)
                continue
            v = tip.x + s_end * d
            if onto:  # onto the face of crack j: exactly on its segment
                seg, t, _ = cracks[j].project(v[None])
                a_, b_ = cracks[j].segments[seg[0]]
                v = a_ + t[0] * (b_ - a_)
            if s_end <= 1e-6 * da:  # the tip is at the face already: move it there, no new segment
                verts = new.vertices.copy()
                verts[-1 if tip.end == 1 else 0] = v
            else:
                verts = np.vstack([new.vertices, v]) if tip.end == 1 else np.vstack([v, new.vertices])
            tips = list(new.tips)
            tips[tip.end] = False
            new = replace(new, vertices=verts, tips=tuple(tips))
            where = f"joined crack {cracks[j].name!r}" if onto else "reached the boundary"
            events.append(f"tip {tip.id} {where} at {np.round(v, 12).tolist()} (after "
                          f"{s_end:.6g}); it is {'a junction' if onto else 'a mouth'} now")
            joined.append(tip.id)
            arrival[tip.id] = (float(s_end / da), (f"crack {cracks[j].name!r}" if onto else
                                                   "the boundary") + f" at {np.round(v, 12).tolist()}")
        cracks[k] = new
    cut = split_by_cracks(cracks, scene.domain)
    if cut is not None:
        return Advance(None, tuple(events), tuple(joined),
                       f"the cracks {', '.join(repr(n) for n in cut)} cut the body into "
                       f"separate pieces ({'; '.join(events)}): a piece cut off moves as a "
                       "rigid body, the loop ends before it"), arrival, True
    return Advance(scene.with_cracks(cracks), tuple(events), tuple(joined)), arrival, False
