"""Moving-least-squares shape functions and first derivatives, as sparse operators.

For a point x with neighbours I (|x - x_I| < d_mI), seed 003 Eqs. (8)-(17):

    A(x) = sum_I w_I p_I p_I^T,        C_I = w_I p_I,
    A gamma = p,                       phi_I = gamma^T C_I,              (13, 15)
    A gamma_,i = p_,i - A_,i gamma,    phi_I,i = gamma_,i^T C_I + gamma^T C_I,i   (14, 17)

with p_I = p((x_I - xbar) / s) in the shifted, scaled basis (xbar = x held
fixed while differentiating, s the largest support radius at x). A is
factorised once per point and reused for the derivatives (the gamma scheme).

The modified MLS of seed 002 (Eqs. 6-19) adds interpolation conditions at the
essential-boundary nodes J of the support (Lagrange multipliers). With the
bordered matrix M = [[A_in, P_b], [P_b^T, 0]] (A_in summed over the other
nodes only), the same scheme reads

    M [gamma; mu] = [p; 0],   phi_I = gamma^T C_I (I not in J),  phi_J = mu_J,
    M [gamma; mu]_,i = [p_,i - A_in,i gamma; 0],

which gives phi_I(x_J) = delta_IJ at the boundary nodes (Eq. 19). Only points
whose support holds such a node take this path.
"""

from __future__ import annotations

import numpy as np

from ..jit import resolve_backend
from ..nodes import NodeCloud
from ..search import Neighbours, find_neighbours
from .bases import basis, basis_origin_gradient, basis_size
from .shape import Shape
from .weights import pair_weights, weight_function

__all__ = ["SingularMomentMatrix", "mls_shape", "moment_shape", "RCOND_MIN"]

RCOND_MIN = 1e-10  # reciprocal 1-norm condition number below which A counts as singular


class SingularMomentMatrix(ValueError):  # noqa: N818 (names the condition, like LinAlgError)
    """The moment matrix at a point is singular or too ill-conditioned to trust."""


