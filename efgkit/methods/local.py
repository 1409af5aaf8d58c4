"""MLPG1 sub-domains: scene + MLPG -> discs, test functions, local boundary pieces, K and f.

Seed 002 Eqs. (20)-(24): for every node I, on the part Omega_s^I of its disc of radius r_sI
inside the body and visible from x_I, with the test function v_I (quartic spline, Eq. 8)
vanishing on the circle L_s,

    K_IJ = int_{Omega_s^I} eps(v_I)^T D eps(phi_J) dOmega - int_{Gamma_su^I} v_I N D B_J dGamma
           (+ alpha int_{Gamma_su^I} v_I phi_J dGamma,  bc="penalty", x_I on Gamma_u)
    f_I  = int_{Gamma_st^I} v_I tbar dGamma + int_{Omega_s^I} v_I b dOmega
           (+ alpha int_{Gamma_su^I} v_I ubar dGamma,   bc="penalty", x_I on Gamma_u)

per displacement component: Gamma_su is where that component is prescribed, Gamma_st the
rest of the body boundary inside the disc (traction tbar, 0 where none is given; crack
faces carry their pressure). With the exact solution every row vanishes identically for
any alpha, so the penalty form is consistent (unlike EFG's global penalty). The penalty
term sits in the rows of the nodes on Gamma_u only: in the row of a node off Gamma_u whose
disc reaches it, alpha int v_I (u - ubar) over the rim of the disc (v_I ~ 1e-3) competed
with the disc's equilibrium and, for large alpha, repeated the condition of the boundary
node beside it, leaving the node's equilibrium unenforced (nearly dependent rows; issue 14,
docs/theory.md "MLPG1": the penalised rows of interior nodes made the error erratic in h).

Enrichment unknowns (extrinsic MLS, PU) have no node and no disc: their equations are the
Galerkin rows of the global weak form tested with the enrichment functions E_e over the
field quadrature, int_Omega eps(E_e)^T D eps(u) - int_Gamma_u E_e . t(u) (+ alpha
int_Gamma_u E_e . (u - ubar)) = int_Gamma_t E_e . tbar + int_Omega E_e . b
(docs/theory.md, "MLPG1").
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np
from scipy.sparse import coo_array, csr_array, diags_array, hstack, vstack

from ..approx.shape import Shape
from ..approx.test_functions import disc_test_functions
from ..nodes import check_memory
from ..problem.crack import FACE_OFFSET
from ..problem.scene import Scene, evaluate_component, evaluate_vector
from ..quadrature.boundary import boundary_points
from ..quadrature.cells import cell_points
from ..quadrature.discs import boundary_pieces, disc_points, edge_segments, sectors, visible
from ..quadrature.rules import Points
from ..quadrature.shadows import shadow_pieces
from ..system.assemble import stiffness
from .boundary import crack_face_loads
from .discretize import (
    Discretization,
    approximation,
    crack_mouths,
    essential_nodes,
    interpolating_supports,
    shadow_rays,
)
from .local_nodes import local_nodes
from .local_size import local_size_estimate
from .local_tips import tip_disc_rule
from .mlpg import MLPG

__all__ = ["LocalBoundary", "discretize_local", "local_loads", "local_system", "DEFAULT_MLPG_PENALTY"]

DEFAULT_MLPG_PENALTY = 1e3  # alpha h / E of the penalty term in the local weak form


@dataclass(frozen=True, eq=False)
class LocalBoundary:
    """The body boundary inside the sub-domains: Gauss points of every piece (``points``:
    x, w, owner node, outward normal), the test and trial functions there, which
    components are prescribed (``fixed (m, 2)``, ``value (m, 2)``) and the traction
    ``(m, 2)`` elsewhere; ``radii (n_nodes,)`` are the test radii r_sI; ``penalised (m,)``
    whether the point's owner lies on Gamma_u (its disc carries the penalty term)."""

    points: Points
    test: Shape
    trial: Shape
    fixed: np.ndarray
    value: np.ndarray
    traction: np.ndarray
    radii: np.ndarray
    edge: np.ndarray | None = None  # (m,) index of each point's edge in scene.domain.edges()
    shadow: tuple | None = None
    penalised: np.ndarray | None = None  # (m,) bool; None: every point (former behaviour)

    def penalty_mask(self, comp: int) -> np.ndarray:
        """(m,) float: 1 where component ``comp`` is prescribed and the owner is on Gamma_u."""
        fix = self.fixed[:, comp]
        return (fix if self.penalised is None else fix & self.penalised).astype(float)


