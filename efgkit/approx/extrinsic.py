"""The operators of the extrinsic MLS enrichment unknowns: the compiled path and the CSR.

Each tip adds two unknowns (K_I, K_II) whose displacement and gradient components at a
point are ``psi_m = Q_m(x) - sum_I phi_I(x) Q_m(x_I)`` and their derivatives (seed 003
Eq. 44b). :func:`efgkit.approx.enrichment.extra_columns` forms them per tip on the rows
where they can be non-zero (all points without a ramp, else the points within r2 of the tip
or with a ramped neighbour), in numpy or, from :data:`efgkit.jit.COMPILED_MIN` points on,
by the one-pass kernel :func:`efgkit.approx.extrinsic_kernel.extrinsic_fields`
(:func:`compiled_fields` here); :func:`column_operators` writes the values of all tips
straight into CSR arrays (a row's columns 2 t + mode ascending, int32 indices when the sizes
allow), the canonical CSR that scipy's conversion of the same triplets gives, without the
triplets and their sort.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

from .tip_functions import TipGeometry, williams_matrix

__all__ = ["KEYS", "column_operators", "compiled_fields", "tip_frame"]

KEYS = ("ux", "uy", "gxx", "gxy", "gyx", "gyy")  # the operators of an Extra, in order


def tip_frame(geom: TipGeometry) -> tuple:
    """What the kernels need of a tip: position (2,), rotation (2, 2) (rows e1, e2), the kink
    in the tip frame (2,) (zeros without one), whether there is a kink, theta_R of Eq. 57,
    and whether the polyline's left face is the frame's upper face."""
    rot = np.ascontiguousarray(geom.tip.rotation, dtype=float)
    tip = np.ascontiguousarray(geom.tip.x, dtype=float)
    kink = np.zeros(2) if geom.kink is None else rot @ (np.asarray(geom.kink, float) - tip)
    return tip, rot, kink, geom.kink is not None, float(geom.theta_r), bool(geom.upper_is_left)


def compiled_fields(x, nb, values, ddx, ddy, enr, t: int, derivatives: bool):
    """psi of tip ``t`` of the extrinsic enrichment ``enr`` at the points ``x (n, 2)`` with
    neighbours ``nb`` and nodal shape functions ``values, ddx, ddy (n, k)`` (derivatives None
    without ``derivatives``), by the compiled kernel.

    Returns
    -------
    rows : ndarray (m,) int
        The points where psi can be non-zero (all of them without a ramp).
    out : tuple of ndarray (m, 2)
        ``out[key][row, mode]`` in the order of :data:`KEYS` (ux, uy only without
        ``derivatives``).
    r : ndarray (m,)
        The rows' tip distances (for the caller's at-the-tip check).
    """
    from .extrinsic_kernel import RAMP_IDS, extrinsic_fields, tip_radii

    frame = tip_frame(enr.tips[t])
    x = np.ascontiguousarray(x, dtype=float)
    ramped = bool(np.isfinite(enr.r2))
    if ramped:  # psi vanishes where neither x nor its nodes are ramped
        node_ramped = (enr.node_q[t] != 0).any(axis=(1, 2))  # (n_nodes,)
        near = (node_ramped[nb.idx] & nb.mask).any(axis=1)
        rows = np.flatnonzero((tip_radii(x, *frame) < enr.r2) | near)
    else:
        rows = np.arange(len(x))
    qn = np.ascontiguousarray(enr.node_q[t].reshape(-1, 4))  # (n_nodes, 2 mode + comp)
    Mg = williams_matrix(enr.tips[t], enr.mu, enr.kappa)
    r2 = float(enr.r2) if ramped else 1.0
    gx, gy = (ddx, ddy) if derivatives else (values, values)  # unread without derivatives
    out, r = extrinsic_fields(x, rows, *frame, Mg, ramped, float(enr.r1), r2,
                              RAMP_IDS[enr.ramp] if ramped else 0, nb.idx, nb.mask, values, gx, gy, qn,
                              derivatives)
    return rows, out if derivatives else out[:2], r


def column_operators(n: int, n_extra: int, per_tip: list, keys=KEYS) -> dict:
    """The operators ``{key: csr_array (n, n_extra)}`` from the fields of every tip.

    ``per_tip[t] = (rows (m_t,), out)``, ``out[i] (m_t, 2)`` of ``keys[i]`` (an array
    (len(keys), m_t, 2) or a sequence of (m_t, 2) arrays): the values of tip t's two
    unknowns (columns 2 t, 2 t + 1) at the rows. A row holds the columns of the tips that
    list it, ascending; each operator has its own data array and all share the index arrays.

    Examples
    --------
    >>> out0 = np.arange(4.0).reshape(1, 2, 2)        # tip 0 at rows 0 and 2
    >>> out1 = np.full((1, 1, 2), 9.0)                # tip 1 at row 2
    >>> ops = column_operators(3, 4, [(np.array([0, 2]), out0), (np.array([2]), out1)], ("ux",))
    >>> ops["ux"].toarray().tolist()
    [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [2.0, 3.0, 9.0, 9.0]]
    """
    member = np.zeros((n, len(per_tip)), np.int64)
    for t, (rows, _) in enumerate(per_tip):
        member[rows, t] = 1
    counts = 2 * member.sum(axis=1)
    nnz = int(counts.sum())
    it = np.int32 if max(n, n_extra, nnz) < 2**31 else np.int64
    indptr = np.zeros(n + 1, it)
    np.cumsum(counts, out=indptr[1:])
    if len(per_tip) == 1 and len(per_tip[0][0]) == n:  # one tip at every point: no scatter
        out = per_tip[0][1]
        indices = np.tile(np.array([0, 1], it), n)
        return {key: csr_array((out[i].reshape(-1), indices, indptr), shape=(n, n_extra))
                for i, key in enumerate(keys)}
    before = np.cumsum(member, axis=1) - member  # tips before t listing the row
    indices = np.empty(nnz, it)
    data = {key: np.empty(nnz) for key in keys}
    for t, (rows, out) in enumerate(per_tip):
        pos = indptr[rows].astype(np.int64) + 2 * before[rows, t]
        for mode in (0, 1):
            indices[pos + mode] = 2 * t + mode
            for i, key in enumerate(keys):
                data[key][pos + mode] = out[i][:, mode]
    return {key: csr_array((data[key], indices, indptr), shape=(n, n_extra)) for key in keys}