def _moment(w: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Moment matrices ``A_n = sum_k w_nk p_nk p_nk^T``, shape (n, m, m), from weights
    ``w (n, k)`` and basis values ``P (n, k, m)``: one batched matmul (5x faster than the
    three-operand einsum, which numpy runs as a generic loop)."""
    return np.matmul((P * w[..., None]).swapaxes(1, 2), P)


def _inv_rcond(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses of stacked matrices ``A (n, m, m)`` and reciprocal 1-norm condition numbers.

    3 x 3 (the linear basis) by the adjugate formula and an unscaled estimate (as the
    compiled linear kernel computes it), others by LAPACK after a
    symmetric Jacobi scaling ``S A S``, ``S = diag(A)^-1/2``: the shape functions
    do not depend on the scaling of the basis, so neither should the condition
    estimate (the branch functions of an enriched basis are much smaller than
    the polynomial terms far from the tip; unscaled, the 7-term matrices looked
    singular at 33 x 33 nodes of the singular patch, rcond 4e-11, equilibrated
    2e-9). A singular matrix gets rcond 0 and an identity placeholder inverse.
    """
    n, m, _ = A.shape
    if m == 3:
        a, b, c = A[:, 0, 0], A[:, 0, 1], A[:, 0, 2]
        d, e, f = A[:, 1, 0], A[:, 1, 1], A[:, 1, 2]
        g, h, i = A[:, 2, 0], A[:, 2, 1], A[:, 2, 2]
        adj = np.stack([e * i - f * h, c * h - b * i, b * f - c * e,
                        f * g - d * i, a * i - c * g, c * d - a * f,
                        d * h - e * g, b * g - a * h, a * e - b * d], axis=-1).reshape(n, 3, 3)
        det = a * adj[:, 0, 0] + b * adj[:, 1, 0] + c * adj[:, 2, 0]
        ok = np.abs(det) > 0
        inv = adj / np.where(ok, det, 1.0)[:, None, None]
        norm = np.abs(A).sum(axis=1).max(axis=1)
        norm_inv = np.abs(inv).sum(axis=1).max(axis=1)
    else:
        diag = np.einsum("nii->ni", A)
        scale = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
        As = A * scale[:, :, None] * scale[:, None, :]
        det = np.linalg.det(As)
        ok = np.isfinite(det) & (np.abs(det) > 0) & np.all(diag > 0, axis=1)
        inv_s = np.linalg.inv(np.where(ok[:, None, None], As, np.eye(m)))
        inv = inv_s * scale[:, :, None] * scale[:, None, :]
        norm = np.abs(As).sum(axis=1).max(axis=1)
        norm_inv = np.abs(inv_s).sum(axis=1).max(axis=1)
    rcond = np.where(ok, 1.0 / np.maximum(norm * norm_inv, 1e-300), 0.0)
    rcond = np.where(np.isfinite(rcond), rcond, 0.0)
    return np.where(ok[:, None, None], inv, np.eye(m)), rcond


def _raise_singular(x, rows, rcond, counts, offset, remedy=""):
    k = int(rows[np.argmin(rcond[rows])])
    raise SingularMomentMatrix(
        f"moment matrix is singular or ill-conditioned (rcond = {rcond[k]:.2e}) at point "
        f"{offset + k} {np.round(x[k], 12).tolist()} with {int(counts[k])} neighbour(s); "
        f"{len(rows)} point(s) affected. Remedy: enlarge the support (d_max) or add nodes "
        f"near this point{remedy}."
    )


def moment_shape(w, dw, P, p0, dp0):
    """The gamma scheme of seed 003 Eqs. (13)-(17) for any basis, on padded arrays.

    Parameters
    ----------
    w : ndarray (n, k)
        Weights of the neighbours (0 where masked).
    dw : ndarray (n, k, 2) or None
        Their derivatives with respect to the evaluation point.
    P : ndarray (n, k, m)
        Basis at the neighbours, ``p(x_I)`` (any basis spanning the same space:
        shifted and scaled).
    p0 : ndarray (n, m)
        Basis at the evaluation point.
    dp0 : ndarray (n, 2, m) or None
        Its derivatives.

    Returns
    -------
    phi, dphidx, dphidy : ndarray (n, k) (derivatives None without ``dw``)
    rcond : ndarray (n,)
        Reciprocal 1-norm condition numbers of the moment matrices.
    """
    A = _moment(w, P)
    inv, rcond = _inv_rcond(A)
    gamma = np.einsum("nij,nj->ni", inv, p0)  # A gamma = p(x), Eq. (15)
    Pg = np.einsum("nki,ni->nk", P, gamma)
    phi = w * Pg
    if dw is None:
        return phi, None, None, rcond
    out = []
    for c in range(2):  # A gamma_,c = p_,c - A_,c gamma, Eq. (17)
        A_c = _moment(dw[..., c], P)
        gamma_c = np.einsum("nij,nj->ni", inv, dp0[:, c, :] - np.einsum("nij,nj->ni", A_c, gamma))
        out.append(dw[..., c] * Pg + w * np.einsum("nki,ni->nk", P, gamma_c))
    return phi, out[0], out[1], rcond


def _mls_chunk(x, nodes, nb, wfun, bname, derivatives, interp, offset, given=None):
    """Values and derivatives on padded arrays (n, k) for one chunk of points.

    ``given``: (w, dwx, dwy) padded weights of the crack rules, else computed.
    """
    m = basis_size(bname)
    if given is None:
        w, dw = pair_weights(x, nodes, nb, wfun, derivatives)
    else:
        w, dw = given[0], np.stack(given[1:], axis=-1) if derivatives else None
    X = nodes.x[nb.idx] - x[:, None, :]
    scale = np.where(nb.mask, nodes.radius[nb.idx], 0.0).max(axis=1)  # (n,)
    P = basis(bname, X / scale[:, None, None])  # (n, k, m)
    gp = basis_origin_gradient(bname) / scale[:, None, None]  # (n, 2, m)
    is_b = interp[nb.idx] & nb.mask if interp is not None else None
    if is_b is not None and is_b.any():
        return _modified_chunk(x, nb, w, dw, P, gp, is_b, m, offset)
    p0 = np.zeros((len(x), m))
    p0[:, 0] = 1.0  # p(0) = e_1 in the shifted basis
    phi, gx, gy, rcond = moment_shape(w, dw, P, p0, gp)
    bad = np.flatnonzero(rcond < RCOND_MIN)
    if len(bad):
        _raise_singular(x, bad, rcond, nb.counts, offset)
    return phi, gx, gy


def _modified_chunk(x, nb, w, dw, P, gp, is_b, m, offset):
    """Seed 002 modified MLS through the bordered system (see module docstring)."""
    n, k = w.shape
    w_in = np.where(is_b, 0.0, w)
    A = _moment(w_in, P)
    M = np.zeros((n, m + k, m + k))
    M[:, :m, :m] = A
    Pb = np.where(is_b[..., None], P, 0.0)  # (n, k, m): columns p(x_J) of boundary nodes
    M[:, :m, m:] = Pb.transpose(0, 2, 1)
    M[:, m:, :m] = Pb
    free = ~is_b  # unused multiplier slots: identity rows decouple them
    M[:, m:, m:] = free[:, :, None] * np.eye(k)
    # Singular values give the condition number directly (the bordered M is
    # indefinite, and these points are few: those near essential boundaries).
    sv = np.linalg.svd(M, compute_uv=False)
    rcond = np.where(np.isfinite(sv).all(axis=1), sv[:, -1] / np.maximum(sv[:, 0], 1e-300), 0.0)
    bad = np.flatnonzero(~(rcond >= RCOND_MIN))
    if len(bad):
        _raise_singular(x, bad, rcond, nb.counts, offset,
                        remedy=(" - with the modified MLS no support may hold more essential-"
                                "boundary nodes than the basis can interpolate (at most 2 collinear "
                                "for a linear basis, 3 for quadratic): reduce d_max, or use another "
                                "bc method"))
    inv = np.linalg.inv(M)
    gam = inv[:, :, 0]  # [gamma; mu]
    gamma, mu = gam[:, :m], gam[:, m:]
    Pg = np.einsum("nki,ni->nk", P, gamma)
    phi = np.where(is_b, mu, w_in * Pg)
    if dw is None:
        return phi, None, None
    out = []
    for c in range(2):
        dw_in = np.where(is_b, 0.0, dw[..., c])
        A_c = _moment(dw_in, P)
        rhs = np.zeros((n, m + k))
        rhs[:, :m] = gp[:, c, :] - np.einsum("nij,nj->ni", A_c, gamma)
        gam_c = np.einsum("nij,nj->ni", inv, rhs)
        val = dw_in * Pg + w_in * np.einsum("nki,ni->nk", P, gam_c[:, :m])
        out.append(np.where(is_b, gam_c[:, m:], val))
    return phi, out[0], out[1]


def _check_neighbour_counts(x, nb, basis, special):
    """Raise SingularMomentMatrix if a point has fewer neighbours than the basis has terms.

    ``special (n,)`` bool or None: points whose support holds an interpolating
    node, left to the bordered system's own check. Returns None.
    """
    lonely = nb.counts < basis_size(basis)
    if special is not None:
        lonely &= ~special
    lonely = np.flatnonzero(lonely)
    if len(lonely):
        k = lonely[0]
        raise SingularMomentMatrix(
            f"point {k} {x[k].tolist()} has {int(nb.counts[k])} neighbour(s), fewer than the "
            f"{basis_size(basis)} terms of the {basis} basis ({len(lonely)} point(s) affected). "
            "Remedy: enlarge the support (d_max) or add nodes near this point."
        )


def _numba_path(x, nodes, nb, given, weight, basis, beta, derivatives, k=1):
    """Plain MLS by the compiled kernels (:mod:`efgkit.approx.kernels`) at every point of ``x (n, 2)``.

    ``nb`` holds the neighbours ``(n, k)``, ``given`` the crack rule's padded
    ``(w, dwx, dwy)``, each (n, k), or None. Returns the list ``[phi, dphidx,
    dphidy]`` of ndarray (n, k); raises SingularMomentMatrix (point numbers
    counted in ``x``).
    """
    from .kernels import BASIS_IDS, mls_linear, mls_padded, weight_id

    wg = [np.zeros((0, 0))] * 3 if given is None else list(given)
    if basis == "linear":
        res = mls_linear(x, nodes.x, nodes.radius, nb.idx, nb.mask, weight_id(weight, k),
                         beta, derivatives, *wg)
    else:
        res = mls_padded(x, nodes.x, nodes.radius, nb.idx, nb.mask, weight_id(weight, k),
                         beta, BASIS_IDS[basis], derivatives, *wg)
    bad = np.flatnonzero(~(res[3] >= RCOND_MIN))
    if len(bad):
        _raise_singular(x, bad, res[3], nb.counts, 0)
    return list(res[:3])


def _numpy_path(x, nodes, nb, given, wfun, basis, derivatives, interpolate, chunk, rows=None, vals=None):
    """MLS by plain numpy at the points ``rows`` of ``x (n, 2)`` (all if None), ``chunk`` at a time.

    A chunk whose supports hold an interpolating node takes the modified MLS
    (:func:`_modified_chunk`). The results go into the rows ``rows`` of
    ``vals`` (new zero arrays if None). Returns ``vals``, the list ``[phi,
    dphidx, dphidy]`` of ndarray (n, k) (the derivatives left as they were
    without ``derivatives``).
    """
    if vals is None:
        vals = [np.zeros(nb.idx.shape) for _ in range(3)]
    if rows is None:
        rows = np.arange(len(x))
    for s in range(0, len(rows), chunk):
        sl = rows[s:s + chunk]
        res = _mls_chunk(x[sl], nodes, nb.subset(sl), wfun, basis, derivatives, interpolate, s,
                         None if given is None else [g[sl] for g in given])
        for v, r in zip(vals, res, strict=True):
            if r is not None:
                v[sl] = r
    return vals


def _modified_path(x, nodes, nb, given, special, weight, basis, beta, derivatives, wfun, interpolate,
                   chunk, k=1):
    """The numba backend when some supports hold interpolating nodes (seed 002 modified MLS).

    The compiled kernel serves the points of ``x (n, 2)`` whose ``special (n,)``
    is False, the numpy path (the bordered system) the others. Returns the list
    ``[phi, dphidx, dphidy]`` of ndarray (n, k).
    """
    plain = np.flatnonzero(~special)
    res = _numba_path(x[plain], nodes, nb.subset(plain),
                      None if given is None else [g[plain] for g in given],
                      weight, basis, beta, derivatives, k)
    vals = [np.zeros(nb.idx.shape) for _ in range(3)]
    for v, r in zip(vals, res, strict=True):
        v[plain] = r
    return _numpy_path(x, nodes, nb, given, wfun, basis, derivatives, interpolate, chunk,
                       rows=np.flatnonzero(special), vals=vals)


def mls_shape(x: np.ndarray, nodes: NodeCloud, weight: str = "quartic", basis: str = "linear",
              *, d_max: float = 2.0, alpha: float = 0.5, derivatives: bool = True,
              neighbours: Neighbours | None = None, interpolate: np.ndarray | None = None,
              weights: tuple | None = None, backend: str = "auto", chunk: int = 32768,
              k: int = 1) -> Shape:
    """MLS shape functions of ``nodes`` at points ``x (n_points, 2)``.

    Parameters
    ----------
    x : ndarray, shape (n_points, 2)
    nodes : NodeCloud
    weight, basis : str
        See :class:`efgkit.EFG`.
    d_max, alpha : float
        Gaussian weight parameters (beta = d_max / alpha).
    derivatives : bool
        Also form d/dx and d/dy (skip for evaluation-only uses).
    neighbours : Neighbours, optional
        Precomputed neighbour lists (found if not given).
    interpolate : ndarray (n_nodes,) bool, optional
        Nodes with the Kronecker-delta property (seed 002 modified MLS).
    weights : (mask, w, dwx, dwy), optional
        Padded pair weights of a crack rule (:func:`efgkit.approx.crack_rules.crack_weights`),
        each (n_points, k) like ``neighbours``; ``mask`` replaces the neighbours' mask.
    k : int
        Exponent of the Gaussian weight (seed 002 Eq. 7; 1: seed 003 Eq. 1a).
    backend : {"auto", "numba", "numpy"}
        Compiled kernel (:mod:`efgkit.approx.kernels`) or the plain-numpy
        reference; they agree to 1e-12. Points of the modified MLS always use
        the numpy path. "auto": numba from :data:`efgkit.jit.COMPILED_MIN` points on.

    Returns
    -------
    Shape
        Padded values and derivatives; ``phi``, ``dx``, ``dy`` csr_array (n_points, n_nodes).

    Raises
    ------
    SingularMomentMatrix
        Naming the point, its coordinates, neighbour count and the remedy.

    Examples
    --------
    >>> from efgkit import Domain, EFG
    >>> from efgkit.nodes import generate_nodes
    >>> cloud = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> sh = mls_shape(np.array([[0.3, 0.7]]), cloud)
    >>> u = 2 * cloud.x[:, 0] - cloud.x[:, 1]          # linear field: reproduced exactly
    >>> round(float((sh.phi @ u)[0]), 12), round(float((sh.dx @ u)[0]), 12)
    (-0.1, 2.0)
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x must have shape (n_points, 2), got {x.shape}")
    nb = find_neighbours(x, nodes) if neighbours is None else neighbours
    given = None
    if weights is not None:
        nb = Neighbours(nb.idx, weights[0])
        given = tuple(np.ascontiguousarray(a, dtype=float) for a in weights[1:])
    # points whose support holds an interpolating node (the modified MLS)
    special = None if interpolate is None else (interpolate[nb.idx] & nb.mask).any(axis=1)
    _check_neighbour_counts(x, nb, basis, special)
    backend = resolve_backend(backend, len(x))
    wfun = weight_function(weight, d_max, alpha, k)
    if backend == "numba" and (special is None or not special.any()):
        vals = _numba_path(x, nodes, nb, given, weight, basis, d_max / alpha, derivatives, k)
    elif backend == "numba" and not special.all():
        vals = _modified_path(x, nodes, nb, given, special, weight, basis, d_max / alpha, derivatives,
                              wfun, interpolate, chunk, k)
    else:
        vals = _numpy_path(x, nodes, nb, given, wfun, basis, derivatives, interpolate, chunk)
    if not derivatives:
        vals[1] = vals[2] = None
    return Shape(nb, vals[0], vals[1], vals[2], nodes.n)
