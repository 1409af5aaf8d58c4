"""How node supports see cracks: visibility, diffraction, transparency, see-through.

A crack cuts the line of sight between a node x_I and a point x when the
segment [x_I, x] crosses one of its segments (seed 003 Sect. 2.2, 4). The
rules differ in what a crossing does to the weight w(d_I / d_mI):

* ``visibility`` (Sect. 4.1): the pair is cut (w = 0).
* ``diffraction`` (Sect. 4.2, Eqs. 29-31): the distance is lengthened around
  the tip x_c of the crossed crack, ``d_I = ((s1 + s2) / s0)^lambda s0`` with
  ``s0 = |x - x_I|``, ``s1 = |x_I - x_c|``, ``s2 = |x - x_c|``.
* ``transparency`` (Sect. 4.3, Eqs. 32-34): ``d_I = s0 + d_mI (s_c / sbar_c)^lambda``
  with s_c the distance along the crack from its tip to the crossing point
  and ``sbar_c = kappa h``; crossings with ``s_c >= sbar_c`` cut the pair.
* ``see_through`` (Sect. 4.4, continuous-line criterion): a crossing cuts the
  pair unless the node's support contains a tip of the crossed crack.

Conventions that make every test deterministic:

* a point on a crack line is on the segment's left face
  (:meth:`efgkit.problem.crack.Crack.side`);
* a crack segment is open at a tip: a ray through the tip itself does not
  cross, so a node at the tip sees every point of its support;
* nodes split on a crack (``NodeCloud.face``, ``face_segment``) look from
  ``1e-7 d_mI`` off the crack on their face (at a kink vertex, into their face's
  sector), so ordinary crossing tests separate the two copies;
* a crack reaches ``1e-4 d_mI`` past a mouth (an end that is not a tip): where the crack
  meets the boundary at an angle, a mouth node's copy looks from a point just outside
  the body, and without this its rays passing outside the body around the mouth reached
  the other face in a wedge as wide as the angle between the crack and the boundary's
  normal (edge crack at 7 degrees: energy 14 % low, docs/robustness.md);
* nodes within ``1e-7 d_mI`` of a tip are taken to be at the tip, so that a
  tip moved by a tiny amount across a node changes nothing;
* a node within ``1e-7 d_mI`` of a segment's line meets that line only at itself: beyond
  the segment (a node on the line ahead of a tip) its rays do not cross the segment, and a
  split node's crossing of its own segment is at the node (transparency's s_c is its arc).
  Otherwise a ray from a node a distance e off the line grazes the crack, and s_c ran from
  the point's arc to the node's across a layer of width ~e along the faces; a tip moved
  by 1e-10 h put thin cut cells, and their points, in that layer, where the weight
  gradients reached 1e10 / d_mI (a solution change of 0.48).

Only candidate pairs are tested (:func:`segment_candidates`): many short segments cost little.

Seed 003 prints ds_c/dx_i as -cos(theta), -sin(theta) (Eq. 34, text below it),
which ignores that the crossing point moves along the crack when x moves; the
derivative used here is the exact one (tested against finite differences).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..methods.efg import CRACK_RULES
from ..nodes import NodeCloud
from ..search import Neighbours
from .crack_lines import CrackLines

__all__ = ["CRACK_RULES", "CrackLines", "CrackRule", "crack_distances", "crack_weights",
           "pair_arrays", "padded_weights", "segment_candidates", "sight_positions", "wrap_distance"]

TIP_SNAP = 1e-7  # nodes closer than this fraction of their support radius to a tip are at it
SIGHT_OFFSET = 1e-7  # split nodes look from this fraction of their support radius off the crack
CANDIDATE_SLACK = 1e-6  # relative slack of the candidate test (rounding of grazing crossings)
MOUTH_REACH = 1e-4  # a crack reaches this fraction of d_mI past its mouth (its sight tests)


@dataclass(frozen=True)
class CrackRule:
    """A crack rule and its parameters.

    Parameters
    ----------
    name : {"visibility", "diffraction", "transparency", "see_through"}
    power : float
        lambda of Eq. (29) (diffraction, seed: 1 or 2) or Eq. (32)
        (transparency, >= 2).
    kappa : float
        Transparency: opaque at ``s_c = kappa h`` behind the tip (Eq. 33).
    spacing : float
        h of Eq. (33).
    """

    name: str = "visibility"
    power: float = 2.0
    kappa: float = 0.5
    spacing: float = 1.0

    def __post_init__(self):
        if self.name not in CRACK_RULES:
            raise ValueError(f"crack rule must be one of {CRACK_RULES}, got {self.name!r}")
        for key in ("power", "kappa", "spacing"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
                raise ValueError(f"crack rule {key} must be finite and > 0, got {v!r}")
        if self.name == "transparency" and self.power < 2:
            raise ValueError(f"transparency needs power (lambda) >= 2 (seed 003 Eq. 32), got {self.power!r}")


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _crossings(xq, xn, lines: CrackLines, s: int, reach=0.0):
    """Whether [x_I, x] crosses segment ``s``, and the crossing parameter t with dt/dx.

    ``xq, xn (P, 2)`` (``xn`` the nodes' sight positions). At a mouth (an end that
    is not a tip) the segment is prolonged by ``reach`` (scalar or (P,), a length)
    outside the body: a split node at the mouth looks from a point up to
    ``SIGHT_OFFSET d_mI`` outside the body when the crack meets the boundary at an
    angle, and its rays that pass outside the body around the mouth must still
    cross the crack. Returns hit (P,), t (P,), dt (P, 2).
    """
    a, b = lines.a[s], lines.b[s]
    # differences scaled by 2^-p ~ 1 / length (exact): dt forms 4th powers of lengths (overflow)
    p = int(np.frexp(lines.length[s])[1])
    e, qa, na, v = (np.ldexp(z, -p) for z in (b - a, xq - a, xn - a, xq - xn))
    side_x = np.where(_cross(e, qa) >= 0, 1, -1)
    side_n = np.where(_cross(e, na) >= 0, 1, -1)
    num = _cross(na, v)
    den = _cross(e, v)
    ok = den != 0
    t = np.where(ok, num / np.where(ok, den, 1.0), qa @ e / (e @ e))
    # dt/dx for t = num / den, num and den linear in v = x - x_I
    dnum = np.stack([-na[:, 1], na[:, 0]], axis=1)
    dden = np.array([-e[1], e[0]])
    dt = np.ldexp(np.where(ok[:, None], (dnum * den[:, None] - num[:, None] * dden)
                           / np.where(ok, den, 1.0)[:, None] ** 2, 0.0), -p)
    k = lines.crack[s]
    first, last = s == 0 or lines.crack[s - 1] != k, s == lines.n - 1 or lines.crack[s + 1] != k
    # open at a tip; an interior vertex belongs to the segment that starts there, so a line
    # through a kink crosses the polyline once, not twice
    ext = np.asarray(reach) / lines.length[s]
    lo = (t > 0) if (first and lines.is_tip[k, 0]) else (t >= -ext) if first else (t >= 0)
    hi = (t <= 1 + ext) if (last and not lines.is_tip[k, 1]) else (t < 1)
    return (side_x != side_n) & lo & hi, t, dt


def segment_candidates(xq: np.ndarray, xn: np.ndarray, lines: CrackLines, reach=0.0
                       ) -> list[np.ndarray]:
    """The pairs that may cross each crack segment: those whose bounding box meets the
    segment's (a necessary condition; the boxes are grown by ``CANDIDATE_SLACK`` of the
    lengths for rounding, and by ``reach``), found run by run of segments
    (:meth:`CrackLines.chunks`).

    Parameters
    ----------
    xq, xn : ndarray, shape (P, 2)
        The pairs' points and the positions the nodes look from.
    lines : CrackLines
        The m crack segments.
    reach : float or ndarray, shape (P,)
        How far past its mouth a crack reaches in the tests (:func:`crack_distances`).

    Returns
    -------
    list of ndarray
        m sorted arrays of pair indices into ``xq`` (int, shape (k_s,)).
    """
    pad = CANDIDATE_SLACK * (np.hypot(*(xq - xn).T) + lines.length.max()) + reach
    (x0, y0), (x1, y1) = np.minimum(xq, xn).T - pad, np.maximum(xq, xn).T + pad
    slo, shi = np.minimum(lines.a, lines.b), np.maximum(lines.a, lines.b)
    out = []
    for segs, clo, chi in lines.chunks():
        near = np.flatnonzero((x0 <= chi[0]) & (x1 >= clo[0]) & (y0 <= chi[1]) & (y1 >= clo[1]))
        n0, n1, m0, m1 = x0[near], x1[near], y0[near], y1[near]
        out += [near[(n0 <= shi[k, 0]) & (n1 >= slo[k, 0]) & (m0 <= shi[k, 1]) & (m1 >= slo[k, 1])]
                for k in range(lines.n)[segs]]
    return out


def _nodes_on_line(xn, dm, lines: CrackLines, s: int):
    """Nodes ``xn (k, 2)`` within ``SIGHT_OFFSET dm (k,)`` of the line of segment ``s``: on (k,),
    whether that is within the segment (k,), and their parameter along it, clipped (k,)."""
    a, e = lines.a[s], lines.b[s] - lines.a[s]
    u = xn - a
    tol = SIGHT_OFFSET * dm / lines.length[s]
    tn = (u @ e) / (e @ e)
    on = np.abs(_cross(e, u)) <= tol * (e @ e)
    return on, (tn >= -tol) & (tn <= 1.0 + tol), np.clip(tn, 0.0, 1.0)


def _arc_from_tip(lines: CrackLines, s: int, t):
    """Distance along the crack from its nearest tip to parameter t of segment s, and its
    derivative with respect to t."""
    k = lines.crack[s]
    arc = lines.start[s] + t * lines.length[s]
    d0 = arc if lines.is_tip[k, 0] else np.full_like(arc, np.inf)
    d1 = lines.total[k] - arc if lines.is_tip[k, 1] else np.full_like(arc, np.inf)
    near0 = d0 <= d1
    return np.where(near0, d0, d1), np.where(near0, lines.length[s], -lines.length[s])


def wrap_distance(d, dd, xq, xn, xc, s0, ds0, lam: float, ok):
    """Lengthen the distances ``d (P,)`` of pairs around wrap points ``xc (P, 2)``.

    Seed 003 Eq. (29) multiplies the distance by ``((s1 + s2) / s0)^lambda`` with
    ``s1 = |x_I - x_c|``, ``s2 = |x - x_c|``, ``s0 = |x - x_I|``; applied to an
    already modified ``d`` (a pair wrapping around two obstacles) the product
    rule gives ``dd' = ratio^lambda dd + lambda ratio^(lambda - 1) d dratio``,
    which for ``d = s0`` is Eq. (31). Only pairs where ``ok`` change.
    """
    s1 = np.hypot(*(xn - xc).T)
    v2 = xq - xc
    s2 = np.hypot(*v2.T)
    ds2 = v2 / np.where(s2 > 0, s2, 1.0)[:, None]
    safe = np.where(s0 > 0, s0, 1.0)
    ratio = np.where(ok, (s1 + s2) / safe, 1.0)
    dratio = (ds2 - ratio[:, None] * ds0) / safe[:, None]
    f = ratio**lam
    new_dd = f[:, None] * dd + (lam * ratio ** (lam - 1) * d)[:, None] * dratio
    return np.where(ok, f * d, d), np.where(ok[:, None], new_dd, dd)


def sight_positions(xn, dm, I, nodes: NodeCloud, lines: CrackLines) -> np.ndarray:
    """Where the nodes ``xn (P, 2)`` look from: split nodes are moved onto their face by
    ``SIGHT_OFFSET d_mI`` along the face normal (at a kink vertex, along the bisector of
    the two segments' normals, so that each copy sees its own sector), and nodes within
    ``TIP_SNAP d_mI`` of a tip sit on it. Only the sight tests use these positions."""
    sight = xn.copy()
    if nodes.face is not None:
        split = np.flatnonzero(nodes.face[I] != 0)
        if len(split):
            seg = nodes.face_segment[I[split]]
            e = lines.b - lines.a
            normal = np.column_stack([-e[:, 1], e[:, 0]]) / lines.length[:, None]
            direction = normal[seg].copy()
            p = xn[split]
            for nxt, end in ((1, lines.b), (-1, lines.a)):  # a kink vertex: add the neighbour's
                other = np.clip(seg + nxt, 0, lines.n - 1)
                kink = ((other != seg) & (lines.crack[other] == lines.crack[seg])
                        & (np.hypot(*(p - end[seg]).T) <= 1e-9 * lines.length[seg]))
                direction[kink] += normal[other[kink]]
            direction /= np.hypot(*direction.T)[:, None]
            sight[split] += (SIGHT_OFFSET * dm[split] * nodes.face[I[split]])[:, None] * direction
    for tip in lines.tip_positions():
        near = np.hypot(*(xn - tip).T) < TIP_SNAP * dm
        sight[near] = tip
    return sight


def crack_distances(xq, xn, dm, I, nodes: NodeCloud, lines: CrackLines, rule: CrackRule,
                    sight=None):
    """Rule-modified distances of the pairs (x_q, x_I): cut (P,), d (P,), dd/dx (P, 2).

    ``xq, xn (P, 2)`` are the pairs' points and nodes, ``dm (P,)`` the support
    radii, ``I (P,)`` the node indices (for the split-node faces); ``sight (P, 2)``, optional:
    the nodes' :func:`sight_positions` (a node's own, so a caller may form them once per node).
    Only the pairs that cross a crack go through the rule's formulas.
    """
    sight = sight_positions(xn, dm, I, nodes, lines) if sight is None else sight
    n_cracks = len(lines.ends)
    hits = np.zeros((len(I), n_cracks), np.int64)
    sc = np.full(len(I), np.inf)  # transparency: arc distance of the crossing from the tip
    dsc = np.zeros((len(I), 2))
    split = np.zeros(len(I), bool) if nodes.face is None else nodes.face[I] != 0
    reach = MOUTH_REACH * dm
    for s, idx in enumerate(segment_candidates(xq, sight, lines, reach)):
        if len(idx) == 0:
            continue
        hit, t, dt = _crossings(xq[idx], sight[idx], lines, s, reach[idx])
        on, inside, tn = _nodes_on_line(xn[idx], dm[idx], lines, s)
        hit &= ~on | inside  # a node on the line beyond the segment meets the line only at itself
        if not hit.any():
            continue
        hits[idx, lines.crack[s]] += hit
        if rule.name == "transparency":  # a split node's rays leave its segment at the node
            at = on & inside & split[idx]
            t, dt = np.where(at, tn, t), np.where(at[:, None], 0.0, dt)
            arc, darc = _arc_from_tip(lines, s, t)
            take = hit & (arc < sc[idx])
            sc[idx] = np.where(take, arc, sc[idx])
            dsc[idx] = np.where(take[:, None], darc[:, None] * dt, dsc[idx])
    n_hit = hits.sum(axis=1)
    diff = xq - xn
    s0 = np.hypot(*diff.T)
    ds0 = diff / np.where(s0 > 0, s0, 1.0)[:, None]
    d, dd = s0, ds0
    cut = n_hit > 0
    h = np.flatnonzero(cut)  # the rules change only the pairs that cross a crack (a few)
    if len(h) == 0:
        return cut, d, dd
    xq, xn, sight, dm, hits, n_hit = xq[h], xn[h], sight[h], dm[h], hits[h], n_hit[h]
    s0h, ds0h = s0[h], ds0[h]
    dh, ddh, cuth = s0h, ds0h, np.ones(len(h), bool)
    if rule.name == "see_through":
        for k in range(n_cracks):
            for end in np.flatnonzero(lines.is_tip[k]):
                inside = np.hypot(*(xn - lines.ends[k, end]).T) < dm
                cuth &= ~((hits[:, k] > 0) & inside & (n_hit == hits[:, k]))
    elif rule.name == "transparency":
        sbar = rule.kappa * rule.spacing
        sch, dsch = sc[h], dsc[h]
        one = (n_hit == 1) & (sch < sbar)
        ratio = np.where(one, sch / sbar, 0.0)
        dh = np.where(one, s0h + dm * ratio**rule.power, dh)
        grad = rule.power * dm * np.where(one, ratio ** (rule.power - 1) / sbar, 0.0)
        ddh = np.where(one[:, None], ds0h + grad[:, None] * dsch, ddh)
        cuth &= ~one
    elif rule.name == "diffraction":  # around the tip of the crossed crack
        single = n_hit == 1
        k = np.argmax(hits, axis=1)
        best = np.full(len(h), np.inf)
        xc = np.zeros_like(xq)
        for end in (0, 1):
            tip = lines.ends[k, end]
            path = np.hypot(*(sight - tip).T) + np.hypot(*(xq - tip).T)
            take = single & lines.is_tip[k, end] & (path < best)
            best = np.where(take, path, best)
            xc = np.where(take[:, None], tip, xc)
        ok = single & np.isfinite(best)
        dh, ddh = wrap_distance(dh, ddh, xq, xn, xc, s0h, ds0h, rule.power, ok)
        cuth &= ~ok
    d, dd = s0.copy(), ds0.copy()
    d[h], dd[h], cut[h] = dh, ddh, cuth
    return cut, d, dd


def pair_arrays(x, nodes: NodeCloud, nb: Neighbours):
    """The valid (point, node) pairs of padded neighbours, flat: rows, cols, I, x_q, x_I, d_m."""
    rows, cols = np.nonzero(nb.mask)
    I = nb.idx[rows, cols]
    return rows, cols, I, x[rows], nodes.x[I], nodes.radius[I]


def padded_weights(nb: Neighbours, rows, cols, cut, d, dd, dm, wfun):
    """Weights W(d / d_m) of flat pairs back on the padded arrays: mask, w, dwx, dwy (n, k).

    ``dw/dx = w'(d / d_m) / d_m * dd/dx`` (seed 003 Eq. 30); cut pairs are masked.
    """
    sn = d / dm
    wv, g = wfun(np.where(cut, 1.0, sn))
    dw = (g * sn / dm)[:, None] * dd  # w'(s) / d_m * dd/dx, with g = w'(s) / s
    keep = ~cut & (wv > 0)
    mask = np.zeros_like(nb.mask)
    w, dwx, dwy = (np.zeros(nb.mask.shape) for _ in range(3))
    mask[rows, cols] = keep
    w[rows, cols] = np.where(keep, wv, 0.0)
    dwx[rows, cols] = np.where(keep, dw[:, 0], 0.0)
    dwy[rows, cols] = np.where(keep, dw[:, 1], 0.0)
    return mask, w, dwx, dwy


def crack_weights(x: np.ndarray, nodes: NodeCloud, nb: Neighbours, lines: CrackLines,
                  rule: CrackRule, wfun):
    """Weights of the (point, neighbour) pairs of ``x`` under a crack rule.

    Parameters
    ----------
    x : ndarray (n, 2)
        Points.
    nodes : NodeCloud
        With ``face`` and ``face_segment`` for nodes split on a crack (or None).
    nb : Neighbours
        ``idx, mask (n, k)`` before the crack is taken into account.
    lines : CrackLines
    rule : CrackRule
    wfun : callable
        ``s -> (w, w'(s) / s)`` (:func:`efgkit.approx.weights.weight_function`).

    Returns
    -------
    mask : ndarray (n, k) bool
        Pairs that still see each other.
    w, dwx, dwy : ndarray (n, k)
        Weights and their derivatives with respect to x (0 where masked):
        ``dw/dx = w'(d / d_m) / d_m * dd/dx`` (Eq. 30).
    """
    rows, cols, I, xq, xn, dm = pair_arrays(x, nodes, nb)
    cut, d, dd = crack_distances(xq, xn, dm, I, nodes, lines, rule)
    return padded_weights(nb, rows, cols, cut, d, dd, dm, wfun)
