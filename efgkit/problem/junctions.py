"""Where the crack ends that are not tips attach, and whether the cracks split the body.

A crack end that is not a tip lies on the domain boundary (a *mouth*: an edge crack, a crack
from a hole) or, once cracks grow into each other, on another crack's face (a *junction*:
seed 003 Sect. 6.1, the cracks "curve around and meet each other behind the tip"; Sect. 6.5,
cracks growing into holes and cracks). For the crack rules a junction is a mouth
(:mod:`efgkit.approx.crack_rules` prolongs a crack ``MOUTH_REACH d_mI`` past every end that
is not a tip); nothing is enriched there (no tip).

Cracks whose ends are attached cut the body along arcs. An arc between two different
boundary components (a loop, or a crack already attached to one) joins them and leaves the
body in one piece (a crack from one hole to another makes the two holes one); an arc whose
two ends reach the same component closes a curve and cuts a piece off (an edge crack run
through to the opposite edge, a crack from a hole back to the same hole, two cracks that
meet behind their tips between two holes). That is a cycle in the graph whose vertices are
the loops and the cracks and whose edges are the attached ends: :func:`split_by_cracks`
finds it with a union-find over the attachments. A piece cut off is a rigid body unless it
has its own supports, so :class:`~efgkit.problem.scene.Scene` refuses such scenes and the
growth loops stop there.

Examples
--------
>>> from efgkit.problem.crack import Crack
>>> from efgkit.problem.geometry import Domain
>>> dom = Domain.rectangle(0, 0, 2, 2)
>>> edge = Crack([[0.0, 1.0], [1.0, 1.0]], tips=(False, False), name="e")
>>> split_by_cracks([edge], dom) is None   # an end in the body is not attached
True
>>> through = Crack([[0.0, 1.0], [2.0, 1.0]], tips=(False, False), name="t")
>>> split_by_cracks([through], dom)
('t',)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Attachment", "attachments", "split_by_cracks"]


@dataclass(frozen=True)
class Attachment:
    """Where a crack end that is not a tip lies.

    Attributes
    ----------
    crack : int
        Index of the crack (in the sequence given).
    end : int
        0 (first vertex) or 1 (last vertex).
    loop : int or None
        Index into ``domain.loops`` of the boundary loop the end lies on, else None.
    other : int or None
        Index of the crack on whose face the end lies (a junction), else None.
    distance : float
        Distance of the end to that loop or crack (inf when neither is within ``tol``).
    """

    crack: int
    end: int
    loop: int | None
    other: int | None
    distance: float


def _polyline_distance(x: np.ndarray, segs: np.ndarray) -> float:
    """Distance of the point ``x (2,)`` to the segments ``segs (m, 2, 2)``."""
    a, ab = segs[:, 0], segs[:, 1] - segs[:, 0]
    t = np.clip(np.einsum("md,md->m", x - a, ab) / np.einsum("md,md->m", ab, ab), 0.0, 1.0)
    return float(np.hypot(*(x - a - t[:, None] * ab).T).min())


def attachments(cracks, domain, tol: float | None = None) -> list[Attachment]:
    """Where every crack end that is not a tip lies: on a loop of ``domain`` (preferred) or
    on another crack, within ``tol`` (default ``1e-9 domain.size``, the Scene's tolerance);
    ``loop`` and ``other`` both None when neither is that close."""
    tol = 1e-9 * domain.size if tol is None else tol
    loops = []
    for loop in domain.loops:
        p, _ = loop.polyline()
        loops.append(np.stack([p, np.roll(p, -1, axis=0)], axis=1))
    out = []
    for i, c in enumerate(cracks):
        for end in (0, 1):
            if c.tips[end]:
                continue
            x = c.vertices[-1 if end else 0]
            dl = [_polyline_distance(x, s) for s in loops]
            k = int(np.argmin(dl))
            if dl[k] <= tol:
                out.append(Attachment(i, end, k, None, dl[k]))
                continue
            dc = [(_polyline_distance(x, o.segments), j) for j, o in enumerate(cracks) if j != i]
            d, j = min(dc, default=(np.inf, -1))
            out.append(Attachment(i, end, None, j, d) if d <= tol
                       else Attachment(i, end, None, None, min(d, dl[k])))
    return out


def split_by_cracks(cracks, domain, tol: float | None = None) -> tuple[str, ...] | None:
    """The names of the cracks that close a cut through the body, or None if it is in one
    piece.

    Union-find over the vertices "loop k" and "crack i" with one edge per attached end
    (:func:`attachments`); the first end whose two vertices are already connected closes a
    curve of cracks and boundary that separates a piece. Returned: the cracks on that
    curve's component (the one just attached first).
    """
    n_loops = len(domain.loops)
    parent = list(range(n_loops + len(cracks)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    for a in attachments(cracks, domain, tol):
        if a.loop is None and a.other is None:
            continue
        u = n_loops + a.crack
        v = a.loop if a.loop is not None else n_loops + a.other
        ru, rv = root(u), root(v)
        if ru == rv:
            names = [cracks[a.crack].name] + [c.name for k, c in enumerate(cracks)
                                              if k != a.crack and root(n_loops + k) == ru]
            return tuple(names)
        parent[ru] = rv
    return None
