"""Image nodes of half and quarter models: the part's MLS coefficients tied to their mirror images.

A symmetric body under a symmetric (mode-I) load has a symmetric solution, ``u(x') = R u(x)``
at ``x' = p + R (x - p)`` for each mirror line (:func:`efgkit.problem.symmetry.reflection`,
``R = I - 2 n n^T``). The EFG approximation of a half or quarter model is the full model's
restricted to such fields: its nodes are the part's nodes and their images under the mirror
group ``G`` (one line: ``{e, g_1}``; two perpendicular lines: ``{e, g_1, g_2, g_1 g_2}``), the
MLS functions those of the whole body (supports crossing the lines, crack rules with the whole
crack), and the coefficients are tied by ``a_{g(I)} = R_g a_I``. With ``j_g(I)`` the node of
the mirrored cloud that ``g`` maps part node ``I`` to (on a crack on the line: the copy of the
split node on the face ``g`` maps to) and ``S_I = {g : j_g(I) = j_e(I)}`` its stabiliser, the
part's coefficients ``b_I`` give ``a = T b`` with the 2 x 2 blocks

    T_{j_g(I), I} = R_g P_I,    P_I = (1 / |S_I|) sum_{g in S_I} R_g,

``P_I`` the projector on the fixed space of ``S_I`` (a node on a line keeps its tangential
coefficient only). With mirror normals along the axes every ``P_I`` is diagonal with entries 0
or 1; the components with 0 are no unknowns. The part's system is ``T^T A T`` over the part's
quadrature (the full model's restricted to the part, weights on a line halved), whose energy is
half the full model's for every tied field: the Galerkin solution is the full model's on the
mirrored cloud. The symmetry condition u_n = 0 on the lines holds identically and is imposed by
no constraint (docs/theory.md, "Image nodes"). The extrinsic enrichment unknowns (extrinsic
MLS, PU) are tied likewise (:func:`extra_action`): mode I kept, mode II eliminated on a line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import block_diag, coo_array, csr_array, identity
from scipy.spatial import cKDTree

from ..problem.symmetry import reflection
from .constraints import RigidBodyModeError
from .linear_system import LinearSystem

__all__ = ["BRANCH_PARITY", "ImageTie", "TiedSystem", "extra_action", "image_group", "image_positions",
           "part_weights", "tie"]


def image_group(lines) -> tuple[np.ndarray, np.ndarray]:
    """The mirror group of ``lines`` as affine maps ``x' = R_s x + c_s``: ``R (m, 2, 2)``,
    ``c (m, 2)``, ``m = 2^len(lines)``; element ``s`` applies the reflections in the bits of
    ``s`` (perpendicular reflections commute, so the group product is ``s xor t``)."""
    refl = [reflection(p, n) for p, n in lines]
    m = 2 ** len(refl)
    R, c = np.tile(np.eye(2), (m, 1, 1)), np.zeros((m, 2))
    for s in range(m):  # tiny fixed size: 2 or 4 elements
        for bit, (p, Rl) in enumerate(refl):
            if s >> bit & 1:
                R[s], c[s] = Rl @ R[s], Rl @ c[s] + p - Rl @ p
    return R, c


def image_positions(x: np.ndarray, lines, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The part's nodes ``x (n, 2)`` and their distinct images, ``(y (m, 2), U (n_g, n))``:
    ``y[U[s, I]]`` is element ``s`` of :func:`image_group` applied to node ``I``; images within
    ``tol`` of a node already listed (nodes on a line) are that node. ``y`` starts with ``x``
    and lists new images in group order (the order of the mirror-union clouds of
    ``verification/symmetry.py``).

    Examples
    --------
    >>> y, U = image_positions(np.array([[1.0, 0.0], [1.0, 1.0]]), (((0.0, 0.0), (0.0, 1.0)),), 1e-9)
    >>> y.tolist(), U.tolist()   # the node on the line y = 0 is its own image
    ([[1.0, 0.0], [1.0, 1.0], [1.0, -1.0]], [[0, 1], [0, 2]])
    """
    R, c = image_group(lines)
    y, U = x, np.zeros((len(R), len(x)), dtype=np.int64)
    U[0] = np.arange(len(x))
    for s in range(1, len(R)):
        z = x @ R[s].T + c[s]
        d, k = cKDTree(y).query(z)
        new = d > tol
        U[s] = np.where(new, len(y) + np.cumsum(new) - 1, k)
        y = np.vstack([y, z[new]])
    return y, U


