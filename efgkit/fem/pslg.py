"""Triangle's input for :func:`efgkit.fem.mesh.mesh_scene`: the planar straight-line graph of a
scene, the tip fans and refinement points, and the refinement loop that meets a size field.

The graph holds every loop of the domain as a polyline (straight edges split at spacing
``h``, arcs at spacing ``h`` and at most pi/8 of sweep), crack mouths inserted into the
boundary, crack polylines as internal segments; segment marker ``2 + k`` for edge ``k``
of ``domain.edges()`` and ``2 + n_edges + c`` for crack ``c`` (Triangle reserves 0 and 1).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

FIRST_MARK = 2  # first free Triangle segment marker
_ARC_MAX_SWEEP = math.pi / 8  # longest arc piece of the initial polyline
EQUILATERAL_AREA = math.sqrt(3.0) / 4.0  # area of the unit equilateral triangle


def triangle_areas(x, t):
    a, b, c = x[t[:, 0]], x[t[:, 1]], x[t[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def scene_pslg(domain, cracks, h):
    """Vertices (m, 2), segments (k, 2), markers (k,), hole seeds (j, 2), crack vertex ids."""
    loops, k0 = [], 0
    for loop in domain.loops:
        pts, own = [], []
        for k, e in enumerate(loop.edges()):
            n = max(1, math.ceil(e.length / h - 1e-9))
            if e.is_arc:
                n = max(n, math.ceil(abs(e.sweep) / _ARC_MAX_SWEEP - 1e-9))
            x, _ = e.at(np.arange(n) / n)
            x[0] = e.start
            pts.append(x)
            own.append(np.full(n, k0 + k))
        loops.append([np.concatenate(pts), np.concatenate(own)])
        k0 += len(loop.vertices)
    n_edges = k0
    scale = domain.size
    mouth_at = {}
    for ci, c in enumerate(cracks):  # insert the mouths into the boundary polylines
        for end in (0, 1):
            if c.tips[end]:
                continue
            m = c.vertices[0 if end == 0 else -1]
            best = None
            for li, (p, _) in enumerate(loops):
                q = np.roll(p, -1, axis=0)
                ab = q - p
                s = np.clip(np.sum((m - p) * ab, 1) / np.sum(ab * ab, 1), 0, 1)
                d = np.linalg.norm(p + s[:, None] * ab - m, axis=1)
                j = int(np.argmin(d))
                if best is None or d[j] < best[0]:
                    best = (d[j], li, j, s[j])
            if best[0] > 1e-9 * scale:
                raise ValueError(
                    f"crack {c.name!r} ends on another crack's face at {m.tolist()} (a junction): "
                    "the FE reference does not open a node shared by three faces; solve this "
                    "scene with EFG")
            _, li, j, s = best
            p, own = loops[li]
            if s < 1e-9 or s > 1 - 1e-9:
                jj = j if s < 0.5 else (j + 1) % len(p)
            else:
                jj = j + 1
                loops[li] = [np.insert(p, jj, m, axis=0), np.insert(own, jj, own[j])]
            mouth_at[(ci, end)] = (li, loops[li][0][jj].copy())
    verts, segs, marks, holes, base = [], [], [], [], 0
    for li, (p, own) in enumerate(loops):
        n = len(p)
        verts.append(p)
        segs.append(base + np.column_stack([np.arange(n), (np.arange(n) + 1) % n]))
        marks.append(FIRST_MARK + own)
        if li > 0:  # a seed just inside the hole, off the middle of its first segment
            d = p[1 % n] - p[0] if n > 1 else np.array([0.0, 1.0])
            holes.append(0.5 * (p[0] + p[1 % n]) + 1e-4 * np.array([d[1], -d[0]]))
        base += n
    x = np.concatenate(verts)
    crack_ids = []
    for ci, c in enumerate(cracks):
        ids = []
        for k, v in enumerate(c.vertices):
            end = 0 if k == 0 else 1 if k == len(c.vertices) - 1 else None
            if end is not None and (ci, end) in mouth_at:
                ids.append(int(np.argmin(np.linalg.norm(x - mouth_at[(ci, end)][1], axis=1))))
            else:
                x = np.vstack([x, v])
                ids.append(len(x) - 1)
        ids = np.array(ids)
        crack_ids.append(ids)
        segs.append(np.column_stack([ids[:-1], ids[1:]]))
        marks.append(np.full(len(ids) - 1, FIRST_MARK + n_edges + ci))
    if cKDTree(x).query_pairs(1e-12 * scale):
        raise ValueError("two vertices of the domain and crack polylines coincide; check the "
                         "cracks' vertices against the boundary")
    return (x, np.concatenate(segs), np.concatenate(marks), np.array(holes).reshape(-1, 2),
            crack_ids, n_edges)


def triangulate(x, segs, marks, holes, h, size, min_angle):
    """Quality mesh refined until every triangle meets the size field."""
    import triangle

    pslg = {"vertices": x, "segments": segs, "segment_markers": marks[:, None]}
    if len(holes):
        pslg["holes"] = holes
    T = triangle.triangulate(pslg, f"pq{min_angle:g}a{EQUILATERAL_AREA * h * h:.17g}Q")
    for _ in range(60):
        p, t = T["vertices"], T["triangles"]
        area = np.abs(triangle_areas(p, t))
        target = EQUILATERAL_AREA * size(p)[t].min(axis=1) ** 2
        bad = area > target
        if not bad.any():
            break
        T["triangle_max_area"] = np.where(bad, np.maximum(target, area / 4), -1.0)[:, None]
        if len(holes):
            T["holes"] = holes
        T = triangle.triangulate(T, f"rpq{min_angle:g}aQ")
    else:  # pragma: no cover - Triangle meets area limits in a few passes
        raise RuntimeError("Triangle did not meet the element sizes in 60 refinement passes")
    t = T["triangles"].astype(np.int64)
    neg = triangle_areas(T["vertices"], t) < 0
    t[neg] = t[neg][:, [0, 2, 1]]
    return T["vertices"], t, T["segments"].astype(np.int64), T["segment_markers"].ravel()


def refinement_points(refine, domain) -> np.ndarray:
    """``refine`` as a float array (k, 2) of points in the closed domain."""
    try:
        p = np.asarray(refine, dtype=float).reshape(-1, 2)
    except (TypeError, ValueError) as err:
        raise ValueError(f"refine must be points of shape (k, 2), got {refine!r}") from err
    bad = ~(np.all(np.isfinite(p), axis=1) & domain.contains(p, tol=1e-9 * domain.size))
    if bad.any():
        raise ValueError(f"refine point {p[np.argmax(bad)].tolist()} is not a finite point of the "
                         "domain; give points inside it or on its boundary")
    return p


def tip_fans(scene, tips, rho: float, n: int) -> np.ndarray:
    """Fan vertices ((n - 1) per tip, 2) at distance ``rho`` (capped at 0.45 of the free radius:
    the distance to the boundary, other cracks and tips, a kink) around every tip."""
    from ..fracture.sif import tip_limits

    th = np.pi * (2 * np.arange(1, n) / n - 1)
    # fan triangles (two sides r, apex 2 pi / n) must not exceed the tip size's area, or the
    # refinement splits them: r^2 sin(2 pi / n) / 2 <= EQ rho^2
    rho = rho * min(1.0, 0.95 * math.sqrt(EQUILATERAL_AREA / (0.5 * math.sin(2 * math.pi / n))))
    out = []
    for tip in tips:
        free = min(tip_limits(scene, tip).values())
        r = min(rho, 0.45 * free)
        out.append(tip.x + r * np.column_stack([np.cos(tip.angle + th), np.sin(tip.angle + th)]))
    return np.concatenate(out)
