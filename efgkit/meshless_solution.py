"""The result of a meshless (EFG) solve: MLS coefficients and the fields they define."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .approx.point_shapes import PointShapes
from .methods.discretize import Discretization, crack_mouths
from .problem.crack import FACE_OFFSET
from .problem.graded import modulus_weights, refuse_grading
from .problem.material import strain_from_gradient, voigt_tensor
from .solution import Solution, resultant

__all__ = ["MeshlessSolution"]


def _on_edge(domain, name: str, x: np.ndarray, tol: float) -> np.ndarray:
    """Mask (m,) of the points ``x (m, 2)`` within ``tol`` of the edges called ``name``."""
    polys = [e.polyline() for e in domain.edges(name)]
    a = np.concatenate([p[:-1] for p in polys])
    ab = np.concatenate([p[1:] for p in polys]) - a
    t = np.clip(np.einsum("mkj,kj->mk", x[:, None] - a[None], ab) / np.sum(ab * ab, -1), 0.0, 1.0)
    d = np.linalg.norm(x[:, None] - a[None] - t[..., None] * ab[None], axis=-1)
    return d.min(axis=1, initial=np.inf) <= tol


@dataclass(frozen=True, eq=False)
class MeshlessSolution(Solution):
    """Scene + discretisation + MLS coefficients: the :class:`~efgkit.solution.Solution`
    of the meshless methods.

    The coefficients ``coeffs (n_dofs,)`` (node-major, interleaved, then any
    enrichment unknowns) are MLS parameters, not nodal displacements: evaluate
    fields with the methods.

    Attributes
    ----------
    disc : Discretization
    coeffs : ndarray, shape (n_dofs,)
        2 per node (interleaved), then the enrichment unknowns.
    info : dict
        Solver information (solver, residual, iterations).
    timings : dict
        Seconds per stage, discretisation included.
    """

    disc: Discretization
    coeffs: np.ndarray
    info: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    resolve: object = field(default=None, repr=False)  # method -> Solution of the same scene
    support_forces: tuple | None = field(default=None, repr=False)  # (x (m, 2), force (m, 2))

    discretization_figure = "nodes"

    @property
    def kind(self) -> str:
        return getattr(self.method, "kind", "efg")

    @property
    def represents_tip_singularity(self) -> bool:
        return self.method.enrichment != "none"

    @property
    def scene(self):
        return self.disc.scene

    @property
    def method(self):
        return self.disc.method

    @property
    def nodes(self):
        return self.disc.nodes

    def _fields(self, x, derivatives):
        if x is None:
            sh = self.disc.post_shape
            if isinstance(sh, PointShapes):  # a large solve: formed a chunk at a time
                return sh
            if sh.neighbours is None and not derivatives:  # values released after a large solve
                return self.disc.shape_at(self.disc.post_points.x, derivatives=False)
            return sh
        x = self.scene.domain.field_points(x)
        return self.disc.shape_at(x, derivatives=derivatives)

    def displacement(self, x=None) -> np.ndarray:
        """Displacement at points ``x (n, 2)`` (default: the area quadrature points of
        post-processing, :attr:`Discretization.post_points`), shape (n, 2)."""
        return self._fields(x, derivatives=False).displacement(self.coeffs)

    def gradient(self, x=None) -> np.ndarray:
        """Displacement gradient du_i/dx_j at points ``x (n, 2)``, shape (n, 2, 2)."""
        return self._fields(x, derivatives=True).gradient(self.coeffs)

    def strain(self, x=None) -> np.ndarray:
        """Strain (xx, yy, xy engineering) at points ``x (n, 2)``, shape (n, 3)."""
        return self._fields(x, derivatives=True).strain(self.coeffs)

    def displacement_stress(self, x) -> tuple[np.ndarray, np.ndarray]:
        """``(displacement (n, 2), stress (n, 3))`` at points ``x (n, 2)`` from one evaluation
        of the shape functions and their derivatives."""
        f = self._fields(x, derivatives=True)
        return f.displacement(self.coeffs), f.strain(self.coeffs) @ self.scene.material.D.T

    def quadrature_fields(self):
        """``(x (n, 2), w (n,), stress (n, 3), grad_u (n, 2, 2))`` at the domain quadrature points."""
        grad = self.gradient()
        pts = self.disc.post_points  # MLPG: the background cells (its discs overlap)
        fE = modulus_weights(self.scene, pts.x, np.ones(len(pts.x)))  # graded: modulus(x)
        return (pts.x, pts.w, fE[:, None] * (strain_from_gradient(grad) @ self.scene.material.D.T), grad)

    def tip_spacing(self, tip) -> float:
        """The nodal spacing at a tip: c_I = d_mI / d_max of the node nearest to it."""
        nodes = self.nodes
        k = int(np.argmin(np.hypot(*(nodes.x - tip.x).T)))
        return float(nodes.radius[k] / self.method.d_max)

    def _sifs(self, radii=None, q="wendland_c2", spread_tol: float = 0.01) -> tuple:
        """The tips' results without the error estimate (:meth:`Solution.sifs
        <efgkit.solution.Solution.sifs>`): the integrals of :mod:`efgkit.fracture.integrals`
        over the domain quadrature points, with the crack-face pressure term when the crack
        is pressurised; radii default to :func:`~efgkit.fracture.sif.default_radii` with
        the spacing at the tip."""
        from .fracture.sif import face_loads, tip_radii, tip_result

        refuse_grading(self.scene, "the J and interaction integrals (SIFs)")
        x, w = self.disc.post_points.x, self.disc.post_points.w
        rs_of = [tip_radii(self.scene, tip, radii, self.tip_spacing(tip)) for tip in self.scene.tips]
        sh = self.disc.post_shape
        if isinstance(sh, PointShapes):  # formed on demand: only the points of the discs
            # (a superset of those domain_integrands takes: r < r_max in the tip frame)
            near = np.zeros(len(x), bool)
            for tip, rs in zip(self.scene.tips, rs_of, strict=True):
                try:  # radii tip_result will refuse: all points (it names the problem)
                    reach = float(np.max(np.asarray(rs, dtype=float)))
                except (TypeError, ValueError):
                    reach = np.inf
                near |= np.hypot(*(x - tip.x).T) < 1.001 * (reach if reach > 0 else np.inf)
            rows = np.flatnonzero(near)
            x, w, grad = x[rows], w[rows], sh.gradient(self.coeffs, rows)
        else:
            grad = self.gradient()
        stress = strain_from_gradient(grad) @ self.scene.material.D.T  # no second pass
        enr = self.disc.approx.enrichment
        out = []
        for k, tip in enumerate(self.scene.tips):
            h = self.tip_spacing(tip)
            rs = rs_of[k]
            faces = face_loads(self.scene, tip, max(rs), lambda xs, side: self.gradient(xs), h)
            kk = None
            if enr is not None and enr.kind == "extrinsic_mls":
                kk = tuple(self.coeffs[2 * self.nodes.n + 2 * k: 2 * self.nodes.n + 2 * k + 2])
            out.append(tip_result(self.scene, tip, x, w, stress, grad, rs, q=q, faces=faces,
                                  spread_tol=spread_tol, enriched=kk))
        return tuple(out)

    def near_tip_estimates(self, tip, r=None) -> dict:
        """Quick estimates of (K_I, K_II) at a tip, for comparison with :meth:`sifs`.

        ``"stress_0"`` and ``"stress_90"``: from the stresses on the rays theta = 0 and
        90 degrees, averaged over the two points nearest the tip (seed 000 Eqs. 5.2-5.5);
        ``"cod"``: the crack-opening displacement behind the tip extrapolated to r = 0
        (:mod:`efgkit.fracture.extrapolation`). ``r`` are the sample distances (default:
        1 to 6 spacings at the tip).
        """
        from .fracture.extrapolation import cod_sif, near_tip_sif, ray_points

        h = self.tip_spacing(tip)
        r = h * np.arange(1.0, 7.0) if r is None else np.asarray(r, dtype=float)
        up = tip.rotation[1]  # e2 of the tip frame: the upper face's side
        face = {s: self.displacement(ray_points(tip, r, np.pi) + s * FACE_OFFSET * h * up)
                for s in (1.0, -1.0)}
        return {"stress_0": near_tip_sif(tip, r, self.stress(ray_points(tip, r, 0.0)), 0.0),
                "stress_90": near_tip_sif(tip, r, self.stress(ray_points(tip, r, np.pi / 2)),
                                          np.pi / 2),
                "cod": cod_sif(tip, r, face[1.0], face[-1.0], self.scene.material)}

    def strain_energy(self) -> float:
        """U = 1/2 int eps : sigma dOmega over the domain quadrature."""
        eps = self.strain()
        w = modulus_weights(self.scene, self.disc.post_points.x, self.disc.post_points.w)
        return 0.5 * float(np.sum(w * np.einsum("ni,ij,nj->n", eps,
                                                                  self.scene.material.D, eps)))

    def errors(self, exact=None) -> dict:
        """Relative L2 displacement and energy-norm errors against an exact field.

        Energy norm as seed 003 Eq. (36): [1/2 int (sigma - sigma^h):(eps - eps^h)]^(1/2),
        divided by the same norm of the exact field. ``exact`` defaults to ``scene.exact``.

        Returns
        -------
        dict with ``l2`` and ``energy`` (relative) and the absolute ``energy_abs``.
        """
        from .problem.exact.fields import field_errors

        return field_errors(exact, self.scene, self.disc.post_points.x, self.disc.post_points.w,
                            self.displacement(), self.strain())

    def reaction(self, edge, about=None) -> np.ndarray:
        """Force ``(2,)`` the supports of ``edge`` apply to the body, from the weak form; with
        ``about=(x0, y0)`` ``(F_x, F_y, M)``, M the moment about that point.

        The forces of the essential conditions at their points (``support_forces``, from
        the solve: the multipliers with bc="lagrange", the penalty force with "penalty",
        the consistent flux with "variational", ``K c - f`` on the eliminated rows with
        "modified_mls"; docs/theory.md "Reactions") summed over the points on the edge
        (a name: within 1e-9 of the domain size of it, so a point support at a vertex
        counts for both edges; or a mask ``x (m, 2) -> bool (m,)``). Contracted with the
        rigid-body motions, which the MLS functions reproduce, the reactions of all
        supports balance the applied loads to rounding.

        A solution without ``support_forces`` (from a driver that does not record them)
        integrates ``sigma n`` along the edge instead, with the discretisation error of
        the boundary stresses. An edge on a symmetry line of an EFG half or quarter model is
        held by the image nodes (:mod:`efgkit.system.images`), not by a support: ValueError.
        """
        scene = self.scene
        if isinstance(edge, str) and edge not in scene.domain.edge_names:
            raise ValueError(f"no edge named {edge!r}; the domain's edges are "
                             f"{sorted(scene.domain.edge_names)}")
        if getattr(self.disc, "images", None) is not None and isinstance(edge, str) and \
                scene.symmetry.line_of(np.vstack([e.polyline() for e in scene.domain.edges(edge)]),
                                       1e-9 * scene.domain.size) is not None:
            raise ValueError(
                f"edge {edge!r} lies on a symmetry line of this EFG half or quarter model: the image "
                "nodes hold it, not a support, so it has no support force (and sigma n along it is "
                "singular at the tip). Take its force from the part's equilibrium: minus the "
                "applied loads and the other edges' reactions")
        if self.support_forces is None:
            from .quadrature.boundary import boundary_points

            m = self.method
            pts = boundary_points(scene.domain, edge, max(m.order, 2), m.spacing, crack_mouths(scene))
            t = np.einsum("nij,nj->ni", voigt_tensor(self.stress(pts.x)), pts.normal).reshape(-1, 2)
            return resultant(pts.x.reshape(-1, 2), pts.w[:, None] * t, about)
        x, force = self.support_forces
        if isinstance(edge, str):
            sel = _on_edge(scene.domain, edge, x, 1e-9 * scene.domain.size)
        else:
            sel = np.asarray(edge(x))
            if sel.shape != (len(x),) or sel.dtype != bool:
                raise TypeError(f"an edge callable must map x (n, 2) to a bool mask (n,), got "
                                f"{sel.dtype} array of shape {sel.shape}")
        return resultant(x[sel], force[sel], about)

    def write_vtu(self, path, n_target: int | None = None):
        """Fields on :func:`~efgkit.io.sample_grid` (``n_target`` points, default 20 000) and
        the node cloud beside them (:func:`efgkit.io.write_vtu`); returns the field file."""
        from .io import nodes_path, write_nodes_vtu
        from .io import write_vtu as write_fields

        path = write_fields(self, path, 20000 if n_target is None else n_target)
        write_nodes_vtu(self.nodes, nodes_path(path))
        return path

    def plot_stress(self, component: str = "von_mises", ax=None, levels: int = 30, limits=None,
                    n_target: int | None = None):
        """Filled contours of a stress component on the sample grid
        (:func:`efgkit.plot.plot_stress`); returns the figure."""
        from .plot import plot_stress

        return plot_stress(self, component, ax, n_target=20000 if n_target is None else n_target,
                           levels=levels, limits=limits)

    def plot_discretization(self, ax=None):
        """The node cloud with supports (:func:`efgkit.plot.plot_nodes`); returns the figure."""
        from .plot import plot_nodes

        return plot_nodes(self, ax=ax)

    def sizes(self) -> dict:
        return {"n_nodes": self.nodes.n, "n_boundary_nodes": int(self.nodes.boundary.sum()),
                "n_dofs": len(self.coeffs)}

