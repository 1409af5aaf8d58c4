"""Shape functions at points, as padded arrays and sparse operators.

A :class:`Shape` holds the nodal MLS functions non-zero at each point
(``neighbours``, padded values and derivatives) and, with enrichment, an
:class:`Extra` block of component operators for the unknowns that follow the
nodal ones (PU functions, extrinsic K_I and K_II). Fields are sparse algebra
on these: :meth:`Shape.displacement`, :meth:`Shape.gradient`, :meth:`Shape.strain`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.sparse import csr_array

from ..problem.material import strain_from_gradient
from ..search import Neighbours

__all__ = ["Extra", "Shape", "Gradients"]


@dataclass(frozen=True, eq=False)
class Extra:
    """Enrichment unknowns beyond the nodal ones, as component operators at the points.

    Attributes
    ----------
    ux, uy : csr_array (n_points, n_extra)
        Displacement components of each enrichment unknown (PU functions
        phi_I q_i carry two unknowns, one per component; the extrinsic MLS
        K_I, K_II of a tip carry vector fields).
    gxx, gxy, gyx, gyy : csr_array (n_points, n_extra) or None
        d ux/dx, d ux/dy, d uy/dx, d uy/dy (None without derivatives).
    """

    ux: csr_array
    uy: csr_array
    gxx: csr_array | None = None
    gxy: csr_array | None = None
    gyx: csr_array | None = None
    gyy: csr_array | None = None

    @property
    def n(self) -> int:
        return (self.ux if self.ux is not None else self.gxx).shape[1]


@dataclass(frozen=True, eq=False)
class Shape:
    """Shape functions at points: padded arrays, and sparse operators built on demand.

    Attributes
    ----------
    neighbours : Neighbours
        ``idx, mask (n_points, k)``: the functions non-zero at each point.
    values, ddx, ddy : ndarray, shape (n_points, k)
        phi_I, d phi_I / dx, d phi_I / dy for the neighbours (0 where masked);
        ``ddx``/``ddy`` are None when derivatives were not asked for.
    n_functions : int
        Number of nodal shape functions (columns of the operators).
    extra : Extra or None
        Enrichment unknowns (their coefficients follow the 2 n_functions
        nodal ones).

    The operators ``phi``, ``dx``, ``dy`` are csr_array (n_points, n_functions):
    ``shape.phi @ coeffs[0:2 * n_functions:2]`` evaluates u_x of the nodal part. With
    enrichment use :meth:`displacement` and :meth:`gradient`, which add it.
    """

    neighbours: Neighbours
    values: np.ndarray
    ddx: np.ndarray | None
    ddy: np.ndarray | None
    n_functions: int
    extra: Extra | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self.neighbours.idx), self.n_functions)

    @property
    def n_dofs(self) -> int:
        """Length of a coefficient vector: 2 n_functions plus the enrichment unknowns."""
        return 2 * self.n_functions + (0 if self.extra is None else self.extra.n)

    def _op(self, vals: np.ndarray | None) -> csr_array:
        if self.neighbours is None:
            raise ValueError("the shape-function values were released after the stiffness "
                             "(Shape.gradients_only); evaluate them with Discretization.shape_at")
        if vals is None:
            raise ValueError("derivatives were not computed: call mls_shape(..., derivatives=True)")
        indptr, cols, full = self._pattern
        data = vals.ravel() if full else vals[self.neighbours.mask]
        # each operator its own copy of the pattern: scipy canonicalises some operands in
        # place (sort_indices, sum_duplicates), which must not reorder another's indices
        return csr_array((data, cols.copy(), indptr.copy()), shape=self.shape)

    @cached_property
    def _pattern(self) -> tuple[np.ndarray, np.ndarray, bool]:
        """(indptr, indices, every row full) of :attr:`phi`, :attr:`dx`, :attr:`dy`, formed once
        for the three (int32 when the sizes allow: scipy would otherwise widen the int32
        neighbour indices to the int64 of the index pointers, a conversion per operator)."""
        nb = self.neighbours
        counts = nb.counts
        it = np.int32 if nb.idx.size < 2**31 and self.n_functions < 2**31 else np.int64
        indptr = np.zeros(len(counts) + 1, dtype=it)
        np.cumsum(counts, out=indptr[1:])
        full = bool(counts.min(initial=0) == nb.idx.shape[1])  # every row full: no masking
        cols = nb.idx.ravel() if full else nb.idx[nb.mask]
        return indptr, cols.astype(it, copy=False), full

    @cached_property
    def phi(self) -> csr_array:
        return self._op(self.values)

    @cached_property
    def dx(self) -> csr_array:
        return self._op(self.ddx)

    @cached_property
    def dy(self) -> csr_array:
        return self._op(self.ddy)

    def _interleaved(self, op: csr_array, comp: int) -> csr_array:
        """A nodal operator with its columns moved to the unknowns 2 I + comp, (n, n_dofs)."""
        return csr_array((op.data, 2 * op.indices + comp, op.indptr),
                         shape=(op.shape[0], self.n_dofs))

    def _with_extra(self, nodal: csr_array, extra: csr_array | None) -> csr_array:
        if extra is None:
            return nodal
        n2 = 2 * self.n_functions
        return csr_array(nodal + csr_array((extra.data, extra.indices + n2, extra.indptr),
                                           shape=nodal.shape))

    def u_operators(self) -> tuple[csr_array, csr_array]:
        """(Ux, Uy), csr_array (n_points, n_dofs) each: ``Ux @ coeffs`` is u_x at the points."""
        e = self.extra
        return (self._with_extra(self._interleaved(self.phi, 0), None if e is None else e.ux),
                self._with_extra(self._interleaved(self.phi, 1), None if e is None else e.uy))

    def grad_operators(self) -> tuple[csr_array, csr_array, csr_array, csr_array]:
        """(d ux/dx, d ux/dy, d uy/dx, d uy/dy), csr_array (n_points, n_dofs) each."""
        e = self.extra
        if e is not None and e.gxx is None:
            raise ValueError("derivatives were not computed: call with derivatives=True")
        pick = (lambda name: None) if e is None else (lambda name: getattr(e, name))
        return (self._with_extra(self._interleaved(self.dx, 0), pick("gxx")),
                self._with_extra(self._interleaved(self.dy, 0), pick("gxy")),
                self._with_extra(self._interleaved(self.dx, 1), pick("gyx")),
                self._with_extra(self._interleaved(self.dy, 1), pick("gyy")))

    def _check(self, coeffs) -> np.ndarray:
        c = np.asarray(coeffs, dtype=float)
        if c.shape != (self.n_dofs,):
            raise ValueError(f"coeffs must have shape ({self.n_dofs},), got {c.shape}")
        return c

    def displacement(self, coeffs) -> np.ndarray:
        """u at the points for coefficients ``coeffs (n_dofs,)``, shape (n_points, 2)."""
        c = self._check(coeffs)
        n2 = 2 * self.n_functions
        u = np.column_stack([self.phi @ c[0:n2:2], self.phi @ c[1:n2:2]])
        if self.extra is not None:
            u += np.column_stack([self.extra.ux @ c[n2:], self.extra.uy @ c[n2:]])
        return u

    def gradient(self, coeffs) -> np.ndarray:
        """du_i/dx_j at the points, shape (n_points, 2, 2)."""
        c = self._check(coeffs)
        n2 = 2 * self.n_functions
        ux, uy = c[0:n2:2], c[1:n2:2]
        g = np.stack([np.column_stack([self.dx @ ux, self.dy @ ux]),
                      np.column_stack([self.dx @ uy, self.dy @ uy])], axis=1)
        e = self.extra
        if e is not None:
            if e.gxx is None:
                raise ValueError("derivatives were not computed: call with derivatives=True")
            ce = c[n2:]
            g += np.stack([np.column_stack([e.gxx @ ce, e.gxy @ ce]),
                           np.column_stack([e.gyx @ ce, e.gyy @ ce])], axis=1)
        return g

    def strain(self, coeffs) -> np.ndarray:
        """Strain (xx, yy, xy engineering) at the points, shape (n_points, 3)."""
        return strain_from_gradient(self.gradient(coeffs))

    def without_values(self) -> Shape:
        """This shape without the values: ``values`` and the enrichment's ``ux, uy`` dropped
        (the stiffness and the gradients need the derivatives only)."""
        e = self.extra
        if e is not None:
            e = Extra(None, None, e.gxx, e.gxy, e.gyx, e.gyy)
        return Shape(self.neighbours, None, self.ddx, self.ddy, self.n_functions, e)

    def gradients_only(self) -> Gradients:
        """What post-processing needs of the derivatives, compact: the operators ``dx, dy``
        as CSR over the valid neighbours only (sharing one int32 index array) and the
        enrichment's gradient operators; the values, the padded arrays and the enrichment's
        displacement operators are dropped. About ``20 nnz`` bytes against ``29 n k`` for
        the padded arrays (nnz = the (point, node) pairs, ``n k`` the padded slots: at
        1e5 nodes of the cracked plate nnz ~ 0.57 n k). The operators are the ones
        :attr:`dx`, :attr:`dy` build, so every field computed from them is unchanged."""
        if self.ddx is None:
            raise ValueError("derivatives were not computed: call with derivatives=True")
        nb = self.neighbours
        small = nb.idx.size < 2**31  # int32 index pointers and indices
        indptr = np.zeros(len(nb.mask) + 1, np.int32 if small else np.int64)
        np.cumsum(nb.counts, out=indptr[1:])
        cols = nb.idx[nb.mask].astype(indptr.dtype, copy=False)  # copies: the padded arrays go
        dx = csr_array((self.ddx[nb.mask], cols, indptr), shape=self.shape)
        dy = csr_array((self.ddy[nb.mask], dx.indices, dx.indptr), shape=self.shape)
        extra = self.extra
        if extra is not None:
            extra = Extra(None, None, *(None if op is None else _narrow(op) for op in
                                        (extra.gxx, extra.gxy, extra.gyx, extra.gyy)))
        return Gradients(None, None, None, None, self.n_functions, extra, dx, dy)


def _narrow(op: csr_array) -> csr_array:
    """``op`` with int32 indices and index pointers when its size allows (half their memory)."""
    if op.nnz >= 2**31 or op.shape[1] >= 2**31:
        return op
    return csr_array((op.data, op.indices.astype(np.int32, copy=False),
                      op.indptr.astype(np.int32, copy=False)), shape=op.shape)


@dataclass(frozen=True, eq=False)
class Gradients(Shape):
    """Shape-function derivatives at points, kept compact for post-processing
    (:meth:`Shape.gradients_only`): :meth:`gradient` and :meth:`strain` work as on the
    :class:`Shape` they come from (the same operators); the values (:attr:`phi`,
    :meth:`displacement`) and the padded arrays (``neighbours``, ``values``, ``ddx``,
    ``ddy``, all None here) are not kept.

    Attributes
    ----------
    dx_op, dy_op : csr_array (n_points, n_functions)
        d phi_I / dx, d phi_I / dy.
    """

    dx_op: csr_array | None = None
    dy_op: csr_array | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return self.dx_op.shape

    @property
    def dx(self) -> csr_array:
        return self.dx_op

    @property
    def dy(self) -> csr_array:
        return self.dy_op
