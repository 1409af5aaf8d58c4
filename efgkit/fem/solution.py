"""The result of a finite-element solve (:func:`efgkit.fem.solve_fem`) and its fields.

A :class:`efgkit.solution.Solution` like the meshless ones; it adds the
quadrature-point fields of its domain integrals, the nodal stresses and the mesh
figure. Its crack-mouth opening is the jump between the two mouth nodes and its
reactions are ``K u - f`` summed over the DOFs of an edge.

Points are located in the mesh by :class:`efgkit.fem.locate.PointLocator`; a
point on a crack line is evaluated on the crack's *left* face.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..problem.exact.fields import field_errors
from ..problem.material import strain_from_gradient
from ..solution import Solution, resultant
from .locate import PointLocator

__all__ = ["FEMSolution"]


@dataclass(frozen=True, eq=False)
class FEMSolution(Solution):
    """Scene + FEM + mesh + nodal displacements.

    Attributes
    ----------
    scene : Scene
    fem : FEM
    mesh : TriMesh
        The linear triangle mesh (cracks opened).
    basis : skfem.CellBasis
        Vector P1/P2 basis; DOFs are node-major interleaved ``2 i + c``.
    fmap : ndarray (n_facets,)
        scikit-fem facet of each ``mesh.facets`` row.
    u : ndarray (n_dofs,)
        Nodal displacements.
    K : csr_array (n_dofs, n_dofs); f : ndarray (n_dofs,)
        Stiffness and load before the supports: ``K u - f`` are the reactions.
    info, timings : dict
        Solver information (``residual``, ``n_dofs``, ...) and seconds per stage.

    Examples
    --------
    Seed 003 Sect. 5.6.1: the mode-I Williams field prescribed around an edge crack.

    >>> from efgkit import Crack, Domain, Elastic, Field, Scene, Support
    >>> from efgkit.fem import FEM, solve_fem
    >>> W = Field.named("williams", KI=1.0)
    >>> scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
    ...               supports=tuple(Support(e, ux=W, uy=W) for e in ("left", "bottom", "right", "top")),
    ...               cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True), name="c"),))
    >>> sol = solve_fem(scene, FEM(0.25, tip_h=0.02, quarter_point=True))
    >>> round(sol.cmod("c"), 4)  # prescribed at the mouth: the exact jump
    2.9043
    >>> x, w, stress, grad_u = sol.quadrature_fields()
    >>> round(float(w.sum()), 12), grad_u.shape[1:]
    (4.0, (2, 2))
    >>> bool(sol.errors(W)["energy"] < 0.1)
    True
    """

    scene: object
    fem: object
    mesh: object
    basis: object
    fmap: np.ndarray
    u: np.ndarray
    K: object
    f: np.ndarray
    info: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    resolve: object = field(default=None, repr=False)  # method -> Solution of the same scene

    kind = "fem"
    discretization_figure = "mesh"

    @property
    def represents_tip_singularity(self) -> bool:
        return self.fem.quarter_point

    @property
    def method(self):
        """The :class:`~efgkit.fem.FEM` description."""
        return self.fem

    @property
    def n_dofs(self) -> int:
        return int(self.basis.N)

    @cached_property
    def _sbasis(self):
        return self.basis.with_element(self.basis.elem.elem)

    @cached_property
    def _locator(self) -> PointLocator:
        return PointLocator(self.scene, self.mesh, self.basis.mesh)

    def _at(self, elems, X, grad: bool):
        """Displacement (n, 2) or displacement gradient (n, 2, 2) at reference points."""
        el = self.basis.elem.elem
        sd = self.basis.element_dofs[0::2, elems] // 2  # scalar DOFs (n_local, n)
        ev = [el.lbasis(X, i) for i in range(sd.shape[0])]
        U = np.stack([self.u[2 * sd], self.u[2 * sd + 1]])  # (2, n_local, n)
        if not grad:
            return np.einsum("cin,in->nc", U, np.array([e[0] for e in ev]))
        J = self._locator.jacobian(elems, X)
        dref = np.array([e[1] for e in ev])  # (n_local, 2, n)
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        if np.any(det == 0):
            raise ValueError("a point is at a quarter-point crack tip, where the strain is singular")
        inv = np.array([[J[1, 1], -J[0, 1]], [-J[1, 0], J[0, 0]]]) / det  # inv[e, d] = dX_e / dx_d
        return np.einsum("cin,ien,edn->ncd", U, dref, inv)

    @cached_property
    def _qp(self):
        """Displacement and its gradient at the quadrature points (skfem DiscreteField)."""
        return self.basis.interpolate(self.u)

    def displacement(self, x=None) -> np.ndarray:
        """Displacement at points ``x (n, 2)`` (default: the quadrature points), shape (n, 2)."""
        if x is None:
            return np.asarray(self._qp).reshape(2, -1).T
        return self._at(*self._locator(x), grad=False)

    def gradient(self, x=None) -> np.ndarray:
        """Displacement gradient du_i/dx_j at points ``x (n, 2)``, shape (n, 2, 2)."""
        if x is None:
            return self._qp.grad.reshape(2, 2, -1).transpose(2, 0, 1)
        return self._at(*self._locator(x), grad=True)

    def quadrature_fields(self):
        """Fields at every element quadrature point, for domain integrals.

        Returns
        -------
        x : ndarray (n, 2)
            Points (element-major).
        w : ndarray (n,)
            Weights (area elements included); ``w.sum()`` is the mesh area.
        stress : ndarray (n, 3)
            Voigt (xx, yy, xy).
        grad_u : ndarray (n, 2, 2)
            ``grad_u[:, i, j] = d u_i / d x_j``.
        """
        x = np.asarray(self.basis.global_coordinates()).reshape(2, -1).T
        return x, self.basis.dx.ravel(), self.stress(), self.gradient(None)

    def tip_size(self, tip) -> float:
        """Mean size (:attr:`TriMesh.size`) of the elements at a tip's node: the local ``h``
        of the default J domains.

        Parameters
        ----------
        tip : Tip
            One of ``scene.tips``.
        """
        from ..fracture.sif import scene_tip

        tip = scene_tip(self.scene, tip)
        node = self.mesh.tip_nodes[[t.id for t in self.scene.tips].index(tip.id)]
        return float(self.mesh.size[np.any(self.mesh.t == node, axis=1)].mean())

    def _sifs(self, radii=None, q="wendland_c2", spread_tol: float = 0.01) -> tuple:
        """The tips' results without the error estimate (:meth:`efgkit.solution.Solution.sifs`):
        the integrals of
        :mod:`efgkit.fracture.integrals` (seed 001 Eq. 7 with the q-functions of
        Eqs. 10, 13, 14) run over the element quadrature points
        (:meth:`quadrature_fields`, Gauss rule of degree ``2 order``), with the
        crack-face pressure term when the crack is pressurised
        (:func:`~efgkit.fracture.sif.face_loads`, fields evaluated on each face);
        each tip's result is the mean over the domains with their spread
        (:func:`~efgkit.fracture.sif.tip_result`).

        Parameters
        ----------
        radii : sequence of float, or callable ``tip -> radii``, optional
            Domain radii, at least three (default:
            :func:`~efgkit.fracture.sif.default_radii` with the global element size
            ``fem.h``: 10, 12.5 and 15 h, shrunk to fit the body; lengths of the geometry,
            not tip elements, whose domains made T worse as ``tip_h`` shrank: 1.5e-3
            against 1.6e-4 sigma on the singular patch at W/20, docs/verification.md).
        q : str or callable
            q-function kind (:class:`~efgkit.fracture.qfunctions.QFunction`) or
            ``radius -> QFunction``.
        spread_tol : float
            Relative spread of K over the domains above which a warning is issued.

        Returns
        -------
        tuple of TipResult, one per tip of ``scene.tips``.

        Examples
        --------
        The mode-I Williams field prescribed around an edge crack (seed 003 Sect. 5.6.1):

        >>> from efgkit import Crack, Domain, Elastic, Field, Scene, Support
        >>> from efgkit.fem import FEM, solve_fem
        >>> W = Field.named("williams", KI=1.0)
        >>> scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
        ...               supports=tuple(Support(e, ux=W, uy=W) for e in ("left", "bottom", "right", "top")),
        ...               cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True)),))
        >>> res, = solve_fem(scene, FEM(0.25, tip_h=0.02, quarter_point=True)).sifs(radii=(0.3, 0.5, 0.7))
        >>> round(res.KI, 3), round(res.KII, 3), bool(res.spread < 1e-3)
        (1.0, 0.0, True)
        """
        from ..fracture.sif import tip_radii, tip_result

        x, w, stress, grad = self.quadrature_fields()
        out = []
        for tip in self.scene.tips:
            rs = tip_radii(self.scene, tip, radii, self.fem.h)  # lengths of the geometry
            faces = self._face_load(tip, max(rs))
            out.append(tip_result(self.scene, tip, x, w, stress, grad, rs, q=q, faces=faces,
                                  spread_tol=spread_tol))
        return tuple(out)

    def _face_load(self, tip, radius: float):
        """Gauss points of the loaded crack-face facets of ``tip``'s crack that reach into the
        disc of ``radius``, as a :class:`~efgkit.fracture.integrals.FaceLoad` (None without
        pressure). The rule follows the elements (degree ``2 order + 2`` on each facet,
        through the facet's isoparametric map, so quarter-point facets get points crowded
        toward the tip) and the gradient is that of the facet's own element: the face
        integral of J sums the FE field exactly, where a global rule across the facets'
        jumps in the gradient would not."""
        from skfem import FacetBasis

        from ..fracture.integrals import FaceLoad

        k = [c.name for c in self.scene.cracks].index(tip.crack)
        p = self.scene.cracks[k].pressure
        if p == 0.0:
            return None
        f = self.fmap[self.mesh.facet_owner == -1 - k]
        sk = self.basis.mesh
        ends = sk.p[:, sk.facets[:, f]]  # (2, 2, n_facets)
        f = f[np.linalg.norm(ends - tip.x[:, None, None], axis=0).min(axis=0) < radius]
        if len(f) == 0:
            return None
        fb = FacetBasis(sk, self.basis.elem, facets=f, intorder=2 * self.fem.order + 2)
        n = np.asarray(fb.normals).reshape(2, -1).T
        up = tip.rotation[1]  # e2 of the tip frame
        return FaceLoad(np.asarray(fb.global_coordinates()).reshape(2, -1).T, fb.dx.ravel(), -p * n,
                        fb.interpolate(self.u).grad.reshape(2, 2, -1).transpose(2, 0, 1),
                        np.where(n @ up < 0, 1.0, -1.0))

    def strain_energy(self) -> float:
        """U = 1/2 u . K u (the strain energy of the discrete solution)."""
        return 0.5 * float(self.u @ (self.K @ self.u))

    def errors(self, exact=None) -> dict:
        """Relative L2 displacement and energy-norm errors against an exact field.

        As :meth:`efgkit.solution.Solution.errors` (seed 003 Eq. (36)), integrated with a
        Gauss rule of degree ``2 order + 2`` on every element.

        Returns
        -------
        dict with ``l2`` and ``energy`` (relative) and the absolute ``energy_abs``.
        """
        from skfem import Basis

        eb = Basis(self.basis.mesh, self.basis.elem, intorder=2 * self.fem.order + 2)
        q = eb.interpolate(self.u)
        x, w = np.asarray(eb.global_coordinates()).reshape(2, -1).T, eb.dx.ravel()
        u, g = np.asarray(q).reshape(2, -1).T, q.grad.reshape(2, 2, -1).transpose(2, 0, 1)
        eps = strain_from_gradient(g)
        return field_errors(exact, self.scene, x, w, u, eps)

    def cmod(self, crack) -> float:
        """Crack-mouth opening: ``(u_left - u_right) . n`` at the mouth vertex.

        ``n`` is the unit normal of the mouth segment pointing to the left face, so the
        opening is positive when the faces separate, whichever way the crack runs.

        Parameters
        ----------
        crack : Crack or str
            A crack of the scene (or its name) with a mouth.
        """
        names = [c.name for c in self.scene.cracks]
        name = getattr(crack, "name", crack)
        if name not in names:
            raise ValueError(f"the scene has no crack {name!r}; its cracks are {names}")
        k = names.index(name)
        c = self.scene.cracks[k]
        if all(c.tips):
            raise ValueError(f"crack {name!r} has no mouth (both ends are tips): a crack-mouth "
                             "opening needs an edge crack")
        end = 0 if not c.tips[0] else 1
        left, right = self.mesh.crack_nodes[k]
        i, j = (left[0], right[0]) if end == 0 else (left[-1], right[-1])
        a, b = c.segments[0 if end == 0 else -1]
        n = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
        return float((self.u[2 * i:2 * i + 2] - self.u[2 * j:2 * j + 2]) @ n)

    def reaction(self, edge, about=None) -> np.ndarray:
        """Resultant force ``(2,)`` of ``K u - f`` over the DOFs of an edge; with
        ``about=(x0, y0)`` ``(F_x, F_y, M)``, M the moment of the nodal forces about that
        point (:func:`efgkit.solution.resultant`).

        For a supported edge this is the force the support applies to the body;
        free DOFs carry no residual. A corner DOF shared by two edges counts for both.

        Parameters
        ----------
        edge : str or callable
            Edge name, or ``x (n, 2) -> bool (n,)`` selecting boundary DOF locations.
        about : (2,) float, optional
        """

        from .dofs import dofs_where

        if isinstance(edge, str) and edge not in self.scene.domain.edge_names:
            raise ValueError(f"no edge named {edge!r}; the domain's edges are "
                             f"{sorted(self.scene.domain.edge_names)}")
        dofs, _ = dofs_where(edge, self.mesh, self.fmap, self._sbasis)
        r = self.K @ self.u - self.f
        return resultant(self._sbasis.doflocs[:, dofs].T, np.column_stack([r[2 * dofs], r[2 * dofs + 1]]),
                         about)

    def nodal_stress(self) -> np.ndarray:
        """Stress (n_nodes, 3) at the mesh vertices (:func:`efgkit.fem.output.nodal_stress`)."""
        from .output import nodal_stress

        return nodal_stress(self)

    def write_vtu(self, path, n_target: int | None = None) -> Path:
        """Write the mesh and fields as VTU (:func:`efgkit.fem.output.write_vtu`), or with
        ``n_target`` the fields on :func:`efgkit.io.sample_grid` as for meshless solutions."""
        if n_target is not None:
            from ..io import write_vtu as write_fields

            return write_fields(self, path, n_target)
        from .output import write_vtu

        return write_vtu(self, path)

    def plot_discretization(self, ax=None):
        """The mesh (:func:`efgkit.fem.output.plot_mesh`); returns the figure."""
        return self.plot_mesh(ax)

    def plot_mesh(self, ax=None):
        """The mesh (:func:`efgkit.fem.output.plot_mesh`); returns the figure."""
        from .output import plot_mesh

        return plot_mesh(self.mesh, ax)

    def plot_stress(self, component: str = "von_mises", ax=None, levels: int = 30, limits=None,
                    n_target: int | None = None):
        """Filled contours of a stress component on the mesh (:func:`efgkit.fem.output.plot_stress`)
        or, with ``n_target``, on the sample grid (:func:`efgkit.plot.plot_stress`)."""
        if n_target is not None:
            from ..plot import plot_stress

            return plot_stress(self, component, ax, n_target=n_target, levels=levels, limits=limits)
        from .output import plot_stress

        return plot_stress(self, component, ax, levels, limits)

    def sizes(self) -> dict:
        return {"n_nodes": self.mesh.n_nodes, "n_elements": self.mesh.n_elements,
                "n_dofs": self.n_dofs}
