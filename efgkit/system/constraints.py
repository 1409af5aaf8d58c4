"""Essential boundary conditions: penalty, Lagrange multipliers, modified variational
principle, and elimination (for the modified MLS of seed 002).

Each method turns ``K c = f`` plus the prescribed displacements into one
:class:`LinearSystem`. Prescribed data come as :class:`Dirichlet`: boundary
quadrature points, the shape functions there, the prescribed components
and values.

* penalty, seed 003 Eq. (28): ``(K + beta G^T S G) c = f + beta G^T S ubar``;
  inconsistent by O(E / (beta h)) and locking for very large beta; default ``1e3 E / h``.
* Lagrange multipliers, Eq. (26): multipliers piecewise linear along each
  constrained edge (hats on the boundary segments), saddle-point system.
* modified variational principle, Eq. (27): the multiplier replaced by the
  traction t(u) = sigma(u) n, ``K - H - H^T``; stabilised (Nitsche) by a
  penalty ``beta`` (default ``100 E / h``) because Eq. (27) alone is not coercive.
* elimination (row cross-out, seed 002 after Eq. 19): with Kronecker-delta
  shape functions at the constrained nodes their coefficients are the
  prescribed values.

``boundary_traction_term`` is the Gamma_u term ``H = G^T W T`` on its own, for the
modified collocation method of :mod:`efgkit.system.collocation`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_array, csr_array, diags_array, vstack

from ..approx.shape import Shape
from .linear_system import LinearSystem

__all__ = ["Dirichlet", "RigidBodyModeError", "penalty", "lagrange", "rigid_body_modes",
           "modified_variational", "eliminate", "check_rigid_modes", "boundary_traction_term"]


class RigidBodyModeError(ValueError):
    """The essential boundary conditions leave a rigid-body motion free."""


@dataclass(frozen=True, eq=False)
class Dirichlet:
    """Prescribed displacements sampled at boundary quadrature points.

    Attributes
    ----------
    x : (m, 2) points; w : (m,) line weights; normal : (m, 2) outward normals
    shape : Shape
        Shape functions (with derivatives for the variational method) at ``x``.
    fixed : (m, 2) bool
        Which components are prescribed at each point.
    value : (m, 2)
        Prescribed values (ignored where not fixed).
    segment : (m,) int, t : (m,) float
        Boundary segment of each point and its local coordinate, in [0, 1]
        except on a corner piece that extrapolates its neighbour's multiplier
        (the Lagrange-multiplier hats are linear in t between the segment's
        two hat nodes).
    seg_nodes : (n_segments, 2) int
        Multiplier-hat node numbers at the two ends of each segment.
    """

    x: np.ndarray
    w: np.ndarray
    normal: np.ndarray
    shape: Shape
    fixed: np.ndarray
    value: np.ndarray
    segment: np.ndarray
    t: np.ndarray
    seg_nodes: np.ndarray


def _fixed_rows(ops, fixed: np.ndarray) -> csr_array:
    """Rows (point, component) of the fixed components, point-major like ``value[fixed]``.

    ``ops`` are the x and y component operators (n_points, n_dofs).
    """
    n = fixed.shape[0]
    q, c = np.nonzero(fixed)
    return csr_array(vstack(list(ops), format="csr")[c * n + q])


def _at_points(fixed: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(m, 2) array with ``values`` (point-major, as ``fixed`` rows) at the fixed components."""
    out = np.zeros(fixed.shape)
    out[fixed] = values
    return out


def _component_operator(shape: Shape, fixed: np.ndarray) -> csr_array:
    """Rows (point, component) for fixed components -> coefficient columns (n_dofs)."""
    return _fixed_rows(shape.u_operators(), fixed)


def rigid_body_modes(x: np.ndarray) -> np.ndarray:
    """Coefficients of the three rigid-body motions, shape (2 n, 3).

    MLS reproduces linear fields, so nodal values of a rigid motion are its
    coefficients.
    """
    R = np.zeros((2 * len(x), 3))
    R[0::2, 0] = 1.0
    R[1::2, 1] = 1.0
    R[0::2, 2] = -(x[:, 1] - x[:, 1].mean())
    R[1::2, 2] = x[:, 0] - x[:, 0].mean()
    return R