def part_weights(x: np.ndarray, lines, sides: np.ndarray, tol: float) -> np.ndarray:
    """Factor of each point ``x (n, 2)`` of a mirror-symmetric quadrature of the whole body in
    the part's: 0 outside the part, 1/2 per line the point lies on (within ``tol``), 1 inside.
    ``sides (n_lines,)``: +1 or -1, the side of each line ``(x - p) . n`` the part lies on."""
    f = np.ones(len(x))
    for (p, n), sd in zip(lines, sides, strict=True):
        n = np.asarray(n) / np.hypot(*n)
        d = sd * ((x - p) @ n)
        f *= np.where(d > tol, 1.0, np.where(d >= -tol, 0.5, 0.0))
    return f


@dataclass(frozen=True, eq=False)
class ImageTie:
    """The tie ``a = T b`` of the mirrored cloud's coefficients ``a`` to the part's ``b``.

    Attributes
    ----------
    T : csr_array (2 n_full + n_extra, n_free + n_extra_free)
        Columns: the part's nodal unknowns that are not fixed by symmetry (``free``), then
        one per orbit of enrichment unknowns that symmetry does not eliminate.
    free : (n_free,) int
        The part coefficients ``2 I + c`` the columns stand for.
    n_part : int
        Nodes of the part (the first ``n_part`` nodes of the mirrored cloud, ``a`` order).
    translations : (k, 2)
        Unit rigid translations along every line (k = 1 for a half model, 0 for a quarter):
        the rigid motions of the tied space the supports must hold.
    """

    T: csr_array
    free: np.ndarray
    n_part: int
    translations: np.ndarray

    def reduce(self, system: LinearSystem) -> LinearSystem:
        """The system over the part's free unknowns (and the multipliers, if any):
        ``Tb^T A Tb``, ``Tb^T b`` with ``Tb = diag(T, I)``; its :meth:`coefficients
        <LinearSystem.coefficients>` are the mirrored cloud's.

        Raises
        ------
        RigidBodyModeError
            When the supports leave a symmetric rigid translation (along a half model's line) free.
        ValueError
            For a system that eliminates coefficients (bc="modified_mls" or "collocation").
        """
        if system.free is not None or system.n_coeffs != self.T.shape[0]:
            raise ValueError("image nodes tie the coefficients of bc='penalty', 'lagrange' or "
                             "'variational' systems; use one of those for a half or quarter model")
        n_mult = system.size - system.n_coeffs
        Tb = csr_array(block_diag([self.T, identity(n_mult)], format="csr")) if n_mult else self.T
        A = csr_array(Tb.T @ system.A @ Tb)
        self._check_modes(A)
        forces = system.support_forces
        return TiedSystem(A, Tb.T @ system.b, system.spd, self.T.shape[1],
                          support_forces=None if forces is None else (lambda z: forces(Tb @ z)),
                          tie=self.T)

    def part_modes(self, modes: np.ndarray) -> np.ndarray:
        """Rows of the part's nodal ``modes (>= 2 n_part, k)`` at the free unknowns (and 0 at
        the enrichment unknowns), shape (n_free + n_extra_free, k)."""
        out = np.zeros((self.T.shape[1], modes.shape[1]))
        out[: len(self.free)] = modes[self.free]
        return out

    def _check_modes(self, A: csr_array) -> None:
        scale = abs(A).max()
        for t in self.translations:
            z = np.zeros(A.shape[0])
            z[: len(self.free)] = t[self.free % 2]
            if np.abs(A @ z).max() <= 1e-9 * scale:
                raise RigidBodyModeError(
                    f"the essential boundary conditions of this half model leave the rigid "
                    f"translation along its symmetry line, direction {t.round(12).tolist()}, free; "
                    "prescribe that component somewhere (e.g. a PointSupport)")


@dataclass(frozen=True, eq=False)
class TiedSystem(LinearSystem):
    """A :class:`LinearSystem` over the part's free unknowns whose coefficients are those of
    the mirrored cloud, ``a = T z[:n_free]``."""

    tie: csr_array | None = None

    def coefficients(self, z: np.ndarray) -> np.ndarray:
        return self.tie @ z[: self.n_coeffs]


