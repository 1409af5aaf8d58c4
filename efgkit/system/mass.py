"""The lumped mass matrix of the explicit driver, with its checks.

Nodal unknowns get the row sum of the consistent mass, seed 002 Eqs. (25)-(27):

    M_I = rho sum_q w_q v_I(x_q) sum_J psi_J(x_q)

with the test functions ``v`` (``v = phi`` for EFG) and every trial function ``psi``
(nodal MLS functions, which are a partition of unity, so ``M_I = rho sum_q w_q v_I(x_q)``).
The enrichment unknowns (tip functions, extrinsic K_I, K_II fields) are not a partition
of unity, are not translations and change sign, so their row sum can be zero or negative:
they get the diagonal of the consistent mass instead,

    M_e = rho sum_q w_q (E_e,x(x_q)^2 + E_e,y(x_q)^2),

positive for every unknown that is non-zero somewhere (docs/theory.md, "Lumped mass").
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array, diags_array

from ..approx.shape import Shape

__all__ = ["ENRICHMENT_MASSES", "MassError", "consistent_mass", "row_sum_mass"]


class MassError(ValueError):
    """A lumped mass is not positive, or the masses do not add up to rho times the area."""


ENRICHMENT_MASSES = ("diagonal", "abs_row_sum")


def row_sum_mass(shape: Shape, w: np.ndarray, rho: float, area: float | None = None,
                 node_x: np.ndarray | None = None, test: Shape | None = None,
                 rtol: float = 1e-6, enrichment: str = "diagonal") -> np.ndarray:
    """Diagonal lumped mass, shape (n_dofs,) in the DOF order of ``shape`` (2 I + c, then
    the enrichment unknowns), seed 002 Eqs. (25)-(27) (module docstring).

    Parameters
    ----------
    shape : Shape
        Trial functions at the domain quadrature points (values only are used).
    w : ndarray, shape (n_points,)
        Quadrature weights.
    rho : float
        Mass density.
    area : float, optional
        Area of the body: with Bubnov-Galerkin test functions the nodal masses of each
        component must add up to ``rho * area`` within ``rtol`` (checked when given).
    node_x : ndarray, shape (n_nodes, 2), optional
        Node positions, to name the node of a failing mass.
    test : Shape, optional
        Test functions (Petrov-Galerkin, e.g. MLPG); default the trial functions. Their
        row sums ``rho int v_I`` need not add up to the body's mass: only positivity is
        checked then.
    rtol : float
        Tolerance of the total-mass check.
    enrichment : {"diagonal", "abs_row_sum"}
        Mass of the enrichment unknowns: the diagonal of their consistent mass (module
        docstring), or the row sum of its absolute values over every unknown,
        ``M_e = sum_b |M_C,eb|`` (:func:`consistent_mass`), which bounds the eigenvalues of
        ``M^-1 M_C`` on those rows by 1 (Gershgorin) and keeps the enrichment from lowering
        the critical step. Measured on ``verification/freund.py`` (spacing 0.01): with
        PU enrichment the critical step goes from 0.0023 to 0.0118 (the unenriched one) and
        the error of K_I(t) from J' from 3.7 % to 0.74 %; with extrinsic MLS from 0.0088 to
        0.0118 and from 0.37 % to 0.62 % (the freund record).

    Raises
    ------
    MassError
        A mass is not positive (naming the unknown, its node and position), or the
        total differs from ``rho * area``.

    Examples
    --------
    >>> from efgkit import Domain, EFG
    >>> from efgkit.methods.discretize import discretize
    >>> from efgkit import Elastic, Scene
    >>> d = discretize(Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3)), EFG(spacing=0.25))
    >>> m = row_sum_mass(d.shape, d.points.w, 3.0, area=2.0)
    >>> round(float(m[0::2].sum()), 10)      # rho * area = 6
    6.0
    """
    if not (np.isfinite(rho) and rho > 0):
        raise ValueError(f"rho must be finite and > 0, got {rho!r}: give Elastic(..., rho=...)")
    test_given = test is not None
    test = shape if test is None else test
    w = np.asarray(w, dtype=float)
    nb = test.neighbours
    pu = np.asarray(shape.phi.sum(axis=1)).ravel()  # sum_J psi_J of the nodal functions
    contrib = rho * (w * pu)[:, None] * test.values * nb.mask
    m_nodal = np.bincount(nb.idx[nb.mask], contrib[nb.mask], minlength=test.n_functions)
    parts = [np.repeat(m_nodal, 2)]
    if enrichment not in ENRICHMENT_MASSES:
        raise ValueError(f"enrichment must be one of {ENRICHMENT_MASSES} (the mass of the "
                         f"enrichment unknowns), got {enrichment!r}")
    if shape.extra is not None and enrichment == "abs_row_sum":
        n2 = 2 * shape.n_functions
        M = abs(consistent_mass(shape, w, rho)).tocsr()[n2:]
        parts.append(np.asarray(M.sum(axis=1)).ravel())
    elif shape.extra is not None:
        e = shape.extra
        m_extra = rho * (w @ (e.ux.multiply(e.ux)) + w @ (e.uy.multiply(e.uy)))
        parts.append(np.asarray(m_extra).ravel())
    m = np.concatenate(parts)
    bad = np.flatnonzero(~(np.isfinite(m) & (m > 0)))
    if len(bad):
        k = int(bad[0])
        n2 = 2 * test.n_functions
        if k < n2:
            where = f"node {k // 2}" + (f" at {node_x[k // 2].tolist()}" if node_x is not None else "")
            why = ("its test function integrates to a non-positive value over the body (a node "
                   "whose support barely reaches into the body, or a quadratic basis near a "
                   "corner); check the quadrature covers its support, or use basis='linear'")
        else:
            where = f"enrichment unknown {k - n2}"
            why = "its function is zero at every quadrature point: enrichment nodes outside the body"
        raise MassError(f"lumped mass {m[k]:.3g} of unknown {k} ({where}) is not positive "
                        f"({len(bad)} unknown(s) fail): {why}")
    if area is not None and not test_given:
        total = float(m_nodal.sum())
        if abs(total - rho * area) > rtol * rho * area:
            raise MassError(
                f"the nodal masses add up to {total:.10g} per component, not rho * area = "
                f"{rho * area:.10g} (relative difference {abs(total / (rho * area) - 1):.2e} > "
                f"{rtol:g}): the domain quadrature weights sum to {w.sum():.10g} against the area "
                f"{area:.10g}, or the shape functions are not a partition of unity at some points")
    return m


def consistent_mass(shape: Shape, w: np.ndarray, rho: float, rows=None) -> csr_array:
    """The consistent (Bubnov-Galerkin) mass ``M_ab = rho sum_q w_q psi_a(x_q) . psi_b(x_q)``,
    csr_array (n_dofs, n_dofs), over the points of ``shape`` (the domain quadrature) with
    weights ``w (n_points,)``, or over the points ``rows`` (int array) alone; enrichment
    unknowns included.

    Its row sums over the nodal unknowns are the lumped masses of :func:`row_sum_mass`
    (seed 002 Eqs. 25-27) for the same points. The explicit driver never solves with it
    (an MLS consistent mass is badly conditioned: ``M^-1 M_C`` has eigenvalues down to
    ~1e-5 on a regular grid with ``d_max = 2.5``); :mod:`efgkit.explicit.dsif` applies it
    in the acceleration recovery of the dynamic J'.

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic, Scene
    >>> from efgkit.methods.discretize import discretize
    >>> d = discretize(Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3)), EFG(spacing=0.25))
    >>> M = consistent_mass(d.shape, d.points.w, 3.0)
    >>> bool(np.allclose(M.sum(axis=1), row_sum_mass(d.shape, d.points.w, 3.0)))
    True
    """
    if not (np.isfinite(rho) and rho > 0):
        raise ValueError(f"rho must be finite and > 0, got {rho!r}: give Elastic(..., rho=...)")
    w = np.asarray(w, dtype=float)
    if w.shape != (shape.neighbours.idx.shape[0],):
        raise ValueError(f"w must have shape ({shape.neighbours.idx.shape[0]},) (one weight per "
                         f"point of shape), got {w.shape}")
    Ux, Uy = shape.u_operators()
    if rows is not None:
        rows = np.asarray(rows, dtype=np.int64)
        Ux, Uy, w = Ux[rows], Uy[rows], w[rows]
    W = diags_array(rho * w)
    return csr_array(Ux.T @ (W @ Ux) + Uy.T @ (W @ Uy))