def check_rigid_modes(C: csr_array, node_x: np.ndarray, rows: int | None = None) -> None:
    """Raise :class:`RigidBodyModeError` unless the constraint operator ``C`` (its first
    ``rows`` rows if given) fixes all three rigid-body motions (rank 3 of ``C R``)."""
    rows = C.shape[0] if rows is None else rows
    if rows == 0:
        raise RigidBodyModeError(
            "the scene has no essential boundary condition: the body can move as a rigid body. "
            "Add a Support that prescribes ux and uy somewhere (and a rotation restraint)."
        )
    R = np.zeros((C.shape[1], 3))  # enrichment unknowns (after the nodal ones) stay 0
    R[: 2 * len(node_x)] = rigid_body_modes(node_x)
    R /= np.linalg.norm(R, axis=0)
    CR = (C @ R)[:rows]
    sv = np.linalg.svd(CR, compute_uv=False)
    names = ["translation in x", "translation in y", "rotation"]
    if len(sv) < 3 or sv[-1] < 1e-8 * sv[0]:  # fewer than 3 constraints (one point) never suffice
        _, _, vt = np.linalg.svd(CR)
        free = names[int(np.argmax(np.abs(vt[-1])))]
        raise RigidBodyModeError(
            f"the essential boundary conditions leave a rigid-body mode free (mostly {free}); "
            "the stiffness matrix would be singular. Prescribe more displacement components."
        )


def penalty(K, f, bc: Dirichlet, beta: float, node_x: np.ndarray,
            check: bool = True) -> LinearSystem:
    """Penalty method, seed 003 Eq. (28). ``check=False`` allows rigid-body modes (dynamics)."""
    G = _component_operator(bc.shape, bc.fixed)
    if check:
        check_rigid_modes(G, node_x)
    w = np.broadcast_to(bc.w[:, None], bc.fixed.shape)[bc.fixed]
    W = diags_array(beta * w)
    A = csr_array(K + G.T @ W @ G)
    b = f + G.T @ (beta * w * bc.value[bc.fixed])

    def forces(z):  # the penalty force -beta (u^h - ubar) ds at each point
        return bc.x, _at_points(bc.fixed, -beta * w * (G @ z[: K.shape[0]] - bc.value[bc.fixed]))
    return LinearSystem(A, b, spd=True, n_coeffs=K.shape[0], support_forces=forces)


def _abs_max(K) -> float:
    """max |K_ij| of a sparse matrix from its stored values without the copy ``abs(K)``
    makes (0.2 GB for the stiffness of 1e5 nodes); the same number."""
    d = csr_array(K).data
    return float(max(d.max(), -d.min())) if len(d) else 0.0


def lagrange(K, f, bc: Dirichlet, node_x: np.ndarray, check: bool = True) -> LinearSystem:
    """Lagrange multipliers, seed 003 Eq. (26), with piecewise-linear multipliers.
    ``check=False`` allows rigid-body modes (dynamics, where the mass holds them).

    ``[[K, G^T], [G, 0]] [c; lambda] = [f; q]`` with ``G_kI = int N_k phi_I ds``
    and ``q_k = int N_k ubar ds`` for each hat N_k and prescribed component. The system
    holds the blocks ``(K, G)``; the matrix is formed only if asked for (:class:`LinearSystem`).
    """
    Gpt = _component_operator(bc.shape, bc.fixed)  # (n_fixed_rows, n_dofs)
    if check:
        check_rigid_modes(Gpt, node_x)
    pts, comps = np.nonzero(bc.fixed)
    n_hat = int(bc.seg_nodes.max()) + 1
    # Rows of Gpt (point, comp) -> hats (node, comp): N = 1 - t and t at the segment ends.
    ends = bc.seg_nodes[bc.segment[pts]]
    tt = bc.t[pts]
    lam_rows = np.concatenate([2 * ends[:, 0] + comps, 2 * ends[:, 1] + comps])
    src = np.concatenate([np.arange(len(pts))] * 2)
    weight = np.concatenate([(1 - tt), tt]) * np.concatenate([bc.w[pts]] * 2)
    N = coo_array((weight, (lam_rows, src)), shape=(2 * n_hat, len(pts))).tocsr()
    G = csr_array(N @ Gpt)
    q = N @ bc.value[pts, comps]
    used = np.flatnonzero(np.asarray(abs(G).sum(axis=1)).ravel() > 0)
    G, q = G[used], q[used]
    # Scale the constraint rows like the stiffness: K ~ E and G ~ h otherwise differ by the
    # modulus, and the residual check ||A z - b|| <= rtol ||b|| would weigh the tiny
    # prescribed displacements against forces (the multipliers come out scaled; unused).
    scale = _abs_max(K) / max(abs(G).max(), np.finfo(float).tiny) if G.shape[0] else 1.0
    G, q = csr_array(scale * G), scale * q
    # held as its blocks: the saddle-point matrix (a copy of K) is formed only if asked for
    n, K = K.shape[0], csr_array(K)

    def forces(z):  # -lambda ds at each point: the multipliers (scaled back) on the hats
        lam = np.zeros(N.shape[0])
        lam[used] = scale * z[n:]
        return bc.x, _at_points(bc.fixed, -(N.T @ lam))
    return LinearSystem(None, np.concatenate([f, q]), spd=False, n_coeffs=n, support_forces=forces,
                        blocks=(K, G))


