"""Where cracks may lie in a body: tips inside, mouths on the boundary or on another crack
(a junction), no crossings, no piece cut off, no crack shorter than ``MIN_CRACK_LENGTH`` of
the domain size. Checked by :class:`~efgkit.problem.scene.Scene` for its cracks and for
the cracks of its :class:`~efgkit.problem.symmetry.Symmetry`."""

from __future__ import annotations

import numpy as np

from .crack import Crack
from .geometry import Domain, segments_intersect
from .junctions import split_by_cracks

__all__ = ["MIN_CRACK_LENGTH", "check_cracks"]

# Cracks shorter than this fraction of the domain size are refused (the Scene knows no spacing;
# a crack must also be a few spacings long for its SIFs, which the J domains check).
MIN_CRACK_LENGTH = 1e-9


def check_cracks(cracks, domain: Domain) -> None:
    """Cracks lie in the body: tips inside, mouths on the boundary or on another crack (a
    junction), no crossings, no piece cut off (:func:`~efgkit.problem.junctions.split_by_cracks`)."""
    names = set()
    tol = 1e-9 * domain.size
    bnd = domain.boundary_segments()
    for c in cracks:
        if not isinstance(c, Crack):
            raise TypeError(f"cracks must hold Crack objects, got {type(c).__name__}")
        if c.name in names:
            raise ValueError(f"two cracks are named {c.name!r}: crack names must be unique")
        names.add(c.name)
        if c.length < MIN_CRACK_LENGTH * domain.size:
            raise ValueError(
                f"crack {c.name!r} is {c.length:.3g} long, shorter than {MIN_CRACK_LENGTH:g} of the "
                f"domain size {domain.size:.6g}: no node spacing resolves it (its SIFs would need "
                "J domains holding points within a fraction of its length); remove it, or make "
                "it at least a few node spacings long")
        v = c.vertices
        dist = domain.distance_to_boundary(v)
        inside = domain.contains(v)
        for k, (d, ins) in enumerate(zip(dist, inside, strict=True)):
            end = 0 if k == 0 else 1 if k == len(v) - 1 else None
            if end is not None and not c.tips[end]:
                if d > tol and not _on_other_crack(v[k], c, cracks, tol):
                    raise ValueError(
                        f"crack {c.name!r}: vertex {k} {v[k].tolist()} is a mouth (tips[{end}] is "
                        f"False) but lies {d:.3g} from the domain boundary and on no other "
                        "crack; put it on the boundary or on another crack's face, or make it a tip")
                continue
            what = "tip" if end is not None else "vertex"
            if not ins or d <= tol:
                where = "on the domain boundary" if d <= tol else "outside the domain"
                raise ValueError(
                    f"crack {c.name!r}: {what} {k} {v[k].tolist()} lies {where}; cracks must run "
                    "inside the body (a crack along the boundary is just boundary; a crack on the "
                    "symmetry line of a half or quarter model goes in Scene(symmetry=Symmetry(...)))")
        # No segment may cross the boundary; a mouth touches it at its vertex only, so the
        # segment at a mouth is tested without its last 1e-7 of length.
        last = len(v) - 2
        for k, (a, b) in enumerate(c.segments):
            a = a + 1e-7 * (b - a) if k == 0 and not c.tips[0] else a
            b = b + 1e-7 * (a - b) if k == last and not c.tips[1] else b
            hit = segments_intersect(np.broadcast_to(a, (len(bnd), 2)), np.broadcast_to(b, (len(bnd), 2)),
                                     bnd[:, 0], bnd[:, 1])
            if hit.any():
                raise ValueError(
                    f"crack {c.name!r}: segment {k} (vertices {k}-{k + 1}) crosses the domain boundary "
                    f"near {bnd[np.argmax(hit), 0].tolist()}; cracks must run inside the body")
    # a junction (an end that is not a tip, on another crack) touches that crack at its end
    # only: its segment is tested without its last 1e-7 of length, as at a mouth
    segs = [(c.name, k, s) for c in cracks for k, s in enumerate(_trimmed_segments(c, domain, tol))]
    for i in range(len(segs)):
        for j in range(i + 1, len(segs)):
            (n1, k1, s1), (n2, k2, s2) = segs[i], segs[j]
            if n1 != n2 and segments_intersect(s1[None, 0], s1[None, 1], s2[None, 0], s2[None, 1])[0]:
                raise ValueError(
                    f"cracks {n1!r} (segment {k1}) and {n2!r} (segment {k2}) intersect; "
                    "crossing or branching cracks are not supported (a crack may end on another "
                    "crack's face: make that end a mouth, tips False)")
    cut = split_by_cracks(cracks, domain, tol)
    if cut is not None:
        raise ValueError(
            f"cracks {', '.join(repr(n) for n in cut)} cut the body into separate pieces (their "
            "ends that are not tips join the boundary and each other in a closed curve): a piece "
            "cut off moves as a rigid body and the stiffness matrix is singular; model the "
            "pieces as separate scenes, or make an end a tip")


def _on_other_crack(x, crack: Crack, cracks, tol: float) -> bool:
    """Whether the point ``x (2,)`` lies within ``tol`` of a crack other than ``crack``."""
    return any(o.name != crack.name and o.distance(x[None])[0] <= tol for o in cracks)


def _trimmed_segments(c: Crack, domain: Domain, tol: float) -> np.ndarray:
    """The segments of ``c`` (m, 2, 2), the first and last shortened by 1e-7 of their length
    at an end that is not a tip and lies off the boundary (a junction on another crack)."""
    s = c.segments.copy()
    for end, k, j in ((0, 0, 0), (1, -1, 1)):
        if not c.tips[end] and domain.distance_to_boundary(c.vertices[[0, -1][end]])[0] > tol:
            s[k, j] = s[k, j] + 1e-7 * (s[k, 1 - j] - s[k, j])
    return s