def tie(lines, U: np.ndarray, origin: np.ndarray, side: np.ndarray, sides: np.ndarray,
        enrichment=None, tol: float = 0.0) -> ImageTie:
    """The :class:`ImageTie` of a mirrored cloud.

    Parameters
    ----------
    lines : the mirror lines ((x0, y0), (nx, ny)), normals along the axes
    U : (n_g, n_part) int
        :func:`image_positions`: the unsplit position of every image of every part node.
    origin : (n_full,) int
        Unsplit position of every node of the mirrored cloud (split crack nodes: two nodes,
        one per face, share one position; the cloud lists the positions first, in order).
    side : (n_full, 2)
        Of a split node, a vector pointing into the face it belongs to; 0 for the others.
    sides : (n_lines,)
        The side (+1 or -1) of each line the part lies on.
    enrichment : Enrichment, optional
        Extrinsic enrichment of the mirrored cloud (:func:`extra_action`); its unknowns are
        tied like the nodal ones, one representative per orbit (the lowest index).
    tol : float
        Distance below which two tips coincide.
    """
    normals = np.array([np.asarray(n) / np.hypot(*n) for _, n in lines])
    if not np.all(np.isclose(np.abs(normals), 0.0, atol=1e-12) | np.isclose(np.abs(normals), 1.0)):
        raise ValueError(f"EFG half and quarter models need mirror lines along the axes (normals "
                         f"(1, 0) or (0, 1)), got normals {normals.tolist()}; rotate the model")
    R, _ = image_group(lines)
    n_g, n_part = U.shape
    n_full, n_pos = len(origin), U.max() + 1
    second = np.full(n_pos, -1)  # the face copy of a split position, appended after the positions
    second[origin[n_pos:]] = np.arange(n_pos, n_full)
    # every position as (group element, part node): the element that maps the part node there
    rep_s, rep_i = np.zeros(n_pos, np.int64), np.zeros(n_pos, np.int64)
    for s in range(n_g - 1, -1, -1):  # tiny fixed size
        rep_s[U[s]], rep_i[U[s]] = s, np.arange(n_part)

    def act(s, j):  # node g_s(node j) of the mirrored cloud
        o = U[s ^ rep_s[origin[j]], rep_i[origin[j]]]
        v = side[j] @ R[s].T
        other = (second[o] >= 0) & (np.einsum("nd,nd->n", side[o], v) < 0)
        return np.where(other, second[o], o)

    part = np.arange(n_part)
    inward = side[part] @ (normals.T * sides).sum(axis=1) if len(lines) else np.zeros(n_part)
    j0 = np.where((second[part] >= 0) & (inward < 0), second[part], part)  # the part's own face
    J = np.array([act(s, j0) for s in range(n_g)])  # (n_g, n_part)
    stab = J == j0[None]
    P = np.einsum("si,sab->iab", stab.astype(float), R) / stab.sum(axis=0)[:, None, None]
    diag = np.stack([P[:, 0, 0], P[:, 1, 1]], axis=1)  # diagonal (axes-aligned mirrors)
    first = np.ones_like(stab)
    for s in range(1, n_g):
        first[s] = ~np.any(J[:s] == J[s][None], axis=0)
    if len(np.unique(J[first])) != n_full:
        raise RuntimeError("image nodes: the mirrored cloud is not the orbit of the part's nodes")
    s_idx, i_idx = np.nonzero(first)
    rows, cols, vals = [], [], []
    for c in (0, 1):
        keep = diag[i_idx, c] != 0
        rows.append(2 * J[s_idx, i_idx][keep] + c)
        cols.append(2 * i_idx[keep] + c)
        vals.append(R[s_idx[keep], c, c] * diag[i_idx[keep], c])
    rows, cols, vals = map(np.concatenate, (rows, cols, vals))
    free = np.flatnonzero(np.column_stack([diag[:, 0] != 0, diag[:, 1] != 0]).ravel())
    col_of = np.full(2 * n_part, -1)
    col_of[free] = np.arange(len(free))
    rows, cols = [rows], [col_of[cols]]
    vals, n_cols, n_extra = [vals], len(free), 0
    if enrichment is not None and enrichment.n_extra:
        n_extra = enrichment.n_extra
        emap, esign = extra_action(enrichment, np.array([act(s, np.arange(n_full)) for s in range(n_g)]),
                                   lines, tol)
        rep = np.flatnonzero(emap.min(axis=0) == np.arange(n_extra))  # one per orbit
        E, S = emap[:, rep], esign[:, rep]
        stab = E == rep[None]
        p = (S * stab).sum(axis=0) / stab.sum(axis=0)  # 1 (kept) or 0 (odd under its stabiliser)
        keep = np.flatnonzero(np.abs(p) > 0.5)
        ef = np.ones_like(E, dtype=bool)
        for s in range(1, n_g):
            ef[s] = ~np.any(E[:s] == E[s][None], axis=0)
        si, k = np.nonzero(ef[:, keep])
        rows.append(2 * n_full + E[si, keep[k]])
        cols.append(n_cols + k)
        vals.append(S[si, keep[k]] * p[keep[k]])
        n_cols += len(keep)
    T = coo_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                  shape=(2 * n_full + n_extra, n_cols)).tocsr()
    trans = np.eye(2)[np.all(np.abs(normals @ np.eye(2)) < 1e-12, axis=0)]
    return ImageTie(T, free, n_part, trans)