DENSE_DOFS = 200  # up to this many unknowns Nitsche's terms are formed in dense arrays
_VOIGT = np.array([[0, 2], [2, 1]])  # (component, derivative) -> Voigt row (xx, yy, xy)


def _triplets(bc: Dirichlet, D: np.ndarray):
    """(rows, cols, values) of ``[G; T]`` (2 m_fixed, n_dofs): the rows (point, fixed
    component) of the displacement ``G`` (point-major, as ``value[fixed]``), then those of
    the traction ``T``, straight from the padded shape functions and the enrichment's COO.

    ``t_c = sum_l n_l sigma_(c l) = sum_(a, j) L_(c a j) du_a/dx_j`` with
    ``L_(c a j) = sum_l n_l D[v(c, l), v(a, j)]`` (v the Voigt row, engineering shear), so
    the nodal function phi_I e_b adds ``sum_j L_(c b j) d phi_I / dx_j`` in column 2 I + b
    and an enrichment gradient entry g_(a j) adds ``L_(c a j) g_(a j)`` (duplicates summed
    when the CSR is formed). The same operators as the component and gradient operators
    combined by sparse algebra (G identical, T to rounding), in a few array passes.
    """
    sh, fixed = bc.shape, bc.fixed
    qs, cs = np.nonzero(fixed)
    m = len(qs)
    rid = np.full(fixed.shape, -1)
    rid[qs, cs] = np.arange(m)
    L = np.einsum("ql,clak->qcak", bc.normal, D[_VOIGT[:, :, None, None], _VOIGT[None, None]])
    nb = sh.neighbours
    mask, idx = nb.mask[qs], nb.idx[qs]
    r = np.broadcast_to(np.arange(m)[:, None], idx.shape)[mask]
    i2 = 2 * idx[mask]
    dx, dy = sh.ddx[qs][mask], sh.ddy[qs][mask]
    Lr = L[qs, cs]  # (m, 2 b, 2 j)
    rows = [r, m + r, m + r]
    cols = [i2 + cs[r], i2, i2 + 1]
    vals = [sh.values[qs][mask]] + [Lr[r, b, 0] * dx + Lr[r, b, 1] * dy for b in (0, 1)]
    e = sh.extra
    if e is not None:
        n2 = 2 * sh.n_functions
        for c, op in enumerate((e.ux, e.uy)):
            q, col, v = _coo(op)
            keep = rid[q, c] >= 0
            rows.append(rid[q[keep], c])
            cols.append(col[keep] + n2)
            vals.append(v[keep])
        for (a, k), op in zip(((0, 0), (0, 1), (1, 0), (1, 1)), (e.gxx, e.gxy, e.gyx, e.gyy),
                              strict=True):
            q, col, v = _coo(op)
            for c in (0, 1):
                keep = rid[q, c] >= 0
                rows.append(m + rid[q[keep], c])
                cols.append(col[keep] + n2)
                vals.append(L[q[keep], c, a, k] * v[keep])
    return m, np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)


