"""The boundary conditions of a discretised scene: the load vector and the essential data.

``loads`` integrates tractions (on boundary lines), the body force (on the domain
points) and crack-face pressure (on both faces) against the trial functions;
``essential_conditions`` samples the prescribed displacements on Gauss rules along the
supported edges, with the Lagrange-multiplier hats (the input of the constraint
methods of :mod:`efgkit.system.constraints`); ``eliminated_dofs`` gives the
coefficients that the modified MLS of seed 002 fixes by row cross-out;
``collocation_rows`` and ``gamma_u_term`` are the data of the modified collocation
method (Zhu and Atluri 1998, :mod:`efgkit.system.collocation`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import csr_array, vstack

from ..problem.crack import FACE_OFFSET
from ..problem.scene import evaluate_component, evaluate_components, evaluate_vector
from ..quadrature.boundary import boundary_points, break_parameters, edge_rule, merge_knots
from ..quadrature.rules import gauss_legendre
from ..system.assemble import load_vector
from ..system.constraints import Dirichlet, boundary_traction_term
from .discretize import (
    Discretization,
    boundary_segments_for,
    crack_mouths,
    essential_nodes,
    support_edges,
)

__all__ = ["collocation_rows", "crack_face_loads", "eliminated_dofs", "essential_conditions",
           "gamma_u_term", "loads", "point_springs"]


def loads(disc: Discretization) -> np.ndarray:
    """External force vector from tractions and body force, shape (n_dofs,)."""
    scene, m = disc.scene, disc.method
    f = np.zeros(disc.n_dofs)
    order = max(m.order, 2)
    for tr in scene.tractions:
        pts = boundary_points(scene.domain, tr.edge, order, m.spacing, crack_mouths(scene))
        if pts.n == 0:  # a named edge always has points: a callable selected none
            raise ValueError(
                f"traction {tr.edge!r} selects none of the boundary quadrature points, so its "
                "load would be lost: EFG applies tractions as integrals along boundary lines, "
                "and a callable that picks isolated points (a point load) selects nothing. "
                "Select a stretch of boundary and give the traction per unit length there.")
        t = evaluate_vector(tr.t, pts.x, pts.normal, scene.material)
        f += load_vector(disc.shape_at(pts.x, derivatives=False), pts.w, t)
    if scene.body_force is not None:
        b = evaluate_vector(scene.body_force, disc.points.x, np.zeros_like(disc.points.x),
                            scene.material)
        f += load_vector(disc.shape, disc.points.w, b)
    for crack in scene.cracks:
        if crack.pressure != 0.0:
            for x, w, t in crack_face_loads(crack, m.spacing, order):
                f += load_vector(disc.shape_at(x, derivatives=False), w, t)
    return f


def crack_face_loads(crack, h: float, order: int):
    """Gauss rules on the two faces of a pressurised crack: [(x, w, traction)] per face.

    A pressure p > 0 pushes each face into its material: traction ``+p n_left``
    on the left face, ``-p n_left`` on the right. The points sit
    :data:`FACE_OFFSET` spacings off the crack line on their face, so that
    the shape functions are those of that face.
    """
    n = max(1, math.ceil(crack.length / h - 1e-9))
    xi, gw = gauss_legendre(order)
    arc = ((np.arange(n)[:, None] + (xi + 1) / 2) * crack.length / n).ravel()
    w = np.tile(gw / 2 * crack.length / n, n)
    x, left = crack.points_along(arc)
    return [(x + sgn * FACE_OFFSET * h * left, w, sgn * crack.pressure * left) for sgn in (1, -1)]


def essential_conditions(disc: Discretization, derivatives: bool) -> Dirichlet:
    """Prescribed displacements sampled by a Gauss rule on the supported edges.

    Each edge is cut into :func:`boundary_segments_for` equal pieces (and at
    crack mouths), which carry the Gauss points and the Lagrange-multiplier
    hats. Where two constrained edges meet, only the first keeps a hat at the
    corner: two multipliers at one corner over-constrain it (on the singular
    patch of seed 003 Sect. 5.6.1, 9 x 9 nodes, all edges prescribed, the
    energy error was 0.65 against 0.26 for penalty and Nitsche). The second
    edge's end piece takes the linear extrapolation of its neighbour piece's
    multiplier, so linear tractions stay exact.
    """
    scene, m = disc.scene, disc.method
    parts, seg0, hat0 = [], 0, 0
    mouths = crack_mouths(scene)
    corner_comps: dict[tuple, set] = {}  # components constrained at each edge end so far
    tol = 1e-9 * scene.domain.size
    mouth_keys = {tuple(np.round(p / tol).astype(np.int64)) for p in mouths}
    for sup in scene.supports:
        selected = 0
        for e in support_edges(scene.domain, sup.edge):
            # A crack mouth on the edge is a knot where the multiplier may jump (the traction
            # on the two sides of a crack differs): it gets one hat node per side.
            at_mouth = break_parameters(e, mouths)
            hat = merge_knots(np.linspace(0.0, 1.0, boundary_segments_for(e, disc.nodes, m.spacing)
                                          + 1), at_mouth)
            x, w, nrm, s = edge_rule(e, hat, max(m.order, 2))
            keep = np.ones(len(x), bool) if isinstance(sup.edge, str) else np.asarray(
                sup.edge(x), bool)
            selected += int(keep.sum())
            fixed = np.zeros((len(x), 2), bool)
            for c, v in enumerate((sup.ux, sup.uy)):
                if v is not None:
                    fixed[:, c] = keep
            value = evaluate_components(sup.ux, sup.uy, x, scene.material)  # a Field once
            nhat = len(hat) - 1
            seg = np.clip(np.searchsorted(hat, s, side="right") - 1, 0, nhat - 1)
            comps = {c for c, v in enumerate((sup.ux, sup.uy)) if v is not None}
            new_seg = seg.copy()
            spare = nhat - 1  # end pieces that may still borrow a neighbour's multiplier
            for j, end in ((0, e.start), (nhat - 1, e.end)):
                key = tuple(np.round(end / tol).astype(np.int64))
                corner = key not in mouth_keys
                if corner and corner_comps.get(key, set()) & comps and spare > 0:
                    # Another constrained edge already has a multiplier at this corner; two
                    # there over-constrain it (unstable). This edge's end piece takes the
                    # linear extrapolation of its neighbour piece's multiplier instead.
                    new_seg[seg == j] = 1 if j == 0 else nhat - 2
                    spare -= 1
                corner_comps.setdefault(key, set()).update(comps)
            seg = new_seg
            t = (s - hat[seg]) / (hat[seg + 1] - hat[seg])  # outside [0, 1] if extrapolated
            split = np.isin(np.round(hat, 12), np.round(at_mouth, 12))
            left_id = hat0 + np.cumsum(np.concatenate([[0], 1 + split[:-1]]))  # ids of knots
            right_id = left_id + split  # the second node of a split knot serves the next piece
            seg_nodes = np.column_stack([right_id[:-1], left_id[1:]])
            parts.append((x, w, nrm, fixed, value, seg + seg0, t, seg_nodes))
            seg0 += nhat
            hat0 = int(right_id[-1]) + 1
        if callable(sup.edge) and selected == 0:
            raise ValueError(
                f"support {sup.edge!r} selects none of the boundary quadrature points: EFG imposes "
                "supports as integrals along boundary lines, so a callable that picks isolated "
                "points (a single point to pin) selects nothing. Select a stretch of boundary "
                "instead, e.g. the points within one spacing of the point to pin, or a "
                "PointSupport.")
    for p in scene.point_supports:  # collocation at the point: its own multiplier (a hat of
        # one point), a spring beta h (penalty), Nitsche without flux (zero normal)
        parts.append((np.array([p.x]), np.array([m.spacing]), np.zeros((1, 2)), np.array([p.fixed]),
                      np.array([p.values]), np.array([seg0]), np.zeros(1), np.array([[hat0, hat0]])))
        seg0, hat0 = seg0 + 1, hat0 + 1
    if not parts:
        x = np.zeros((0, 2))
        return Dirichlet(x, np.zeros(0), x, disc.shape_at(x, derivatives), np.zeros((0, 2), bool),
                         x, np.zeros(0, int), np.zeros(0), np.zeros((0, 2), int))
    cat = [np.concatenate([p[i] for p in parts]) for i in range(8)]
    x = cat[0]
    return Dirichlet(x, cat[1], cat[2], disc.shape_at(x, derivatives), cat[3], cat[4], cat[5],
                     cat[6], cat[7])


def point_springs(disc: Discretization, beta: float):
    """The point supports as springs of stiffness ``beta`` for :func:`efgkit.system.constraints.
    eliminate` (bc="modified_mls"): ``(P (k, n_dofs), values (k,), beta (k,), x (k, 2), comp (k,))``
    with one row ``u^h_comp(x)`` per prescribed component, or None without point supports."""
    pts = disc.scene.point_supports
    if not pts:
        return None
    x = np.array([p.x for p in pts])
    fixed, vals = np.array([p.fixed for p in pts]), np.array([p.values for p in pts])
    ux, uy = disc.shape_at(x, derivatives=False).u_operators()
    q, c = np.nonzero(fixed)
    rows = [(ux, uy)[ci][[qi]] for qi, ci in zip(q, c, strict=True)]  # k <= 2 per point support
    from scipy.sparse import csr_array, vstack

    return (csr_array(vstack(rows, format="csr")), vals[q, c], np.full(len(q), beta), x[q], c)


def eliminated_dofs(disc: Discretization, x=None):
    """Coefficient indices and values of the modified-MLS essential nodes (row cross-out).

    ``x (n_nodes, 2)``: where to evaluate the prescribed values (default the node positions;
    :func:`collocation_rows` passes the split nodes' face positions, so that the two copies
    of a node at a crack mouth get the values of their own face)."""
    scene = disc.scene
    x = disc.nodes.x if x is None else x
    dofs, vals = [], []
    for sup in scene.supports:
        on = essential_nodes(scene.with_supports((sup,)), disc.nodes, disc.method.spacing)
        idx = np.flatnonzero(on)
        for c, v in enumerate((sup.ux, sup.uy)):
            if v is not None and len(idx):
                dofs.append(2 * idx + c)
                vals.append(evaluate_component(v, x[idx], c, scene.material))
    if not dofs:
        return np.zeros(0, int), np.zeros(0)
    dofs, vals = np.concatenate(dofs), np.concatenate(vals)
    dofs, first = np.unique(dofs, return_index=True)  # a node on two supports: first wins
    return dofs, vals[first]


def collocation_rows(disc: Discretization):
    """Constraint rows of the modified collocation method (Zhu and Atluri 1998).

    For every prescribed component a of every node I on a supported edge (the nodes and
    values of :func:`eliminated_dofs`), the row ``u^h_a(x_I) = sum_J phi_J(x_I) c_Ja``
    of the plain MLS functions. The two copies of a node split by a crack mouth are
    evaluated (shape functions and prescribed values) on their own face, 1e-3 of their
    support radius off the crack (``NodeCloud.face_positions``).

    Returns
    -------
    rows : csr_array (n_c, n_dofs)
    values : (n_c,)
        ``ubar_a(x_I)``.
    dofs : (n_c,) int
        ``2 I + a``: the equations the rows replace (:func:`efgkit.system.collocation.collocation`).

    Raises
    ------
    ValueError
        A support (a callable edge) that selects no node.
    """
    scene = disc.scene
    for sup in scene.supports:
        if not essential_nodes(scene.with_supports((sup,)), disc.nodes, disc.method.spacing).any():
            raise ValueError(
                f"support {sup.edge!r} holds no node: bc='collocation' imposes the prescribed "
                "values at the nodes on supported edges, and its boundary term along the edge "
                "would be left without them. Select a stretch of boundary holding nodes, or use "
                "bc='lagrange' or 'variational', which impose supports along boundary lines.")
    faces = disc.nodes.face_positions(disc.approx.lines, 1e-3)
    dofs, values = eliminated_dofs(disc, faces)
    x = faces[dofs // 2]
    ux, uy = disc.shape_at(x, derivatives=False).u_operators()
    n = len(dofs)
    rows = csr_array(vstack([ux, uy], format="csr")[(dofs % 2) * n + np.arange(n)])
    return rows, values, dofs


def gamma_u_term(disc: Discretization) -> csr_array:
    """``H = int_{Gamma_u} phi_I t(phi_J) dGamma`` (n_dofs, n_dofs) on the prescribed components,
    by the boundary rule of :func:`essential_conditions` with ``t = N^T D B``
    (:func:`efgkit.system.constraints.boundary_traction_term`). The modified collocation method
    solves with ``K - H``: MLS test functions do not vanish on Gamma_u."""
    bc = essential_conditions(disc, derivatives=True)
    return boundary_traction_term(bc, disc.scene.material.D)
