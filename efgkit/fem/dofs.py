"""Degrees of freedom of the finite-element model selected by an edge name or a mask, and the
face on which a crack-face node's fields are evaluated."""

from __future__ import annotations

import numpy as np

from .mesh import TriMesh

__all__ = ["dofs_where", "face_side"]


def dofs_where(where, sol_mesh: TriMesh, fmap, sbasis):
    """Scalar DOFs on the edges called ``where`` or, for a callable mask, the boundary DOFs
    (on domain edges, not crack faces) whose locations it selects; and the facets."""
    if isinstance(where, str):
        fac = fmap[sol_mesh.boundary(where)]
        return np.unique(sbasis.get_dofs(facets=fac).flatten()), fac
    fac = fmap[sol_mesh.facet_owner >= 0]
    dofs = np.unique(sbasis.get_dofs(facets=fac).flatten())
    mask = np.asarray(where(sbasis.doflocs[:, dofs].T))
    if mask.shape != dofs.shape or mask.dtype != bool:
        raise TypeError(f"an edge callable must map x (n, 2) to a bool mask (n,), got "
                        f"{mask.dtype} array of shape {mask.shape}")
    sk = sbasis.mesh
    mid = 0.5 * (sk.p[:, sk.facets[0, fac]] + sk.p[:, sk.facets[1, fac]])
    return dofs[mask], fac[np.asarray(where(mid.T), dtype=bool)]


def face_side(mesh: TriMesh, x, dofs):
    """``x (k, 2)`` of scalar ``dofs (k,)`` with crack-face nodes (a mouth) moved 1e-12 of the
    domain size into their own elements, so that fields discontinuous across the crack
    (a Williams field) are evaluated on the node's face."""
    split = np.concatenate([np.concatenate(p) for p in mesh.crack_nodes] + [np.zeros(0, int)])
    on = np.isin(dofs, split)
    if not on.any():
        return x
    owner = np.empty(mesh.n_nodes, dtype=np.int64)
    owner[mesh.t.ravel()] = np.repeat(np.arange(mesh.n_elements), 3)
    d = mesh.x[mesh.t[owner[dofs[on]]]].mean(axis=1) - x[on]
    x = x.copy()
    x[on] += 1e-12 * mesh.domain.size * d / np.linalg.norm(d, axis=1)[:, None]
    return x
