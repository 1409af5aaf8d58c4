"""Quadrature on MLPG sub-domains: discs and sectors clipped to the visible body (seed 002 Eq. 39).

Every node I owns a disc of radius r_sI. The part of it inside the body and visible
from x_I is star-shaped from x_I, so it is integrated in polar coordinates about x_I:
angles theta_i of an angular rule on the node's sector [theta_a, theta_a + Theta]
(Theta = 2 pi for interior nodes; the interior angle at boundary and crack-face
nodes), and on each ray a radial rule on [0, r_max(theta_i)], with
r_max(theta) = min(r_sI, distance to the first boundary, hole or crack segment along
the ray) by ray casting (vectorised over (ray, segment) pairs of the nodes whose disc
reaches a segment, in chunks).

Rules (n_r = ``radial``, n_theta = ``angular``):

* ``"midpoint"``, seed 002 Eq. (39) (De and Bathe 2001): theta_i = theta_a +
  (i - 1/2) dtheta, dtheta = Theta / n_theta (the seed prints theta_init + theta_init
  (i - 1/2) dtheta, a typo); ring j of width dr = r_max / n_r at its centroid radius
  r_j = (j^2 - j + 1/3) / (j - 1/2) dr with weight (j - 1/2) dr^2 dtheta (the area of
  the ring sector; the seed prints no weights). Per ring it integrates a + b r exactly
  (measure r dr); on a full disc it is exact for polynomials of total degree <= 1 (and
  for (a + b r) times trigonometric polynomials of degree < n_theta), on a sector for
  degree 0 only.
* ``"gauss"``: Gauss-Jacobi in r (weight r on [0, r_max], n_r points, exact for r^p,
  p <= 2 n_r - 1) times, on a full disc, the equally spaced rule in theta (the Gauss
  rule of trigonometric polynomials: exact to degree n_theta - 1) and on a sector
  Gauss-Legendre in theta (exact for polynomials in theta of degree 2 n_theta - 1).
  On a full disc it is exact for polynomials of total degree <= min(2 n_r - 1,
  n_theta - 1); on a sector with straight sides it is accurate but not exact for
  x^a y^b of degree >= 1 (their theta factors are trigonometric).

Clipped rays make r_max(theta) piecewise smooth, so neither rule is exact on cut discs.
"""

from __future__ import annotations

import numpy as np
from scipy.special import roots_jacobi

from .rules import Points, check_count, gauss_legendre

__all__ = ["RULES", "edge_segments", "polar_rule", "ray_lengths", "near_pairs", "sectors", "disc_points",
           "disc_rays", "polar_points", "sorted_points", "boundary_pieces"]

RULES = ("midpoint", "gauss")
CHUNK = 2_000_000  # (ray or node, segment) pairs per vectorised block


