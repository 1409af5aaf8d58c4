"""Finite-element reference model of a scene: scikit-fem triangles, P2 (default) or P1.

:func:`solve_fem` meshes the scene (:func:`efgkit.fem.mesh.mesh_scene`: cracks
opened, graded toward the tips), assembles the stiffness with scikit-fem's
vectorised ``asm`` (``linear_elasticity`` with the 2D Lame constants of
:attr:`Elastic.lame <efgkit.problem.material.Elastic.lame>`), the tractions on the
named edges (Gauss rules on the boundary facets, outward normals) and the body
force, prescribes the supports' components at the boundary DOF locations
(vertices and, for P2, edge mid-nodes) by condensation, and solves with
:func:`efgkit.system.linalg.solve` (SuperLU, or CG with smoothed aggregation above
20 000 unknowns; the residual is checked).

The P2 mesh is isoparametric (scikit-fem ``MeshTri2``) when an edge is an
arc (mid-nodes of arc facets on the circle) or when ``quarter_point=True``
(the mid-nodes of the edges at a tip moved to the quarter point next to the
tip, which puts the 1/sqrt(r) strain of the crack tip in the element;
Barsoum, Int. J. Numer. Meth. Eng. 10 (1976) 25-37); otherwise it is affine.

The :class:`FEMSolution` mirrors :class:`efgkit.solution.Solution`: fields at
points, strain energy and errors against an exact field, plus quadrature-point
fields for domain integrals, the crack-mouth opening and support reactions.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..problem.scene import Scene, evaluate_component, evaluate_vector
from ..system.constraints import RigidBodyModeError
from ..system.linear_system import LinearSystem
from .dofs import dofs_where, face_side
from .mesh import TriMesh, check_sizes, mesh_scene
from .solution import FEMSolution

__all__ = ["FEM", "FEMSolution", "solve_fem"]


@dataclass(frozen=True)
class FEM:
    """Finite-element discretisation choices.

    Parameters
    ----------
    h : float
        Global element size (edge of the equilateral triangle of the element's area).
    tip_h : float, optional
        Element size at the crack tips and ``refine`` points (``<= h``); default (None):
        ``h / 8`` where there are crack tips or refine points, graded by ``grading``
        (:meth:`for_scene`; measured in docs/verification.md, ``defaults``), else ``h``.
    grading : float
        Size ratio of neighbouring elements away from a tip, in (1, 4].
    quarter_point : bool, optional
        Move the mid-nodes of the edges at each tip to the quarter point (P2 only); default
        (None): True for P2 on a scene with crack tips.
    order : {1, 2}
        Polynomial degree of the Lagrange triangles.
    min_angle : float
        Smallest triangle angle in degrees, in (0, 33].
    tip_fan : int
        Elements around every tip, ``5 <= tip_fan <= 360 / min_angle``, or 0
        for whatever Triangle leaves (4-6); see :func:`efgkit.fem.mesh.mesh_scene`.
        The default 12 (30 degrees per element) halves the energy error of
        the graded singular patch and quarters the tip's spurious displacement
        against Triangle's own 5-6 element fans (``verification/fem_reference.py``).
    refine : tuple of (float, float)
        Further points the mesh is graded toward, with ``tip_h`` (for example
        the tip of a crack modelled by a symmetry support).

    Examples
    --------
    >>> FEM(0.1, tip_h=0.01).order
    2
    >>> FEM(0.1, order=3)
    Traceback (most recent call last):
    ...
    ValueError: order must be 1 or 2 (P1 or P2 triangles), got 3
    """

    h: float
    tip_h: float | None = None
    grading: float = 1.25
    quarter_point: bool | None = None
    order: int = 2
    min_angle: float = 28.0
    tip_fan: int = 12
    refine: tuple = ()

    def __post_init__(self):
        check_sizes(self.h, self.tip_h, self.grading, self.min_angle, self.tip_fan)
        try:
            pts = tuple(tuple(float(c) for c in p) for p in np.asarray(self.refine, float).reshape(-1, 2))
        except (TypeError, ValueError) as err:
            raise ValueError(f"refine must be a sequence of points (x, y), got {self.refine!r}") from err
        object.__setattr__(self, "refine", pts)
        if isinstance(self.order, bool) or self.order not in (1, 2):
            raise ValueError(f"order must be 1 or 2 (P1 or P2 triangles), got {self.order!r}")
        if self.quarter_point is not None and not isinstance(self.quarter_point, bool):
            raise TypeError(f"quarter_point must be True, False or None (automatic), got "
                            f"{self.quarter_point!r}")
        if self.quarter_point and self.order != 2:
            raise ValueError("quarter_point=True needs order=2 (quarter-point nodes are P2 mid-nodes)")

    def for_scene(self, scene) -> FEM:
        """This model with its automatic choices made for ``scene``: ``tip_h = h / 8`` at crack
        tips and refine points and quarter-point P2 elements at the tips (K within 2.5e-4 and
        T within 2.1e-3 sigma at W/10 and W/20 on the specimens of ``defaults``, against
        0.3-3.4 % for uniform P2), none of it without tips. Explicit choices are kept.

        Examples
        --------
        >>> from efgkit import Crack, Domain, Elastic, Scene
        >>> sc = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3),
        ...            cracks=(Crack([[0.0, 0.5], [1.0, 0.5]], tips=(False, True)),))
        >>> f = FEM(0.1).for_scene(sc)
        >>> round(f.tip_h, 6), f.quarter_point
        (0.0125, True)
        """
        graded = bool(scene.tips) or bool(self.refine)
        kw = {}
        if self.tip_h is None and graded:
            kw["tip_h"] = self.h / 8
        if self.quarter_point is None:
            kw["quarter_point"] = self.order == 2 and bool(scene.tips)
        return replace(self, **kw) if kw else self

    def coarsened(self, factor: float = 2.0) -> FEM:
        """The same model with ``h`` and ``tip_h`` ``factor`` times larger (the companion solve
        of the error estimate, :meth:`efgkit.solution.Solution.sifs`).

        Examples
        --------
        >>> c = FEM(0.1, tip_h=0.01).coarsened()
        >>> c.h, c.tip_h
        (0.2, 0.02)
        """
        if isinstance(factor, bool) or not isinstance(factor, (int, float)) or not factor > 0:
            raise ValueError(f"factor must be a number > 0, got {factor!r}")
        return replace(self, h=self.h * factor,
                       tip_h=None if self.tip_h is None else self.tip_h * factor)


def _skfem_mesh(mesh: TriMesh, fem: FEM):
    """scikit-fem mesh (affine MeshTri1 or isoparametric MeshTri2) with named boundaries.

    Returns the mesh and ``fmap (n_facets,)``: the scikit-fem facet of each ``mesh.facets`` row.
    """
    from skfem import MeshTri1, MeshTri2

    sk = MeshTri1(mesh.x.T.copy(), mesh.t.T.copy())
    n = mesh.n_nodes
    keys = sk.facets[0].astype(np.int64) * n + sk.facets[1]  # facets are sorted pairs
    lo, hi = mesh.facets.min(axis=1), mesh.facets.max(axis=1)
    fmap = np.searchsorted(keys, lo * n + hi)
    if np.any(keys[np.minimum(fmap, len(keys) - 1)] != lo * n + hi):  # pragma: no cover
        raise RuntimeError("a boundary facet of the mesh is not a scikit-fem facet")
    edges = mesh.domain.edges()
    arcs = [k for k, e in enumerate(edges) if e.is_arc]
    if fem.order == 2 and (arcs or (fem.quarter_point and mesh.tip_nodes)):
        sk = MeshTri2.from_mesh(sk)
        p = sk.doflocs.copy()
        mid = sk.dofs.facet_dofs[0]
        for k in arcs:  # mid-nodes of arc facets onto the circle
            e, f = edges[k], fmap[mesh.facet_owner == k]
            d = p[:, sk.facets[0, f]] + p[:, sk.facets[1, f]] - 2 * e.centre[:, None]
            r = np.linalg.norm(e.start - e.centre)
            p[:, mid[f]] = e.centre[:, None] + r * d / np.linalg.norm(d, axis=0)
        if fem.quarter_point and mesh.tip_nodes:
            tips = np.array(mesh.tip_nodes)
            a, b = sk.facets
            at = np.isin(a, tips) | np.isin(b, tips)
            tip, other = np.where(np.isin(a, tips), a, b)[at], np.where(np.isin(a, tips), b, a)[at]
            p[:, mid[at]] = 0.75 * p[:, tip] + 0.25 * p[:, other]
        sk = replace(sk, doflocs=p)
    names = {e.name for e in edges}
    return sk.with_boundaries({nm: fmap[mesh.boundary(nm)] for nm in names}), fmap


def _rigid_modes(x):
    """Rigid-body motions at scalar DOF locations ``x (n, 2)``, shape (2 n, 3), unit columns."""
    R = np.zeros((2 * len(x), 3))
    R[0::2, 0] = R[1::2, 1] = 1.0
    R[0::2, 2] = -(x[:, 1] - x[:, 1].mean())
    R[1::2, 2] = x[:, 0] - x[:, 0].mean()
    return R / np.linalg.norm(R, axis=0)


def _facets_touched(where, mesh, fmap, sbasis, order: int = 4):
    """Boundary facets (scikit-fem numbering) with a Gauss point (``order`` per facet, as EFG's
    boundary rules) in the mask ``where``."""
    fac = fmap[mesh.facet_owner >= 0]
    sk = sbasis.mesh
    a, b = sk.p[:, sk.facets[0, fac]].T, sk.p[:, sk.facets[1, fac]].T
    t = (np.polynomial.legendre.leggauss(order)[0] + 1) / 2
    x = (a[:, None] + t[None, :, None] * (b - a)[:, None]).reshape(-1, 2)
    return fac[np.asarray(where(x), dtype=bool).reshape(len(fac), order).any(axis=1)]


def _essential(scene, mesh, fmap, sbasis):
    """Prescribed vector DOFs (k,) and values (k,); later supports override earlier ones."""
    val = np.zeros(2 * sbasis.N)
    fixed = np.zeros(2 * sbasis.N, dtype=bool)
    for s in scene.supports:
        dofs, fac = dofs_where(s.edge, mesh, fmap, sbasis)
        if callable(s.edge) and not len(dofs):  # a stretch holding no node: as EFG, which imposes
            # it at the boundary Gauss points it holds, fix the facets with a Gauss point in it
            fac = _facets_touched(s.edge, mesh, fmap, sbasis)
            if not len(fac):
                raise ValueError(
                    f"support {s.edge!r} selects no node and no boundary Gauss point of the mesh: "
                    "FEM imposes supports at nodes. Select a longer stretch of boundary, or use a "
                    "PointSupport (a pin or roller at a vertex or a FEM.refine point)")
            dofs = np.unique(sbasis.get_dofs(facets=fac).flatten())
        x = face_side(mesh, sbasis.doflocs[:, dofs].T, dofs)
        for c, v in ((0, s.ux), (1, s.uy)):
            if v is not None and len(dofs):
                val[2 * dofs + c] = evaluate_component(v, x, c, scene.material)
                fixed[2 * dofs + c] = True
    for p in scene.point_supports:  # the DOFs of the mesh node at the point
        dist = np.linalg.norm(sbasis.doflocs.T - np.asarray(p.x), axis=1)
        k = int(np.argmin(dist))
        if dist[k] > 1e-9 * mesh.domain.size:
            raise ValueError(f"point support at {list(p.x)}: the mesh has no node there (nearest "
                             f"{dist[k]:.3g} away); put the point at a vertex of the domain, or add "
                             "it to FEM.refine, which makes it a mesh vertex")
        for c in (0, 1):
            if p.fixed[c]:
                val[2 * k + c], fixed[2 * k + c] = p.values[c], True
    D = np.flatnonzero(fixed)
    R = _rigid_modes(sbasis.doflocs.T)
    if len(D) == 0:
        raise RigidBodyModeError(
            "the scene has no essential boundary condition: the body can move as a rigid body. "
            "Add a Support that prescribes ux and uy somewhere (and a rotation restraint).")
    sv = np.linalg.svd(R[D], compute_uv=False)
    if len(sv) < 3 or sv[-1] < 1e-8 * sv[0]:
        _, _, vt = np.linalg.svd(R[D])
        free = ["translation in x", "translation in y", "rotation"][int(np.argmax(np.abs(vt[-1])))]
        raise RigidBodyModeError(
            f"the supports leave a rigid-body mode free (mostly {free}); the stiffness matrix "
            "would be singular. Prescribe more displacement components.")
    return D, val[D], R


def _loads(scene, mesh, fmap, basis, order):
    """Load vector (n_dofs,) from the tractions, the crack-face pressures and the body force.

    A crack's ``pressure`` p acts on both of its faces as the traction ``-p n`` (``n`` the
    outward normal of the face's elements), as in :func:`efgkit.methods.boundary.crack_face_loads`."""
    from skfem import FacetBasis, LinearForm, asm
    from skfem.helpers import dot

    @LinearForm
    def load(v, w):
        return dot(w["g"], v)

    f = np.zeros(basis.N)
    mat, sk = scene.material, basis.mesh
    sbasis = basis.with_element(basis.elem.elem)
    for tr in scene.tractions:
        _, fac = dofs_where(tr.edge, mesh, fmap, sbasis)
        if len(fac):
            fb = FacetBasis(sk, basis.elem, facets=fac, intorder=2 * order + 2)
            xq = np.asarray(fb.global_coordinates())
            nq = np.asarray(fb.normals)
            g = evaluate_vector(tr.t, xq.reshape(2, -1).T, nq.reshape(2, -1).T, mat)
            f += asm(load, fb, g=g.T.reshape(xq.shape))
    for c, crack in enumerate(scene.cracks):  # pressure p > 0 pushes each face into its material
        fac = fmap[mesh.facet_owner == -1 - c]
        if crack.pressure != 0.0 and len(fac):
            fb = FacetBasis(sk, basis.elem, facets=fac, intorder=2 * order + 2)
            f += asm(load, fb, g=-crack.pressure * np.asarray(fb.normals))
    if scene.body_force is not None:
        xq = np.asarray(basis.global_coordinates())
        g = evaluate_vector(scene.body_force, xq.reshape(2, -1).T, np.zeros((xq[0].size, 2)), mat)
        f += asm(load, basis, g=g.T.reshape(xq.shape))
    return f