def disc_radii(nodes, method: MLPG) -> np.ndarray:
    """r_sI = test_radius c_I with c_I = d_mI / d_max (the spacing on a regular grid), (n,)."""
    return method.test_radius * nodes.radius / method.d_max




def _segments(scene: Scene):
    """Boundary segments (split at crack mouths) with their edges, and the crack segments."""
    edges = scene.domain.edges()
    bseg, bedge, bs = edge_segments(edges, crack_mouths(scene))
    cseg = (np.concatenate([c.segments for c in scene.cracks]) if scene.cracks
            else np.zeros((0, 2, 2)))
    return edges, bseg, bedge, bs, cseg


def _face_sides(nodes, cseg) -> np.ndarray:
    """For nodes split on a crack, a vector into their face's material; 0 elsewhere, (n, 2)."""
    side = np.zeros((nodes.n, 2))
    if nodes.face is None or not np.any(nodes.face):
        return side
    k = np.flatnonzero(nodes.face != 0)
    e = cseg[nodes.face_segment[k], 1] - cseg[nodes.face_segment[k], 0]
    side[k] = nodes.face[k, None] * np.column_stack([-e[:, 1], e[:, 0]])
    return side


def discretize_local(scene: Scene, method: MLPG) -> Discretization:
    """Nodes, disc quadrature, trial and test functions and local boundary pieces.

    Examples
    --------
    >>> from efgkit import Domain, Elastic, Scene, Support
    >>> scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3),
    ...               supports=(Support("left", ux=0.0, uy=0.0),))
    >>> d = discretize_local(scene, MLPG(spacing=0.25, quadrature="midpoint"))  # seed 002's 5 x 8
    >>> d.nodes.n, d.points.n, int(d.test.neighbours.idx.shape[1])   # 25 discs of 40 points
    (25, 1000, 1)

    Raises
    ------
    ValueError
        Before allocating anything, when the discretisation and its solve would need more
        memory than the machine has (:func:`~efgkit.methods.local_size.local_size_estimate`,
        :func:`~efgkit.nodes.check_memory`), and for a linear basis on a cracked scene.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(method, MLPG):
        raise TypeError(f"method must be an MLPG description, got {type(method).__name__}")
    method = method.for_scene(scene)
    if scene.cracks and method.basis == "linear":
        raise ValueError(
            f"MLPG with basis='linear' on a cracked scene ({scene.name!r}) gives wrong stress "
            "intensity factors (issue 14): K_I 1012 against 1259 on the SENT of seed 001 "
            "(spacing 0.5), and K_I from -133 to 30 against 34.0 with K_II of either sign on "
            "the shear edge crack of seed 003 (spacings 0.3-0.5), with or without enrichment; "
            "the linear basis is also ~25 % too stiff in bending (docs/theory.md, MLPG1). Use "
            "basis='quadratic' with d_max >= 3, or the EFG method")
    est = local_size_estimate(scene, method)
    check_memory(est.bytes, f"MLPG with {max(est.point_parts, key=est.point_parts.get)} would give "
                 f"about {est.nodes:.2g} nodes and {est.points:.2g} quadrature points (test discs, "
                 f"boundary pieces, field cells) with up to {est.width} neighbours each; it needs "
                 f"{est.shape_bytes / 1e9:.3g} GB for the shape functions and "
                 f"{est.solve_bytes / 1e9:.3g} GB for the stiffness and the solve",
                 "Remedy: a discretisation about {factor:.2g} times coarser (spacing, zone "
                 "spacings) would fit; refine only near tips (zones), or lower d_max, radial, "
                 "angular or cut_angular.")
    timings = {}
    t0 = time.perf_counter()
    nodes = local_nodes(scene.domain, method, scene.cracks)
    r_s = disc_radii(nodes, method)
    interpolate = None
    if method.bc == "modified_mls":
        interpolate = essential_nodes(scene, nodes, method.spacing)
        nodes = interpolating_supports(nodes, interpolate)
    timings["nodes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    edges, bseg, bedge, bs, cseg = _segments(scene)
    allseg = np.concatenate([bseg, cseg])
    side = _face_sides(nodes, cseg)
    theta_a, span = sectors(nodes.x, r_s, allseg, scene.domain.contains, side)
    points = disc_points(nodes.x, r_s, allseg, theta_a, span, method.quadrature, method.radial,
                         method.angular, piece_angular=method.cut_angular)
    points = tip_disc_rule(points, scene, method, nodes, r_s, allseg, theta_a, span)
    bpts, edge_of = boundary_pieces(nodes.x, r_s, bseg, bedge, bs, edges, method.boundary_order,
                                    blockers=cseg)
    own_side = side[bpts.owner]
    keep = np.einsum("nd,nd->n", own_side, bpts.x - nodes.x[bpts.owner]) >= 0
    bpts = Points(bpts.x[keep], bpts.w[keep], bpts.owner[keep], bpts.normal[keep])
    edge_of = edge_of[keep]
    cells = cell_points(scene.domain, method.cell_size or method.spacing, method.order,
                        zones=method.zones + method.tip_cell_zones(scene),
                        refined_order=method.refined_order, cracks=scene.cracks,
                        tip_rays=shadow_rays(scene, nodes), tip_order=method.tip_order)
    timings["quadrature"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    approx = approximation(scene, method, nodes, interpolate)
    timings["search"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    shape = approx.shape(points.x)
    test = disc_test_functions(points.x, points.owner, nodes.x, r_s)
    local = _local_boundary(scene, approx, nodes, r_s, bpts, edge_of, edges)
    local = replace(local, penalised=essential_nodes(scene, nodes, method.spacing)[bpts.owner])
    sh = shadow_pieces(scene, nodes, r_s, cseg, method.boundary_order)
    if sh.n:
        local = replace(local, shadow=(
            sh, disc_test_functions(sh.x, sh.owner, nodes.x, r_s, derivatives=False), approx.shape(sh.x)))
    timings["shape"] = time.perf_counter() - t0
    return Discretization(scene, method, nodes, points, shape, approx, timings, test=test,
                          field_points=cells, local=local)


def _local_boundary(scene, approx, nodes, r_s, bpts, edge_of, edges) -> LocalBoundary:
    """Prescribed components and tractions at the boundary pieces of the sub-domains."""
    x, mat = bpts.x, scene.material
    fixed, value = np.zeros((bpts.n, 2), bool), np.zeros((bpts.n, 2))
    names = np.array([e.name for e in edges])
    for sup in scene.supports:
        sel = names[edge_of] == sup.edge if isinstance(sup.edge, str) else np.asarray(sup.edge(x), bool)
        for c, v in enumerate((sup.ux, sup.uy)):
            if v is not None and sel.any():
                new = sel & ~fixed[:, c]  # a point on two supports: the first wins
                value[new, c] = evaluate_component(v, x[new], c, mat)
                fixed[new, c] = True
    traction = _tractions(scene, bpts, edge_of, names, fixed)
    test = disc_test_functions(x, bpts.owner, nodes.x, r_s, derivatives=False)
    return LocalBoundary(bpts, test, approx.shape(x), fixed, value, traction, r_s, edge_of)


def _tractions(scene, bpts, edge_of, names, fixed) -> np.ndarray:
    """The traction tbar (m, 2) of ``scene.tractions`` at the boundary pieces, 0 where the
    component is prescribed."""
    x, traction = bpts.x, np.zeros((bpts.n, 2))
    for tr in scene.tractions:
        sel = names[edge_of] == tr.edge if isinstance(tr.edge, str) else np.asarray(tr.edge(x), bool)
        if sel.any():
            traction[sel] += evaluate_vector(tr.t, x[sel], bpts.normal[sel], scene.material)
    return np.where(fixed, 0.0, traction)


def local_loads(disc: Discretization, alpha: float | None, scene: Scene | None = None) -> np.ndarray:
    """The nodal rows of the MLPG1 load vector, shape (2 n_nodes,) (module docstring):
    ``int_{Gamma_st^I} v_I tbar + int_{Omega_s^I} v_I b`` (+ the crack-face pressure, + the
    penalty term ``alpha int_{Gamma_su^I} v_I ubar`` when ``alpha`` is given) with the loads
    of ``scene`` (default ``disc.scene``; another scene on the same domain, supports and
    cracks, e.g. one load history of a dynamic scene) on ``disc``'s sub-domains."""
    scene = disc.scene if scene is None else scene
    mat, loc = scene.material, disc.local
    n2 = 2 * disc.nodes.n
    f = np.zeros(n2)
    traction = loc.traction
    if scene is not disc.scene:
        names = np.array([e.name for e in scene.domain.edges()])
        traction = _tractions(scene, loc.points, loc.edge, names, loc.fixed)
    for c in range(2):
        if alpha is not None:
            f += _rows(loc.test, loc.points.w, c, n2, loc.penalty_mask(c)) @ (
                alpha * loc.value[:, c])
        f += _rows(loc.test, loc.points.w, c, n2) @ traction[:, c]
    if scene.body_force is not None:
        b = evaluate_vector(scene.body_force, disc.points.x, np.zeros_like(disc.points.x), mat)
        for c in range(2):
            f += _rows(disc.test, disc.points.w, c, n2) @ b[:, c]
    return f + _face_pressure(disc, scene)