def polar_rule(rule: str, radial: int, angular: int, full: bool):
    """Reference rule: angles ``t (n_theta,)`` as fractions of the sector in [0, 1] with
    weights ``wt`` summing to 1, and radii ``rho (n_r,)`` as fractions of r_max with
    weights ``wr`` such that ``sum wr f(rho r) r^2 ~ int_0^r f(s) s ds``.

    Examples
    --------
    >>> t, wt, rho, wr = polar_rule("midpoint", 5, 8, True)
    >>> round(float(wr.sum()), 15), round(float(wt.sum()), 15)   # int_0^1 s ds = 1/2
    (0.5, 1.0)
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, got {rule!r}")
    check_count("radial", radial)
    check_count("angular", angular)
    if rule == "midpoint" or full:
        t = (np.arange(angular) + 0.5) / angular
        wt = np.full(angular, 1.0 / angular)
    else:
        xi, g = gauss_legendre(angular)
        t, wt = (xi + 1) / 2, g / 2
    if rule == "midpoint":
        j = np.arange(1, radial + 1, dtype=float)
        dr = 1.0 / radial
        rho = (j * j - j + 1.0 / 3.0) / (j - 0.5) * dr
        wr = (j - 0.5) * dr * dr
    else:
        a, g = roots_jacobi(radial, 0.0, 1.0)  # weight (1 + a) on [-1, 1]
        rho, wr = (a + 1) / 2, g / 4
    return t, wt, rho, wr


def edge_segments(edges, breaks: np.ndarray | None = None):
    """The polyline segments of ``edges`` split at the points ``breaks (b, 2)`` on them
    (crack mouths): ``segments (s, 2, 2)``, ``edge (s,)`` the index of each one's edge and
    ``s_ends (s, 2)`` the edge parameters of its ends.

    Examples
    --------
    >>> from efgkit.problem.geometry import Domain
    >>> seg, edge, s = edge_segments(Domain.rectangle(0, 0, 1, 1).edges(), np.array([[0.5, 0.0]]))
    >>> len(seg), edge.tolist(), s[:2].tolist()
    (5, [0, 0, 1, 2, 3], [[0.0, 0.5], [0.5, 1.0]])
    """
    from .boundary import break_parameters, merge_knots

    segs, owner, params = [], [], []
    for k, e in enumerate(edges):  # tiny loop over the edges
        m = len(e.polyline()) - 1
        knots = merge_knots(np.linspace(0.0, 1.0, m + 1), break_parameters(e, breaks))
        p, _ = e.at(knots)
        p[0], p[-1] = e.start, e.end
        segs.append(np.stack([p[:-1], p[1:]], axis=1))
        owner.append(np.full(len(knots) - 1, k))
        params.append(np.column_stack([knots[:-1], knots[1:]]))
    return np.concatenate(segs), np.concatenate(owner), np.concatenate(params)


def near_pairs(x: np.ndarray, r: np.ndarray, segments: np.ndarray, tol: float = 0.0):
    """(point, segment) pairs with the segment closer than ``r + tol`` to the point.

    ``x (n, 2)``, ``r (n,)``, ``segments (s, 2, 2)``. Returns ``i, j (p,)`` sorted by i,
    and the projection parameter ``u (p,)`` in [0, 1] and distance ``d (p,)``.
    """
    n, s = len(x), len(segments)
    if n == 0 or s == 0:
        z = np.zeros(0, np.int64)
        return z, z, np.zeros(0), np.zeros(0)
    a, e = segments[:, 0], segments[:, 1] - segments[:, 0]
    ee = np.maximum(np.einsum("sd,sd->s", e, e), 1e-300)
    out = [[], [], [], []]
    step = max(1, CHUNK // s)
    for k in range(0, n, step):
        p = x[k:k + step, None, :] - a[None]
        u = np.clip(np.einsum("nsd,sd->ns", p, e) / ee, 0.0, 1.0)
        d = np.hypot(*(p - u[..., None] * e).transpose(2, 0, 1))
        i, j = np.nonzero(d < (r[k:k + step, None] + tol))
        for lst, v in zip(out, (i + k, j, u[i, j], d[i, j]), strict=True):
            lst.append(v)
    return tuple(np.concatenate(v) for v in out)


def ray_lengths(origin: np.ndarray, theta: np.ndarray, r_max: np.ndarray, segments: np.ndarray,
                tol: float | np.ndarray = 0.0) -> np.ndarray:
    """Distance along rays to the first segment they cross, capped at ``r_max``.

    ``origin (n, 2)``, ``theta (n, a)`` ray angles, ``r_max (n,)``, ``segments (s, 2, 2)``;
    crossings closer than ``tol`` (scalar or (n,)) are ignored (rays leaving a segment
    their origin lies on). Only the segments within ``r_max`` of an origin are tested.
    Returns ``(n, a)``.

    Examples
    --------
    >>> seg = np.array([[[1.0, -1.0], [1.0, 1.0]]])
    >>> ray_lengths(np.zeros((1, 2)), np.array([[0.0, np.pi]]), np.array([2.0]), seg).tolist()
    [[1.0, 2.0]]
    """
    n, na = theta.shape
    out = np.repeat(np.asarray(r_max, float)[:, None], na, axis=1)
    tol = np.broadcast_to(np.asarray(tol, float), (n,))
    i, j, _, _ = near_pairs(origin, r_max, segments)
    if len(i) == 0:
        return out
    step = max(1, CHUNK // na)
    for k in range(0, len(i), step):
        ii, jj = i[k:k + step], j[k:k + step]
        a, e = segments[jj, 0], segments[jj, 1] - segments[jj, 0]
        ap = a - origin[ii]  # (p, 2)
        dx, dy = np.cos(theta[ii]), np.sin(theta[ii])  # (p, a)
        den = dx * e[:, 1, None] - dy * e[:, 0, None]  # d x e
        safe = np.where(np.abs(den) > 1e-300, den, 1.0)
        t = (ap[:, 0, None] * e[:, 1, None] - ap[:, 1, None] * e[:, 0, None]) / safe
        u = (ap[:, 0, None] * dy - ap[:, 1, None] * dx) / safe
        hit = (np.abs(den) > 1e-14 * np.hypot(*e.T)[:, None]) & (u >= 0) & (u <= 1) & \
            (t > tol[ii, None])
        t = np.where(hit, t, np.inf)
        np.minimum.at(out, ii, t)  # rows of one node may span chunks
    return out


def sectors(x: np.ndarray, r: np.ndarray, segments: np.ndarray, inside, side=None,
            tol: float = 1e-6):
    """The angular sector ``[theta_a, theta_a + span]`` of every node's visible disc.

    Nodes farther than ``tol r`` from every segment get the full circle (theta_a = 0,
    span = 2 pi). A node on segments (the boundary, a crack face, a tip) has the
    directions of those segments leaving it; between consecutive directions lie the
    candidate sectors, and it gets the widest whose bisector enters the body
    (``inside(points (m, 2)) -> bool (m,)``) on its own side (``side (n, 2)``: for a
    node split on a crack face, a vector pointing into its face's material, else 0).
    A node with no such sector gets span 0.

    Returns ``theta_a (n,)``, ``span (n,)``.
    """
    n = len(x)
    theta_a, span = np.zeros(n), np.full(n, 2 * np.pi)
    i, j, u, d = near_pairs(x, tol * r, segments, tol=1e-300)
    if len(i) == 0:
        return theta_a, span
    e = segments[j, 1] - segments[j, 0]
    ang = np.arctan2(e[:, 1], e[:, 0])
    eps = 1e-9
    inner = (u > eps) & (u < 1 - eps)
    dirs = np.concatenate([ang[inner], ang[inner] + np.pi, ang[~inner & (u <= eps)],
                           ang[~inner & (u >= 1 - eps)] + np.pi])
    owner = np.concatenate([i[inner], i[inner], i[~inner & (u <= eps)], i[~inner & (u >= 1 - eps)]])
    dirs = np.mod(dirs, 2 * np.pi)
    nodes, local = np.unique(owner, return_inverse=True)
    order = np.lexsort((dirs, local))
    dirs, local = dirs[order], local[order]
    counts = np.bincount(local, minlength=len(nodes))
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    pos = np.arange(len(dirs)) - first[local]
    nxt = np.where(pos + 1 < counts[local], np.arange(len(dirs)) + 1, first[local])
    gap = np.mod(dirs[nxt] - dirs, 2 * np.pi)
    gap = np.where(counts[local] == 1, 2 * np.pi, gap)
    mid = dirs + gap / 2
    probe = x[nodes[local]] + (1e-4 * r[nodes[local]])[:, None] * np.column_stack(
        [np.cos(mid), np.sin(mid)])
    ok = np.asarray(inside(probe), bool) & (gap > 1e-12)
    if side is not None:
        s = side[nodes[local]]
        has = np.hypot(*s.T) > 0
        ok &= ~has | (np.einsum("nd,nd->n", s, probe - x[nodes[local]]) > 0)
    score = np.where(ok, gap, -1.0)
    best = np.full(len(nodes), -1)
    key = np.lexsort((-score, local))  # per node, the widest valid gap first
    firsts = key[np.concatenate([[True], local[key][1:] != local[key][:-1]])]
    best[local[firsts]] = firsts
    valid = score[best] > 0
    theta_a[nodes] = np.where(valid, dirs[best], 0.0)
    span[nodes] = np.where(valid, gap[best], 0.0)
    return theta_a, span


def disc_points(x: np.ndarray, r: np.ndarray, segments: np.ndarray, theta_a: np.ndarray,
                span: np.ndarray, rule: str = "midpoint", radial: int = 5, angular: int = 8,
                tol: float = 1e-6, piece_angular: int | None = None) -> Points:
    """Quadrature points of the visible discs of radii ``r (n,)`` about ``x (n, 2)``.

    The sector ``theta_a, span (n,)`` comes from :func:`sectors`; ``segments (s, 2, 2)``
    are all boundary, hole and crack segments (rays stop at the first). With
    ``rule="gauss"`` a disc cut by a segment is integrated on its angular pieces with
    ``piece_angular`` (default ``angular``) Gauss-Legendre points each. Returns Points
    with ``owner (m,)`` the node of each point; points of zero weight are dropped.

    Examples
    --------
    >>> pts = disc_points(np.zeros((1, 2)), np.ones(1), np.zeros((0, 2, 2)), np.zeros(1),
    ...                   np.full(1, 2 * np.pi))
    >>> pts.n, round(float(pts.w.sum() - np.pi), 14)   # 5 x 8, the area pi r^2
    (40, 0.0)
    """
    _, _, rho, wr = polar_rule(rule, radial, 1, True)
    rays = disc_rays(x, r, segments, theta_a, span, rule, angular, tol, piece_angular)
    return sorted_points([polar_points(x[k], k, theta, rm[:, :, None] * rho,  # (m, a, n_r)
                                       dth[:, :, None] * rm[:, :, None] ** 2 * wr)
                          for k, theta, dth, rm in rays])


def disc_rays(x: np.ndarray, r: np.ndarray, segments: np.ndarray, theta_a: np.ndarray,
              span: np.ndarray, rule: str = "midpoint", angular: int = 8, tol: float = 1e-6,
              piece_angular: int | None = None):
    """The angular part of :func:`disc_points`: for each kind of disc (full, sector, cut),
    ``(k (m,), theta (m, a), dtheta (m, a), r_max (m, a))``: the discs' indices, the ray
    angles, their angular weights and the ray lengths (to the circle or the first segment)."""
    full = np.isclose(span, 2 * np.pi)
    cut = np.zeros(len(x), bool)
    if rule == "gauss" and len(segments):
        cut[near_pairs(x, r, segments)[0]] = True
    for kind in ("full", "sector", "pieces"):
        k = np.flatnonzero(full & ~cut if kind == "full" else ~full & ~cut if kind == "sector"
                           else cut)
        if len(k) == 0:
            continue
        na = piece_angular if kind == "pieces" and piece_angular is not None else angular
        t, wt, _, _ = polar_rule(rule, 1, na, kind == "full")
        if kind == "pieces":  # Gauss on the angular pieces between the kinks of r_max
            start, length = angular_pieces(x[k], r[k], segments, theta_a[k], span[k])
            theta = (start[:, :, None] + length[:, :, None] * t).reshape(len(k), -1)
            dth = (length[:, :, None] * wt).reshape(len(k), -1)
        else:
            theta = theta_a[k, None] + span[k, None] * t[None]  # (m, a)
            dth = span[k, None] * wt[None]
        yield k, theta, dth, ray_lengths(x[k], theta, r[k], segments, tol * r[k])


def polar_points(centre: np.ndarray, k: np.ndarray, theta: np.ndarray, rad: np.ndarray,
                  w: np.ndarray) -> Points:
    """Points at radii ``rad (m, a, p)`` on the rays ``theta (m, a)`` from ``centre (m, 2)``,
    owners ``k (m,)``; zero weights dropped."""
    px = centre[:, None, None, 0] + rad * np.cos(theta)[..., None]
    py = centre[:, None, None, 1] + rad * np.sin(theta)[..., None]
    own = np.broadcast_to(k[:, None, None], rad.shape)
    keep = w > 0
    return Points(np.column_stack([px[keep], py[keep]]), w[keep], own[keep])


def sorted_points(parts) -> Points:
    """The points of ``parts`` concatenated, stably sorted by owner."""
    if not parts:
        return Points(np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int64))
    pts = Points.concatenate(*parts)
    order = np.argsort(pts.owner, kind="stable")
    return Points(pts.x[order], pts.w[order], pts.owner[order])


def angular_pieces(x, r, segments, theta_a, span, eps: float = 1e-9):
    """The angles where r_max(theta) of a disc kinks (segment ends inside it, crossings of
    its circle with segments) cut its sector into pieces: ``start, length (n, K)`` (unused
    pieces have length 0)."""
    n = len(x)
    i, j, _, _ = near_pairs(x, r, segments)
    a, e = segments[j, 0], segments[j, 1] - segments[j, 0]
    ap = a - x[i]
    A = np.maximum(np.einsum("pd,pd->p", e, e), 1e-300)
    B = np.einsum("pd,pd->p", ap, e)
    C = np.einsum("pd,pd->p", ap, ap) - r[i] ** 2
    root = np.sqrt(np.maximum(B * B - A * C, 0.0))
    cand = np.stack([np.zeros(len(i)), np.ones(len(i)), (-B - root) / A, (-B + root) / A], 1)
    ok = (cand >= 0) & (cand <= 1)
    ok[:, 0] = np.hypot(*ap.T) < r[i]  # segment ends inside the disc
    ok[:, 1] = np.hypot(*(ap + e).T) < r[i]
    pts = ap[:, None, :] + cand[..., None] * e[:, None, :]  # relative to the node
    ang = np.arctan2(pts[..., 1], pts[..., 0])
    rel = np.mod(ang - theta_a[i, None], 2 * np.pi)
    ok &= (rel > eps) & (rel < span[i, None] - eps) & (np.hypot(*pts.transpose(2, 0, 1)) > eps * r[i, None])
    owner = np.repeat(i, 4)[ok.ravel()]
    rel = rel.ravel()[ok.ravel()]
    counts = np.bincount(owner, minlength=n)
    K = int(counts.max(initial=0)) + 2
    brk = np.repeat(span[:, None], K, axis=1)  # unused breaks sit at the end: zero pieces
    brk[:, 0] = 0.0
    order = np.lexsort((rel, owner))
    owner, rel = owner[order], rel[order]
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    brk[owner, 1 + np.arange(len(owner)) - first[owner]] = rel
    brk = np.sort(brk, axis=1)
    return theta_a[:, None] + brk[:, :-1], np.diff(brk, axis=1)


def boundary_pieces(x: np.ndarray, r: np.ndarray, segments: np.ndarray, seg_edge: np.ndarray,
                    seg_s: np.ndarray, edges, order: int = 8, blockers: np.ndarray | None = None):
    """Gauss points on the pieces of the body boundary inside every node's disc.

    Parameters
    ----------
    x, r : (n, 2), (n,)
        Disc centres and radii.
    segments : (s, 2, 2)
        Boundary polyline segments; ``seg_edge (s,)`` their edge (index into ``edges``) and
        ``seg_s (s, 2)`` the edge parameters of their ends (points are placed by
        ``edge.at``, on the exact arc).
    order : int
        Gauss points per piece (seed 002: 8); a piece is split where the node's
        perpendicular meets it (the test function kinks there when the node lies on it).
    blockers : (b, 2, 2), optional
        Segments that hide a boundary point from the disc's node (cracks and other
        boundary segments); points hidden are dropped.

    Returns
    -------
    Points
        ``x, w, owner`` (the node), ``normal`` (outward); and ``edge (m,)`` int.
    """
    check_count("order", order)
    i, j, _, _ = near_pairs(x, r, segments)
    a, e = segments[j, 0], segments[j, 1] - segments[j, 0]
    ap = a - x[i]
    # |ap + t e|^2 = r^2: the piece of the segment inside the disc
    A = np.einsum("pd,pd->p", e, e)
    B = np.einsum("pd,pd->p", ap, e)
    C = np.einsum("pd,pd->p", ap, ap) - r[i] ** 2
    disc = np.sqrt(np.maximum(B * B - A * C, 0.0))
    t0 = np.clip((-B - disc) / A, 0.0, 1.0)
    t1 = np.clip((-B + disc) / A, 0.0, 1.0)
    # split at the foot of the perpendicular from the node: v(|x - x_I|) kinks there along
    # the line when the node lies on it (a boundary node's own edge)
    tf = np.clip(-B / A, t0, t1)
    i, j = np.concatenate([i, i]), np.concatenate([j, j])
    t0, t1 = np.concatenate([t0, tf]), np.concatenate([tf, t1])
    keep = t1 - t0 > 1e-12
    i, j, t0, t1 = i[keep], j[keep], t0[keep], t1[keep]
    xi, gw = gauss_legendre(order)
    tt = t0[:, None] + (t1 - t0)[:, None] * (xi + 1)[None] / 2  # (p, order)
    s = seg_s[j, 0, None] + tt * (seg_s[j, 1] - seg_s[j, 0])[:, None]
    px, tang, lengths = np.zeros(s.shape + (2,)), np.zeros(s.shape + (2,)), np.zeros(len(j))
    for k, edge in enumerate(edges):  # tiny loop over the domain's edges
        m = seg_edge[j] == k
        if m.any():
            px[m], tang[m] = (v.reshape(-1, order, 2) for v in edge.at(s[m].ravel()))
            lengths[m] = edge.length
    w = (gw[None] / 2) * ((t1 - t0) * np.abs(seg_s[j, 1] - seg_s[j, 0]) * lengths)[:, None]
    normal = np.stack([tang[..., 1], -tang[..., 0]], axis=-1)
    owner = np.repeat(i, order)
    pts = px.reshape(-1, 2)
    vis = np.ones(len(pts), bool)
    if blockers is not None and len(blockers):
        vis = visible(x[owner], pts, blockers)
    edge_of = np.repeat(seg_edge[j], order)
    return (Points(pts[vis], w.ravel()[vis], owner[vis], normal.reshape(-1, 2)[vis]),
            edge_of[vis])


def visible(p: np.ndarray, q: np.ndarray, blockers: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Whether the open segments p q ``(n, 2)`` cross none of ``blockers (b, 2, 2)``
    (crossings within ``tol`` of either end do not count), shape (n,)."""
    d = q - p
    length = np.hypot(*d.T)
    theta = np.arctan2(d[:, 1], d[:, 0])[:, None]
    reach = ray_lengths(p, theta, length * (1 - tol), blockers, tol * length)[:, 0]
    return reach >= length * (1 - tol)