def solve_fem(scene: Scene, fem: FEM, mesh: TriMesh | None = None) -> FEMSolution:
    """Mesh, assemble and solve a static scene with finite elements.

    Parameters
    ----------
    scene : Scene
        A static scene (``duration`` None).
    fem : FEM
    mesh : TriMesh, optional
        A mesh of ``scene`` to use instead of meshing it with ``fem`` (for example
        :func:`~efgkit.fem.mesh.mirror_mesh` of a half model's mesh).

    Returns
    -------
    FEMSolution

    Raises
    ------
    RigidBodyModeError
        The supports leave a rigid-body motion free.
    ValueError
        A graded scene (position-dependent material: not in the FE reference).
    efgkit.system.linalg.SolverError
        The linear solve fails its residual check (relative residual > 1e-8).

    Examples
    --------
    >>> from efgkit import Domain, Elastic, Support, Traction
    >>> scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(100.0, 0.25, "stress"),
    ...               supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
    ...               tractions=(Traction("right", (1.0, 0.0)),))
    >>> sol = solve_fem(scene, FEM(h=0.5))
    >>> np.round(sol.displacement([[2.0, 1.0]]), 12).tolist()   # (sigma L / E, -nu sigma H / E)
    [[0.02, -0.0025]]
    >>> np.round(sol.reaction("left"), 12).tolist()
    [-1.0, 0.0]
    """
    from skfem import Basis, ElementTriP1, ElementTriP2, ElementVector, asm
    from skfem.models.elasticity import linear_elasticity

    from ..problem.graded import refuse_grading
    from ..system.linalg import solve

    refuse_grading(scene, "the FE reference (solve_fem)")
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(fem, FEM):
        raise TypeError(f"fem must be a FEM, got {type(fem).__name__}")
    if not scene.is_static:
        raise ValueError(f"solve_fem solves static scenes; scene {scene.name!r} has duration "
                         f"{scene.duration!r}: give duration=None")
    if scene.symmetry is not None:  # grade toward the modelled tips of a half or quarter model
        tips = tuple(tuple(map(float, t.x)) for t in scene.symmetry.modelled_tips(scene.domain))
        fem = replace(fem, refine=fem.refine + tuple(t for t in tips if t not in fem.refine))
    fem = fem.for_scene(scene)  # tip grading and quarter points where there are tips
    t = {"start": time.perf_counter()}
    if mesh is None:
        mesh = mesh_scene(scene, fem.h, fem.tip_h, fem.grading, fem.min_angle, fem.tip_fan, fem.refine)
    elif not isinstance(mesh, TriMesh):
        raise TypeError(f"mesh must be a TriMesh, got {type(mesh).__name__}")
    t["mesh"] = time.perf_counter()
    sk, fmap = _skfem_mesh(mesh, fem)
    elem = ElementTriP2() if fem.order == 2 else ElementTriP1()
    basis = Basis(sk, ElementVector(elem), intorder=2 * fem.order)
    K = asm(linear_elasticity(*scene.material.lame), basis).tocsr()
    f = _loads(scene, mesh, fmap, basis, fem.order)
    t["assemble"] = time.perf_counter()
    sbasis = basis.with_element(elem)
    D, uD, R = _essential(scene, mesh, fmap, sbasis)
    free = np.setdiff1d(np.arange(basis.N), D)
    K_free = K[free]
    A = K_free[:, free]
    b = f[free] - K_free[:, D] @ uD
    z, info = solve(LinearSystem(A, b, True, len(free)), near_nullspace=R[free])
    u = np.zeros(basis.N)
    u[free], u[D] = z, uD
    t["solve"] = time.perf_counter()
    info.update(n_dofs=int(basis.N), n_elements=mesh.n_elements, n_fixed=len(D))
    timings = {k: t[k] - t[p] for p, k in (("start", "mesh"), ("mesh", "assemble"),
                                           ("assemble", "solve"))}
    return FEMSolution(scene, fem, mesh, basis, fmap, u, K, f, info, timings,
                       resolve=lambda coarse: solve_fem(scene, coarse))