def _rows(test: Shape, w: np.ndarray, comp: int, n_rows: int, scale=None) -> csr_array:
    """Sparse (n_rows, n_points): entry (2 owner + comp, q) = w_q v_q (times ``scale (n,)``)."""
    owner = test.neighbours.idx[:, 0]
    val = w * test.values[:, 0] * (1.0 if scale is None else scale)
    return csr_array(coo_array((val, (2 * owner + comp, np.arange(len(w)))),
                               shape=(n_rows, len(w))))


def _traction_ops(shape: Shape, normal: np.ndarray, D: np.ndarray):
    """(Tx, Ty) csr (m, n_dofs): the traction sigma(u) n of the coefficients at the points."""
    gxx, gxy, gyx, gyy = shape.grad_operators()
    eps = (gxx, gyy, csr_array(gxy + gyx))
    sig = [csr_array(sum(D[i, j] * eps[j] for j in range(3) if D[i, j] != 0)) for i in range(3)]
    nx, ny = diags_array(normal[:, 0]), diags_array(normal[:, 1])
    return csr_array(nx @ sig[0] + ny @ sig[2]), csr_array(nx @ sig[2] + ny @ sig[1])


def local_system(disc: Discretization, alpha: float | None) -> tuple[csr_array, np.ndarray]:
    """K (n_dofs, n_dofs) and f (n_dofs,) of MLPG1 (module docstring); ``alpha`` the
    penalty factor (force / length^3), None for no penalty term (modified MLS,
    collocation: their essential rows are replaced afterwards)."""
    D = disc.scene.material.D
    n2 = 2 * disc.nodes.n
    nd = disc.n_dofs
    K = stiffness(disc.shape, disc.points.w, D, test=disc.test)  # (2 n, n_dofs)
    f = np.zeros(nd)
    loc = disc.local
    bp = loc.points
    U = loc.trial.u_operators()
    T = _traction_ops(loc.trial, bp.normal, D)
    for c in range(2):
        # Gamma_su: -int v t_c(u) in every disc reaching it; + alpha int v (u_c - ubar_c) in
        # the discs of the nodes on Gamma_u (LocalBoundary.penalised); Gamma_st: int v tbar_c
        Rs = _rows(loc.test, bp.w, c, n2, loc.fixed[:, c].astype(float))
        K = K + _pad(Rs @ (-T[c]), nd)
        if alpha is not None:
            K = K + _pad(_rows(loc.test, bp.w, c, n2, loc.penalty_mask(c)) @ (alpha * U[c]), nd)
    if loc.shadow is not None:  # -int v_I t(u) on the shadow rays (shadow_pieces)
        sp, sv, su = loc.shadow
        Ts = _traction_ops(su, sp.normal, D)
        for c in range(2):
            K = K + _pad(_rows(sv, sp.w, c, n2) @ (-Ts[c]), nd)
    f[:n2] = local_loads(disc, alpha)
    K = csr_array(K)
    if nd > n2:
        Ke, fe = _enrichment_rows(disc, alpha)
        K = csr_array(vstack([K, Ke], format="csr"))
        f[n2:] = fe
    return K, f


