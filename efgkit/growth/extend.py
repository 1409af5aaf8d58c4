"""Extend the tips of a scene's cracks by one growth increment.

Growing a crack is adding a segment at its tip (seed 003 Sect. 2, Fig. 2). A tip whose
increment reaches the boundary (an outer edge or a hole) stops there: its end becomes a
mouth and the tip is no longer active (the crack joins the boundary). A tip whose
increment reaches another crack stops the loop: crossing and branching cracks are not
supported by :class:`~efgkit.problem.scene.Scene`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["Advance", "advance", "ray_hits"]


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
        Ids of the tips that reached the boundary in this increment.
    stop : str or None
        Why the loop cannot go on (a crack cut the body through, cracks meet).
    """

    scene: object
    events: tuple[str, ...] = ()
    joined: tuple[str, ...] = ()
    stop: str | None = None


def advance(scene, moves: dict, snap: float = 0.5) -> Advance:
    """Extend tips of ``scene`` by ``moves = {tip id: (da, kink angle)}``.

    Parameters
    ----------
    scene : Scene
    moves : dict str -> (float, float)
        Increment length (> 0) and kink angle (radians, tip frame) per tip id; tips not
        listed stay.
    snap : float
        An increment that would end within ``snap * da`` of the boundary runs on to it.

    Returns
    -------
    Advance
    """
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
            others = [s for j, o in enumerate(cracks) if j != k for s in o.segments]
            own = new.segments[:-1] if tip.end == 1 else new.segments[1:]
            reach = da * (1.0 + snap)
            s_b = ray_hits(tip.x, d, bnd).min(initial=np.inf)
            s_c = ray_hits(tip.x, d, np.array(others + list(own)).reshape(-1, 2, 2)).min(initial=np.inf)
            if s_c <= min(s_b, da) + 1e-12 * da:
                hit = tip.x + s_c * d
                return Advance(None, tuple(events), tuple(joined),
                               f"tip {tip.id} reaches a crack at {np.round(hit, 12).tolist()}: "
                               "joining or crossing cracks is not supported")
            if s_b <= reach:
                v = tip.x + s_b * d
                verts = (np.vstack([new.vertices, v]) if tip.end == 1 else np.vstack([v, new.vertices]))
                tips = list(new.tips)
                tips[tip.end] = False
                if not any(tips):
                    return Advance(None, tuple(events), tuple(joined),
                                   f"crack {c.name!r} cuts the body through: tip {tip.id} reaches "
                                   f"the boundary at {np.round(v, 12).tolist()} and the crack's "
                                   "other end is on the boundary too")
                new = replace(new, vertices=verts, tips=tuple(tips))
                events.append(f"tip {tip.id} reached the boundary at {np.round(v, 12).tolist()} "
                              f"(after {s_b:.6g}); it is a mouth now")
                joined.append(tip.id)
            else:
                new = new.extended(float(da), float(angle), end=tip.end)
        cracks[k] = new
    return Advance(scene.with_cracks(cracks), tuple(events), tuple(joined))