BRANCH_PARITY = np.array([1.0, -1.0, 1.0, -1.0])  # the "full" branch functions under theta -> -theta


def extra_action(enrichment, node_act: np.ndarray, lines, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """How the mirror group acts on the extrinsic enrichment unknowns of a mirrored cloud:
    ``(map, sign)``, each (n_g, n_extra): element ``s`` maps unknown ``e``'s field ``v_e`` to
    ``R_s v_e(g_s^{-1} x) = sign[s, e] v_{map[s, e]}(x)``.

    A reflection maps a tip to a tip (``tol``) and its local angle ``theta`` to ``-theta``, so the
    Williams fields (extrinsic MLS, unknowns ``2 t + mode``) keep mode I (+1) and reverse mode II
    (-1), and the PU unknowns ``8 j + 2 i + c`` (enriched node ``j``, branch function ``i``,
    component ``c``) go to node ``node_act[s, j]`` with the parity of ``F_i``
    (:data:`BRANCH_PARITY`) times ``R_s[c, c]`` (parities to the power of the number of
    reflections in ``s``).

    Raises
    ------
    ValueError
        When the enrichment is not mirror-symmetric (a PU node enriched by a tip whose image
        node is enriched by another tip, e.g. a node halfway between two tips).
    """
    R, c = image_group(lines)
    n_g = len(R)
    odd = np.array([bin(s).count("1") % 2 for s in range(n_g)])[:, None]  # reflections in s
    tip_x = np.array([g.tip.x for g in enrichment.tips])
    tip_img = np.zeros((n_g, len(tip_x)), np.int64)
    for s in range(n_g):  # tiny fixed size
        d, tip_img[s] = cKDTree(tip_x).query(tip_x @ R[s].T + c[s])
        if np.any(d > tol):
            raise ValueError("the crack tips of the whole body are not mirror images of each other")
    if enrichment.kind == "extrinsic_mls":
        e = np.arange(enrichment.n_extra)
        t, mode = e // 2, e % 2
        return 2 * tip_img[:, t] + mode, np.where(mode[None] == 1, (-1.0) ** odd, 1.0)
    if enrichment.kind != "pu":
        raise ValueError(f"no extrinsic unknowns in enrichment {enrichment.kind!r}")
    e = np.arange(enrichment.n_extra)
    j, i, comp = e // 8, e % 8 // 2, e % 2
    where = np.full(node_act.shape[1], -1)
    where[enrichment.pu_nodes] = np.arange(len(enrichment.pu_nodes))
    jn = where[node_act[:, enrichment.pu_nodes[j]]]
    if np.any(jn < 0) or np.any(enrichment.pu_tip[jn] != tip_img[:, enrichment.pu_tip[j]]):
        raise ValueError(
            "enrichment='pu' is not mirror-symmetric on this cloud: a node and its image are "
            "enriched by tips that are not each other's images (a node about as far from two "
            "tips). Give a smaller enrich_radius, or enrichment='none'")
    return 8 * jn + 2 * i + comp, BRANCH_PARITY[i][None] ** odd * R[:, comp, comp]

