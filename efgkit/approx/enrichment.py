"""Crack-tip enrichment of the MLS approximation (seed 003 Sect. 5).

* ``radial`` / ``full`` (intrinsic, Sects. 5.3, 5.4): the basis is extended by
  sqrt(r) (Eq. 52) or by the four near-tip functions (Eq. 50) within the ramp
  radius r2 of a tip, and the enriched functions are blended with the linear
  ones, ``phi = R phi_enr + (1 - R) phi_lin`` (Eqs. 53-56). No unknowns are
  added; the 5- or 7-term moment matrices are formed only where R > 0 (they
  go singular tens of spacings away from the tip).
* ``extrinsic_mls`` (Sect. 5.1): ``u = sum phi_I u_I + sum_tips k_m psi_m`` with
  ``psi_m = Q_m(x) - sum_I phi_I(x) Q_m(x_I)`` and the Williams fields Q of unit
  K_I and K_II (Eq. 38), so the solve returns K_I and K_II of every tip;
  optionally ramped. This is the form of Eq. (44b): the same trial space as
  Eq. (46) (``u_I = u~_I + sum k Q(x_I)``, Eq. 47), so the same solution and the
  same k, but ``psi`` is small wherever the nodal functions reproduce Q, i.e.
  away from the tip, which keeps the system well conditioned (CG iterations on
  a 45k-node edge crack: 52 against 134 for the global Q of Eq. 46).
* ``pu`` (Sect. 5.2, Eq. 49): every node whose support comes within the PU
  radius of a tip carries four more vector unknowns b_Ii multiplying
  ``phi_I (q_i(x) - q_i(x_I))`` (the branch functions, shifted by their nodal
  values so that the added functions vanish at the node and stay small).

Branch functions, tip coordinates (with the kinked-crack mapping) and ramps
are in :mod:`efgkit.approx.tip_functions`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array

from ..jit import resolve_backend
from ..methods.efg import INTRINSIC
from .bases import basis as poly_basis
from .bases import basis_origin_gradient, basis_size
from .crack_rules import TIP_SNAP
from .extrinsic import KEYS, column_operators, compiled_fields
from .mls import RCOND_MIN, SingularMomentMatrix, moment_shape
from .shape import Extra, Shape
from .tip_functions import TipGeometry, branch_functions, ramp, tip_coordinates, williams_modes

__all__ = ["Enrichment", "blend_intrinsic", "extra_columns", "interpolant"]



@dataclass(frozen=True, eq=False)
class Enrichment:
    """An enrichment of the approximation of a cracked scene.

    Attributes
    ----------
    kind : {"radial", "full", "extrinsic_mls", "pu"}
    tips : tuple of TipGeometry
    r1, r2 : float
        Ramp radii (intrinsic, ramped extrinsic); ``r2 = inf``: no ramp.
    ramp : {"linear", "quintic"}
    mu, kappa : float
        Shear modulus and Kolosov constant of the Williams fields (extrinsic MLS).
    pu_nodes : ndarray (n_pu,) int
        Enriched nodes (PU), each enriched by the tip ``pu_tip``.
    pu_tip : ndarray (n_pu,) int
    pu_values : ndarray (n_pu, 4)
        Branch functions at the enriched nodes (the shift of Eq. 49's functions).
    node_q : ndarray (n_tips, n_nodes, 2, 2)
        Extrinsic MLS: the (ramped) Williams fields Q[mode, comp] at the nodes.
    """

    kind: str
    tips: tuple[TipGeometry, ...]
    r1: float
    r2: float
    ramp: str
    mu: float = 1.0
    kappa: float = 2.0
    pu_nodes: np.ndarray | None = None
    pu_tip: np.ndarray | None = None
    pu_values: np.ndarray | None = None
    node_q: np.ndarray | None = None

    @property
    def n_extra(self) -> int:
        """Enrichment unknowns: 2 per tip (extrinsic MLS), 8 per enriched node (PU)."""
        if self.kind == "extrinsic_mls":
            return 2 * len(self.tips)
        if self.kind == "pu":
            return 8 * len(self.pu_nodes)
        return 0

    @classmethod
    def build(cls, kind, tips, nodes, material, r1, r2, ramp_kind, pu_radius) -> Enrichment:
        """The enrichment of ``kind`` for ``tips`` (TipGeometry) on ``nodes``."""
        tips = tuple(tips)
        if kind in INTRINSIC or (kind == "extrinsic_mls" and np.isfinite(r2)):
            xs = np.array([g.tip.x for g in tips])
            for i in range(len(tips)):
                for j in range(i + 1, len(tips)):
                    if np.hypot(*(xs[i] - xs[j])) < 2 * r2:
                        raise ValueError(
                            f"the enrichment discs (radius enrich_radius = {r2:g}) of tips "
                            f"{tips[i].tip.id} and {tips[j].tip.id} overlap; give a smaller "
                            "enrich_radius (each point is enriched by one tip)")
        if kind == "extrinsic_mls":
            node_q = np.zeros((len(tips), nodes.n, 2, 2))
            for t, g in enumerate(tips):
                F = node_branch(nodes, np.arange(nodes.n), g, "full")
                node_q[t] = williams_modes(F, np.zeros((nodes.n, 2, 4)), g, material.mu,
                                           material.kappa)[0]
                if np.isfinite(r2):
                    r, _, gr, _ = tip_coordinates(nodes.x, g)
                    node_q[t] *= ramp(r, gr, r1, r2, ramp_kind)[0][:, None, None]
            return cls(kind, tips, r1, r2, ramp_kind, material.mu, material.kappa, node_q=node_q)
        if kind != "pu":
            return cls(kind, tips, r1, r2, ramp_kind, material.mu, material.kappa)
        near = np.full(nodes.n, -1)
        best = np.full(nodes.n, np.inf)
        for t, g in enumerate(tips):
            d = np.hypot(*(nodes.x - g.tip.x).T)
            take = (d < nodes.radius + pu_radius) & (d < best)
            near, best = np.where(take, t, near), np.where(take, d, best)
        sel = np.flatnonzero(near >= 0)
        vals = np.zeros((len(sel), 4))
        for t, g in enumerate(tips):
            on = near[sel] == t
            vals[on] = node_branch(nodes, sel[on], g, "full")
        return cls(kind, tips, r1, r2, ramp_kind, material.mu, material.kappa, sel, near[sel], vals)

    def in_ramp(self, x: np.ndarray, t: int) -> np.ndarray:
        """Indices of the points ``x (n, 2)`` whose tip coordinate r of tip ``t`` (kink-mapped,
        as the ramp uses it) is below r2.

        The map keeps the distance to the kink, so for a kinked crack only the points
        within r2 of the tip or with | |x - kink| - |tip - kink| | < r2 can qualify.
        """
        g = self.tips[t]
        near = np.hypot(*(x - g.tip.x).T) < self.r2
        if g.kink is None:  # r is the straight distance
            return np.flatnonzero(near)
        L = np.hypot(*(g.kink - g.tip.x))
        near |= np.abs(np.hypot(*(x - g.kink).T) - L) < self.r2
        idx = np.flatnonzero(near)
        return idx[tip_coordinates(x[idx], g)[0] < self.r2]


def node_branch(nodes, index: np.ndarray, geom: TipGeometry, kind: str):
    """Branch functions at the nodes ``index`` (split nodes on their face), shape (m, k).

    Nodes within ``TIP_SNAP`` of their support radius from the tip count as at it
    (F = 0): sqrt(r) is not Lipschitz, and a tip moved by 1e-10 h off a node would
    otherwise change the node's values by 1e-5 (the crack rules snap the same way).
    """
    side = None if nodes.face is None else nodes.face[index]
    r, th, gr, gt = tip_coordinates(nodes.x[index], geom, side)
    F = branch_functions(r, th, gr, gt, kind)[0]
    return np.where((r < TIP_SNAP * nodes.radius[index])[:, None], 0.0, F)


def _check_off_tip(x, r, geom: TipGeometry, scale: float):
    bad = np.flatnonzero(r <= 1e-12 * scale)
    if len(bad):
        raise ValueError(
            f"point {x[bad[0]].tolist()} is at crack tip {geom.tip.id}: the enriched gradient is "
            "singular there; evaluate fields off the tip")


def blend_intrinsic(x, nodes, nb, w, dw, lin, enr: Enrichment, tip: int, basis: str,
                    derivatives: bool):
    """Intrinsically enriched and ramped shape functions at points near tip ``tip``.

    Parameters
    ----------
    x : ndarray (n, 2)
        Points within r2 of the tip (kink-mapped distance, :meth:`Enrichment.in_ramp`).
    nodes : NodeCloud
    nb : Neighbours
        Their neighbours (after the crack rule).
    w : ndarray (n, k); dw : ndarray (n, k, 2) or None
        Pair weights (after the crack rule).
    lin : tuple of (n, k) arrays
        phi, dphi/dx, dphi/dy of the polynomial basis (the ``(1 - R)`` part).
    enr : Enrichment
    tip : int
    basis : str
        The polynomial basis extended by the branch functions.
    derivatives : bool
        Also the x and y derivatives.

    Returns
    -------
    phi, dphidx, dphidy : ndarray (n, k) (derivatives None if not asked)
    """
    geom = enr.tips[tip]
    scale = np.where(nb.mask, nodes.radius[nb.idx], 0.0).max(axis=1)  # (n,)
    r, th, gr, gt = tip_coordinates(x, geom)
    if derivatives:
        _check_off_tip(x, r, geom, float(scale.max()))
    F0, dF0 = branch_functions(r, th, gr, gt, enr.kind)
    used = np.unique(nb.idx[nb.mask])
    Fn = np.zeros((nodes.n, F0.shape[1]))
    Fn[used] = node_branch(nodes, used, geom, enr.kind)
    sq = np.sqrt(scale)[:, None, None]
    X = (nodes.x[nb.idx] - x[:, None, :]) / scale[:, None, None]
    P = np.concatenate([poly_basis(basis, X), (Fn[nb.idx] - F0[:, None, :]) / sq], axis=2)
    P = np.where(nb.mask[..., None], P, 0.0)
    m0 = basis_size(basis)
    p0 = np.zeros((len(x), P.shape[2]))
    p0[:, 0] = 1.0
    dp0 = np.concatenate([basis_origin_gradient(basis)[None] / scale[:, None, None], dF0 / sq],
                         axis=2)
    phi, gx, gy, rcond = moment_shape(w, dw, P, p0, dp0)
    bad = np.flatnonzero(~(rcond >= RCOND_MIN))
    if len(bad):
        k = bad[np.argmin(rcond[bad])]
        raise SingularMomentMatrix(
            f"the {enr.kind}-enriched moment matrix ({P.shape[2]} terms, {m0} polynomial) is "
            f"singular (rcond = {rcond[k]:.2e}) at point {x[k].tolist()} near tip {geom.tip.id} "
            f"with {int(nb.counts[k])} neighbour(s). Remedy: enlarge d_max, use the diffraction or "
            "transparency rule, or reduce enrich_radius")
    R, dR = ramp(r, gr, enr.r1, enr.r2, enr.ramp)
    out_phi = R[:, None] * phi + (1 - R[:, None]) * lin[0]
    if not derivatives:
        return out_phi, None, None
    diff = phi - lin[0]
    return (out_phi,
            R[:, None] * gx + (1 - R[:, None]) * lin[1] + diff * dR[:, 0:1],
            R[:, None] * gy + (1 - R[:, None]) * lin[2] + diff * dR[:, 1:2])


# Points per pass of the extrinsic enrichment's branch functions and modes (~370 bytes of
# temporaries per point: at 2.9M points 1.1 GB at once before; docs/performance.md, memory_release).
EXTRA_CHUNK = 65536


def _ops(n, rows, cols, vals, n_extra):
    """csr_array (n, n_extra) from triplets, int32 indices when the sizes allow (scipy keeps
    the index type of the triplets: int64 ones would double the indices' memory)."""
    it = np.int32 if max(n, n_extra, len(vals)) < 2**31 else np.int64
    return csr_array((vals, (rows.astype(it, copy=False), cols.astype(it, copy=False))),
                     shape=(n, n_extra))


def interpolant(vals, nb, rows, qn, chunk: int = 65536) -> np.ndarray:
    """sum_I v_I(x) q_I at the points ``rows``, shape (m, c), from the padded shape-function
    values ``vals (n, k)`` (or a derivative) and the nodal values ``qn (n_nodes, c)``: the
    MLS interpolant of seed 003 Eq. 44b on the rows that need it, in chunks of rows (no
    operator over all points, no (n, k, c) array): each chunk's valid (point, neighbour)
    values as a CSR operator, times ``qn`` (the sums over a row's neighbours in their order)."""
    out = np.empty((len(rows), qn.shape[1]))
    for s in range(0, len(rows), chunk):
        r = rows[s:s + chunk]
        m = nb.mask[r]
        indptr = np.zeros(len(r) + 1, np.int64)
        np.cumsum(m.sum(axis=1), out=indptr[1:])
        op = csr_array((vals[r][m], nb.idx[r][m], indptr), shape=(len(r), len(qn)))
        out[s:s + chunk] = op @ qn
    return out


def extra_columns(x, nodal: Shape, enr: Enrichment, derivatives: bool, scale: float,
                  backend: str = "auto") -> Extra:
    """The enrichment unknowns' component operators at points ``x (n, 2)``.

    ``nodal`` holds the nodal shape functions at x; ``scale`` is a length (the
    spacing) for the at-the-tip check. ``backend`` ("auto", "numba", "numpy"): the extrinsic
    MLS columns by the compiled kernel (:mod:`efgkit.approx.extrinsic`; "auto": from
    :data:`efgkit.jit.COMPILED_MIN` points on) or in numpy; they agree to rounding.
    """
    n = len(x)
    ne = enr.n_extra
    nb, values, ddx, ddy = nodal.neighbours, nodal.values, nodal.ddx, nodal.ddy
    if enr.kind == "extrinsic_mls":
        keys = KEYS if derivatives else KEYS[:2]
        compiled = resolve_backend(backend, n) == "numba"
        per_tip = []  # (rows, out (len(keys), m, 2)) of every tip
        for t, g in enumerate(enr.tips):
            if compiled:  # the same formulas point by point (efgkit.approx.extrinsic_kernel)
                rows, out, r = compiled_fields(x, nb, values, ddx, ddy, enr, t, derivatives)
                if derivatives:
                    _check_off_tip(x[rows], r, g, scale)
                per_tip.append((rows, out))
                continue
            r, th, gr, gt = tip_coordinates(x, g)
            rows = np.arange(n)
            if np.isfinite(enr.r2):  # psi vanishes where neither x nor its nodes are ramped
                ramped = (enr.node_q[t] != 0).any(axis=(1, 2))  # (n_nodes,)
                near_node = ramped[nb.idx] & nb.mask
                rows = np.flatnonzero((r < enr.r2) | near_node.any(axis=1))
            # minus the MLS interpolant of Q (Eq. 44b): sum over the neighbours of phi_I Q(x_I)
            qn = enr.node_q[t].reshape(-1, 4)  # (n_nodes, mode * comp)
            out = np.empty((len(keys), len(rows), 2))  # (key, row, mode)
            for s in range(0, len(rows), EXTRA_CHUNK):  # the modes' temporaries a chunk at a time
                rr = rows[s:s + EXTRA_CHUNK]
                if derivatives:
                    _check_off_tip(x[rr], r[rr], g, scale)
                F, dF = branch_functions(r[rr], th[rr], gr[rr], gt[rr], "full")
                Q, dQ = williams_modes(F, dF, g, enr.mu, enr.kappa)
                if np.isfinite(enr.r2):
                    R, dR = ramp(r[rr], gr[rr], enr.r1, enr.r2, enr.ramp)
                    dQ = R[:, None, None, None] * dQ + Q[..., None] * dR[:, None, None, :]
                    Q = R[:, None, None] * Q
                Q = Q - interpolant(values, nb, rr, qn).reshape(-1, 2, 2)
                out[0, s:s + EXTRA_CHUNK], out[1, s:s + EXTRA_CHUNK] = Q[..., 0], Q[..., 1]
                if derivatives:
                    dQ = dQ - np.stack([interpolant(v, nb, rr, qn).reshape(-1, 2, 2)
                                        for v in (ddx, ddy)], axis=-1)
                    for i, (c, d) in enumerate(((0, 0), (0, 1), (1, 0), (1, 1))):
                        out[2 + i, s:s + EXTRA_CHUNK] = dQ[:, :, c, d]  # gxx, gxy, gyx, gyy
            per_tip.append((rows, out))
        ops = column_operators(n, ne, per_tip, keys)
    else:  # PU: functions phi_I (q_i(x) - q_i(x_I)) of the enriched nodes
        where = np.full(max(int(nb.idx.max(initial=0)), int(enr.pu_nodes.max(initial=0))) + 1, -1)
        where[enr.pu_nodes] = np.arange(len(enr.pu_nodes))
        q, a = np.nonzero(nb.mask & (where[nb.idx] >= 0))
        j = where[nb.idx[q, a]]
        F = np.zeros((len(q), 4))
        dF = np.zeros((len(q), 2, 4))
        for t, g in enumerate(enr.tips):
            on = enr.pu_tip[j] == t
            if not on.any():
                continue
            r, th, gr, gt = tip_coordinates(x[q[on]], g)
            if derivatives:
                _check_off_tip(x[q[on]], r, g, scale)
            F[on], dF[on] = branch_functions(r, th, gr, gt, "full")
        shifted = F - enr.pu_values[j]
        psi = values[q, a][:, None] * shifted  # (m, 4)
        col = 8 * j[:, None] + 2 * np.arange(4)[None, :]  # x-component unknowns
        qq = np.repeat(q, 4)
        ops = {"ux": _ops(n, qq, col.ravel(), psi.ravel(), ne),
               "uy": _ops(n, qq, col.ravel() + 1, psi.ravel(), ne)}
        if derivatives:
            for c, (name_x, name_y) in enumerate((("gxx", "gyx"), ("gxy", "gyy"))):
                dphi = (ddx if c == 0 else ddy)[q, a]
                dpsi = dphi[:, None] * shifted + values[q, a][:, None] * dF[:, c, :]
                ops[name_x] = _ops(n, qq, col.ravel(), dpsi.ravel(), ne)
                ops[name_y] = _ops(n, qq, col.ravel() + 1, dpsi.ravel(), ne)
    if not derivatives:
        return Extra(ops["ux"], ops["uy"])
    return Extra(ops["ux"], ops["uy"], ops["gxx"], ops["gxy"], ops["gyx"], ops["gyy"])