def _coo(op: csr_array) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(row, column, value) of the stored entries of a CSR ``op``."""
    return np.repeat(np.arange(op.shape[0]), np.diff(op.indptr)), op.indices, op.data


def boundary_traction_term(bc: Dirichlet, D: np.ndarray) -> csr_array:
    """The Gamma_u boundary term of the Galerkin weak form, ``H = G^T W T`` (n_dofs, n_dofs).

    ``H_(Ia),(Jb) = sum_q w_q phi_I(x_q) t_a(phi_J e_b)(x_q)`` over the boundary points
    of the prescribed components a, with ``t = N^T D B`` the traction: the term ``-int_{Gamma_u}
    v . t(u) dGamma`` that test functions not vanishing on Gamma_u leave in the weak form.
    ``K - H`` is the stiffness of the modified collocation method (Zhu and Atluri 1998,
    :mod:`efgkit.system.collocation`); ``K - H - H^T`` that of Eq. (27) below. Needs the
    shape derivatives at the boundary points (``essential_conditions(disc, derivatives=True)``).
    """
    m, rows, cols, vals = _triplets(bc, D)
    B = csr_array((vals, (rows, cols)), shape=(2 * m, bc.shape.n_dofs))  # [G; T]
    w = np.broadcast_to(bc.w[:, None], bc.fixed.shape)[bc.fixed]
    return csr_array(csr_array(B[:m]).T @ diags_array(w) @ csr_array(B[m:]))


def modified_variational(K, f, bc: Dirichlet, D: np.ndarray, beta: float,
                         node_x: np.ndarray, check: bool = True) -> LinearSystem:
    """Modified variational principle, seed 003 Eq. (27), with Nitsche stabilisation beta.

    With G u the prescribed components and T u the matching traction
    components at boundary points (weights w):
    ``A = K - G^T W T - T^T W G + beta G^T W G``,
    ``b = f - T^T W ubar + beta G^T W ubar``.
    """
    m, rows, cols, vals = _triplets(bc, D)
    n = bc.shape.n_dofs
    w = np.broadcast_to(bc.w[:, None], bc.fixed.shape)[bc.fixed]
    ub = bc.value[bc.fixed]
    # A - K = [G; T]^T [[beta W, -W], [-W, 0]] [G; T]: one product of B^T and the rows of
    # [beta W G - W T; -W G] (formed from the same triplets); dense for a few unknowns
    if n <= DENSE_DOFS:
        B = np.zeros((2 * m, n))
        np.add.at(B, (rows, cols), vals)
        if check:
            check_rigid_modes(B, node_x, m)
        C = np.vstack([w[:, None] * (beta * B[:m] - B[m:]), -w[:, None] * B[:m]])
        A = csr_array(K.toarray() + B.T @ C)
        b = f + B.T @ np.concatenate([beta * w * ub, -w * ub])
    else:
        B, A, b = _nitsche_sparse(K, f, m, rows, cols, vals, n, w, ub, beta, node_x, check)

    def forces(z):  # the consistent flux (sigma^h n - beta (u^h - ubar)) ds at each point
        gc, tc = np.split(B @ z[: K.shape[0]], 2)
        return bc.x, _at_points(bc.fixed, w * (tc - beta * (gc - ub)))
    return LinearSystem(A, b, spd=True, n_coeffs=K.shape[0], support_forces=forces)


def _nitsche_sparse(K, f, m, rows, cols, vals, n, w, ub, beta, node_x, check):
    """``[G; T]``, A and b of :func:`modified_variational` by sparse products."""
    B = csr_array((vals, (rows, cols)), shape=(2 * m, n))  # [G; T]
    if check:
        check_rigid_modes(B, node_x, m)
    g = rows < m
    wr = np.where(g, w[np.where(g, rows, rows - m)], 0.0)
    Bt = csr_array((vals, (cols, rows)), shape=(n, 2 * m))
    scaled = np.concatenate([np.where(g, beta * wr, -w[np.where(g, rows, rows - m)]) * vals,
                             -wr[g] * vals[g]])
    C = csr_array((scaled, (np.concatenate([np.where(g, rows, rows - m), rows[g] + m]),
                            np.concatenate([cols, cols[g]]))), shape=(2 * m, n))
    return B, csr_array(K + Bt @ C), f + Bt @ np.concatenate([beta * w * ub, -w * ub])


def eliminate(K, f, fixed_dofs: np.ndarray, fixed_values: np.ndarray,
              node_x: np.ndarray, springs=None) -> LinearSystem:
    """Direct elimination of coefficients known to equal prescribed values.

    Valid for shape functions with the Kronecker-delta property at the
    constrained nodes (seed 002 Eq. 19, 'row cross-out'). ``springs``: optional
    ``(P (k, n_dofs), values (k,), beta (k,), x (k, 2), comp (k,))``, point constraints
    ``P c = values`` on component ``comp`` imposed by springs of stiffness ``beta`` at the
    points ``x`` (point supports).
    """
    n = K.shape[0]
    C = csr_array((np.ones(len(fixed_dofs)), (np.arange(len(fixed_dofs)), fixed_dofs)),
                  shape=(len(fixed_dofs), n))
    K0, f0 = K, f  # the support forces are K0 c - f0 on the eliminated rows
    if springs is not None:
        P, pv, pb, px, pc = springs
        check_rigid_modes(csr_array(vstack([C, P], format="csr")), node_x)
        K = csr_array(K + P.T @ diags_array(pb) @ P)
        f = f + P.T @ (pb * pv)
    else:
        check_rigid_modes(C, node_x)
    c0 = np.zeros(n)
    c0[fixed_dofs] = fixed_values
    free = np.setdiff1d(np.arange(n), fixed_dofs)
    Kc = K.tocsc()
    A = csr_array(Kc[:, free].tocsr()[free])
    b = (f - K @ c0)[free]
    fx = np.repeat(node_x, 2, axis=0)[fixed_dofs] if len(fixed_dofs) else np.zeros((0, 2))

    def forces(z):  # K c - f on the eliminated rows, at their nodes (and the springs' forces)
        c = c0.copy()
        c[free] = z
        r = np.zeros((len(fixed_dofs), 2))
        r[np.arange(len(fixed_dofs)), fixed_dofs % 2] = (K0 @ c - f0)[fixed_dofs]
        if springs is None:
            return fx, r
        rs = np.zeros((len(pv), 2))
        rs[np.arange(len(pv)), pc] = -pb * (P @ c - pv)
        return np.vstack([fx, px]), np.vstack([r, rs])
    return LinearSystem(A, b, spd=True, n_coeffs=n, free=free, fixed_values=c0,
                        support_forces=forces)