def _pad(A, n_cols) -> csr_array:
    A = csr_array(A)
    return A if A.shape[1] == n_cols else csr_array(hstack(
        [A, csr_array((A.shape[0], n_cols - A.shape[1]))], format="csr"))


def _face_pressure(disc: Discretization, scene: Scene) -> np.ndarray:
    """int_{crack faces in Omega_s^I} v_I p n dGamma: pressurised crack faces are loaded
    parts of the sub-domain boundaries (the Gauss rules of
    :func:`~efgkit.methods.boundary.crack_face_loads`, tested by every disc holding a point
    on its own side)."""
    from scipy.spatial import cKDTree

    n2 = 2 * disc.nodes.n
    f = np.zeros(n2)
    m = disc.method
    r_s = disc.local.radii
    tree = cKDTree(disc.nodes.x)
    side = _face_sides(disc.nodes, _segments(disc.scene)[4])
    for crack in scene.cracks:
        if crack.pressure == 0.0:
            continue
        for x, w, t in crack_face_loads(crack, m.spacing, max(m.order, 2)):
            near = tree.query_ball_point(x, r_s.max())
            q = np.repeat(np.arange(len(x)), [len(v) for v in near])
            node = np.concatenate([np.asarray(v, int) for v in near]) if len(q) else np.zeros(0, int)
            d = np.hypot(*(x[q] - disc.nodes.x[node]).T)
            ok = d < r_s[node]
            ok &= _same_side(disc, x[q], node, FACE_OFFSET * m.spacing)
            # a node split on a crack tests only its own face (it sees the other one along
            # the crack line): else the two faces' pressures cancel on it
            ok &= np.einsum("nd,nd->n", side[node], x[q] - disc.nodes.x[node]) >= 0
            q, node = q[ok], node[ok]
            v = disc_test_functions(x[q], node, disc.nodes.x, r_s, derivatives=False).values[:, 0]
            for c in range(2):
                f[c::2] += np.bincount(node, w[q] * v * t[q, c], minlength=disc.nodes.n)
    return f


def _same_side(disc, x, node, tol) -> np.ndarray:
    """Whether face points ``x (p, 2)`` are visible from their nodes (no crack between)."""
    cseg = np.concatenate([c.segments for c in disc.scene.cracks])
    return visible(disc.nodes.x[node], x, cseg, tol * 1e-3)


def _enrichment_rows(disc: Discretization, alpha: float | None):
    """Galerkin rows of the enrichment unknowns over the field quadrature (module docstring):
    Ke (n_extra, n_dofs), fe (n_extra,)."""
    scene, mat = disc.scene, disc.scene.material
    D = mat.D
    sh = disc.post_shape
    w = disc.post_points.w
    e = sh.extra
    eps_e = (e.gxx, e.gyy, csr_array(e.gxy + e.gyx))
    gxx, gxy, gyx, gyy = sh.grad_operators()
    eps = (gxx, gyy, csr_array(gxy + gyx))
    W = diags_array(w)
    Ke = None
    for i in range(3):
        sig_i = csr_array(sum(D[i, j] * eps[j] for j in range(3) if D[i, j] != 0))
        term = csr_array(eps_e[i].T @ W @ sig_i)
        Ke = term if Ke is None else Ke + term
    fe = np.zeros(e.n)
    if scene.body_force is not None:
        b = evaluate_vector(scene.body_force, disc.post_points.x, np.zeros_like(disc.post_points.x), mat)
        fe += e.ux.T @ (w * b[:, 0]) + e.uy.T @ (w * b[:, 1])
    m = disc.method
    order = max(m.order, 2)
    mouths = crack_mouths(scene)
    for tr in scene.tractions:
        pts = boundary_points(scene.domain, tr.edge, order, m.spacing, mouths)
        t = evaluate_vector(tr.t, pts.x, pts.normal, mat)
        ex = disc.shape_at(pts.x, derivatives=False).extra
        fe += ex.ux.T @ (pts.w * t[:, 0]) + ex.uy.T @ (pts.w * t[:, 1])
    for sup in scene.supports:
        pts = boundary_points(scene.domain, sup.edge, order, m.spacing, mouths)
        sh_b = disc.shape_at(pts.x)
        U = sh_b.u_operators()
        T = _traction_ops(sh_b, pts.normal, D)
        ex = sh_b.extra
        for c, v in enumerate((sup.ux, sup.uy)):
            if v is None:
                continue
            E = (ex.ux, ex.uy)[c]
            Wb = diags_array(pts.w)
            Ke = Ke - csr_array(E.T @ Wb @ T[c])
            if alpha is not None:
                ub = evaluate_component(v, pts.x, c, mat)
                Ke = Ke + alpha * csr_array(E.T @ Wb @ U[c])
                fe += alpha * (E.T @ (pts.w * ub))
    return csr_array(Ke), fe
