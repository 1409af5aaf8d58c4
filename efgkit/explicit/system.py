"""The semi-discrete system ``M u'' + K u = f(t)`` of a dynamic scene, built once.

:func:`dynamics` assembles the stiffness, the lumped mass (:mod:`efgkit.system.mass`),
the load vectors of each load history, and the essential conditions;
:func:`~efgkit.explicit.spectrum.stable_step` estimates the critical step ``2 / omega_max``
(seed 002 Eqs. 29-30) from these matrices.

Essential conditions in the explicit scheme follow ``method.bc``:

* ``"lagrange"`` (and ``"auto"``, for dynamic scenes): the constraint ``G u = q`` of the
  static Lagrange method (piecewise-linear multipliers along the supported edges) is
  imposed on every new displacement by the M-orthogonal projection
  ``u <- u - M^-1 G^T (G M^-1 G^T)^-1 (G u - q)`` (the forward-increment Lagrange
  multipliers of Carpenter, Taylor and Katona, 1991), with ``G M^-1 G^T`` (a few hundred
  rows) factorised once. The constraint forces do no work, the stiffness is untouched, and
  the critical step is that of the constrained operator (not lowered).
* ``"penalty"`` and ``"variational"``: the constraint terms are added to K (the static
  system's matrix), which raises omega_max: the stable step falls (docs/theory.md).
* ``"modified_mls"``: the coefficients of the interpolating boundary nodes are fixed
  (row cross-out, seed 002 after Eq. 27): their inverse mass is set to 0.

MLPG (:class:`~efgkit.MLPG`, :func:`local_dynamics`): K and the loads of the local weak
forms (:func:`~efgkit.methods.local.local_system`, one load vector per load history), the
mass ``M_I = rho int_{Omega_s^I} v_I sum_J phi_J dOmega`` over the node's own disc (seed
002 Eqs. 25-27, the test functions ``v_I``); ``bc="penalty"``: the penalty of the local weak
form is in K (its prescribed values in ``f_bc``); ``"modified_mls"``: as above;
``"collocation"``: the rows ``u^h_c(x_I) = ubar_c(x_I)`` at the essential nodes are imposed
by the projection (the equations of those nodes are kept, with the constraint's reaction,
instead of replaced as in the static solve). K is not symmetric: docs/theory.md
("Explicit MLPG") on its spectrum and the energy balance; the trial weight of explicit runs
is ``MLPG.explicit_weight`` (:func:`~efgkit.explicit.mlpg_weight.explicit_mlpg`). That is
MLPG1 (``explicit_form="petrov_galerkin"``, opt-in); by default explicit MLPG runs step the
symmetric Galerkin form of its trial functions (:mod:`efgkit.explicit.galerkin_form`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.sparse import csc_array, csr_array, diags_array
from scipy.sparse.linalg import splu

from ..meshless_solution import MeshlessSolution
from ..methods.boundary import collocation_rows, eliminated_dofs, essential_conditions, loads
from ..methods.discretize import Discretization, discretize
from ..methods.efg import EFG
from ..methods.local import DEFAULT_MLPG_PENALTY, discretize_local, local_loads, local_system
from ..methods.mlpg import MLPG
from ..problem.exact.fields import Field
from ..problem.graded import density_weights, modulus_weights, refuse_grading
from ..problem.scene import Scene
from ..static import DEFAULT_PENALTY, DEFAULT_STABILISATION
from ..system.assemble import stiffness
from ..system.constraints import lagrange, modified_variational, penalty
from ..system.mass import ENRICHMENT_MASSES, row_sum_mass
from .galerkin_form import galerkin_system, resolve_form
from .mlpg_weight import explicit_mlpg
from .moving import split_values, still_scene

__all__ = ["Dynamics", "Projection", "dynamics", "fit_coefficients", "local_dynamics"]


@dataclass(frozen=True, eq=False)
class Projection:
    """Impose ``G u = q`` on a displacement by the M-orthogonal projection.

    Attributes
    ----------
    G : csr_array (r, n_dofs); q : (r,)
    minv_GT : csr_array (n_dofs, r)
        ``M^-1 G^T``.
    lu : SuperLU
        Factors of ``G M^-1 G^T`` (r, r).
    """

    G: csr_array
    q: np.ndarray
    minv_GT: csr_array
    lu: object

    @classmethod
    def build(cls, G: csr_array, q: np.ndarray, minv: np.ndarray) -> Projection:
        minv_GT = csr_array(diags_array(minv) @ G.T)
        S = csc_array(G @ minv_GT)
        try:
            lu = splu(S)
        except RuntimeError as err:  # exactly singular
            raise ValueError(f"the constraint matrix G M^-1 G^T ({S.shape[0]} rows) is singular: "
                             "two supports constrain the same motion twice; prescribe each "
                             "component once on an edge or use bc='penalty'") from err
        return cls(G, np.asarray(q, float), minv_GT, lu)

    def correction(self, u: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """``M^-1 G^T (G M^-1 G^T)^-1 (G u - q)``, shape (n_dofs,): subtract it from u
        (``q`` default: the constant ``self.q``; moving supports pass ``Dynamics.prescribed(t)``)."""
        return self.minv_GT @ self.lu.solve(self.G @ u - (self.q if q is None else q))


@dataclass(frozen=True, eq=False)
class Dynamics:
    """``M u'' + K u = f(t)``: everything the time loop needs, assembled.

    Attributes
    ----------
    disc : Discretization
    K : csr_array (n_dofs, n_dofs)
        Stiffness, with the penalty / Nitsche terms of those methods.
    m : ndarray (n_dofs,)
        Lumped mass; ``minv`` its inverse, 0 on the fixed coefficients.
    F : ndarray (n_dofs, n_loads)
        One load vector per load history; ``histories`` their factors g(t) (None:
        constant); ``f_bc`` the constant forcing of prescribed values (penalty, Nitsche).
    projection : Projection or None
        The Lagrange constraint (bc="lagrange").
    fixed : ndarray (k,) int, fixed_values (k,)
        Fixed coefficients (bc="modified_mls").
    bc : str
    timings : dict
    form : str or None
        The equations of an MLPG run, ``"petrov_galerkin"`` (MLPG1) or ``"galerkin"``
        (:mod:`efgkit.explicit.galerkin_form`); None for EFG.
    Q : ndarray (r, k) or None; q_histories : tuple (k,)
        Moving supports (:mod:`efgkit.explicit.moving`): the constraint values are
        ``prescribed(t) = q_0 + Q g(t)`` (``q_0``: ``projection.q`` or ``fixed_values``).
        With penalty or Nitsche constraints their forcing is in ``F`` instead (Q None).
    """

    disc: Discretization
    K: csr_array
    m: np.ndarray
    minv: np.ndarray
    F: np.ndarray
    histories: tuple
    f_bc: np.ndarray
    projection: Projection | None
    fixed: np.ndarray
    fixed_values: np.ndarray
    bc: str
    timings: dict = field(default_factory=dict)
    Q: np.ndarray | None = None
    q_histories: tuple = ()
    form: str | None = None

    @property
    def n_dofs(self) -> int:
        return len(self.m)

    @property
    def moving_supports(self) -> bool:
        """Whether constraint values change in time (a support with a history)."""
        return self.Q is not None

    def prescribed(self, t: float) -> np.ndarray:
        """The constraint values at ``t``: ``q_0 + Q g(t)``, shape (r,) (the Lagrange or
        collocation rows' ``q``, or the modified-MLS fixed values)."""
        base = self.projection.q if self.projection is not None else self.fixed_values
        if self.Q is None:
            return base
        return base + self.Q @ np.array([float(g(t)) for g in self.q_histories])

    @property
    def time_dependent(self) -> bool:
        return any(g is not None for g in self.histories)

    def factors(self, t: float) -> np.ndarray:
        """The load factors at ``t``, shape (n_loads,)."""
        return np.array([1.0 if g is None else float(g(t)) for g in self.histories])

    def force(self, t: float) -> np.ndarray:
        """``f(t) = F g(t) + f_bc``, shape (n_dofs,)."""
        return self.F @ self.factors(t) + self.f_bc


def _load_scenes(scene: Scene) -> list[tuple[Scene, object]]:
    """The scene split by load history: [(scene with only those loads, history)]."""
    quiet = [replace(c, pressure=0.0) for c in scene.cracks]
    bare = replace(scene, tractions=(), body_force=None, body_force_history=None, cracks=quiet,
                   initial_displacement=None, initial_velocity=None)
    const_t = tuple(t for t in scene.tractions if t.history is None)
    const_b = scene.body_force if scene.body_force_history is None else None
    out = []
    if const_t or const_b is not None or any(c.pressure != 0 for c in scene.cracks):
        out.append((replace(bare, tractions=const_t, body_force=const_b, cracks=scene.cracks), None))
    out += [(replace(bare, tractions=(t,)), t.history) for t in scene.tractions if t.history is not None]
    if scene.body_force is not None and scene.body_force_history is not None:
        out.append((replace(bare, body_force=scene.body_force), scene.body_force_history))
    return out


def fit_coefficients(disc: Discretization, u) -> np.ndarray:
    """MLS coefficients ``(n_dofs,)`` whose field interpolates ``u`` (a callable
    ``x (n, 2) -> (n, 2)``, a :class:`~efgkit.problem.exact.fields.Field` or a 2-vector) at the nodes
    (enrichment unknowns 0): ``Phi c = u(x_I)`` with the sparse nodal matrix ``Phi_IJ =
    phi_J(x_I)`` (split nodes evaluated on their own face), solved by SuperLU."""
    x = disc.nodes.face_positions(disc.approx.lines, 1e-3)
    if isinstance(u, Field):
        vals = u.displacement(x, disc.scene.material)
    elif callable(u):
        vals = np.asarray(u(x), dtype=float)
    else:
        vals = np.broadcast_to(np.asarray(u, dtype=float), x.shape)
    if vals.shape != (len(x), 2) or not np.all(np.isfinite(vals)):
        raise ValueError(f"an initial field must map x (n, 2) to finite values (n, 2); got shape "
                         f"{vals.shape} for n = {len(x)}" + ("" if vals.shape != (len(x), 2) else
                                                             " with non-finite values"))
    phi = csc_array(csr_array(disc.shape_at(x, derivatives=False).phi)[:, : len(x)])
    lu = splu(phi)
    c = np.zeros(disc.n_dofs)
    c[0:2 * len(x):2] = lu.solve(vals[:, 0])
    c[1:2 * len(x):2] = lu.solve(vals[:, 1])
    return c


def dynamics(scene: Scene, method: EFG | MLPG, disc: Discretization | None = None,
             enrichment_mass: str = "diagonal") -> Dynamics:
    """Assemble ``M u'' + K u = f(t)`` for ``scene`` (module docstring).

    ``enrichment_mass``: the lumped mass of enrichment unknowns (EFG, MLPG's Galerkin form),
    :func:`~efgkit.system.mass.row_sum_mass` ``enrichment`` (``"abs_row_sum"`` keeps the
    unenriched critical step).

    Raises
    ------
    ValueError
        The scene is static (``duration`` None) or has no density (``Elastic.rho``).
    MassError
        A lumped mass is not positive or the masses do not add up to rho times the area.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if scene.is_static:
        raise ValueError(f"scene {scene.name!r} is static (duration None): give "
                         "Scene(..., duration=...) to integrate it in time, or solve it with "
                         "efgkit.solve")
    if scene.material.rho is None:
        raise ValueError(f"scene {scene.name!r}: a dynamic run needs the mass density: give "
                         "Elastic(..., rho=...) (the [material] key rho in a scene file)")
    if enrichment_mass not in ENRICHMENT_MASSES:
        raise ValueError(f"enrichment_mass must be one of {ENRICHMENT_MASSES}, got "
                         f"{enrichment_mass!r}")
    if isinstance(method, MLPG):
        return local_dynamics(scene, method, disc, enrichment_mass)
    bc_auto = method.bc == "auto"
    method = method.for_scene(scene)
    if bc_auto:
        method = replace(method, bc="lagrange")  # projection: the stable step is not lowered
    disc = discretize(scene, method) if disc is None else disc
    if getattr(disc, "images", None) is not None:
        raise ValueError(f"scene {scene.name!r}: dynamic EFG runs of half and quarter models "
                         "(symmetry) are not supported (the image nodes are tied in static solves "
                         "only); model the whole body")
    timings = {}
    t0 = time.perf_counter()
    mat = scene.material
    test = getattr(disc, "test", None)  # Petrov-Galerkin test functions (MLPG), else None
    K = stiffness(disc.shape, modulus_weights(scene, disc.points.x, disc.points.w), mat.D, test=test)
    timings["stiffness"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    wr = density_weights(scene, disc.points.x, disc.points.w)  # graded: int rho(x) = rho sum wr
    m = row_sum_mass(disc.shape, wr, mat.rho, node_x=disc.nodes.x, test=test,
                     area=scene.domain.area if scene.grading is None else float(wr.sum()),
                     enrichment=enrichment_mass)
    timings["mass"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    parts = _load_scenes(scene)
    F = np.column_stack([loads(replace(disc, scene=s)) for s, _ in parts]) if parts \
        else np.zeros((disc.n_dofs, 0))
    histories = tuple(g for _, g in parts)
    timings["loads"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    minv = 1.0 / m
    zero = np.zeros(disc.n_dofs)
    f_bc, projection = zero, None
    fixed, fixed_values = np.zeros(0, int), np.zeros(0)
    Q = None
    if scene.supports:
        h = method.spacing
        still = replace(disc, scene=still_scene(scene))  # moving supports at 0: q_0
        var = method.bc == "variational"
        if method.bc == "modified_mls":
            fixed, fixed_values = eliminated_dofs(still)
            minv[fixed] = 0.0
            Q, qh = split_values(scene, lambda s: eliminated_dofs(replace(disc, scene=s))[1])
        else:
            K0 = K

            def constrained(d):
                bc = essential_conditions(d, derivatives=var)
                if method.bc == "penalty":
                    return penalty(K0, zero, bc, (method.penalty or DEFAULT_PENALTY) * mat.E / h,
                                   disc.nodes.x, check=False)
                if var:
                    beta = (method.penalty or DEFAULT_STABILISATION) * mat.E / h
                    return modified_variational(K0, zero, bc, mat.D, beta, disc.nodes.x, check=False)
                return lagrange(K0, zero, bc, disc.nodes.x, check=False)

            lin = constrained(still)
            n = disc.n_dofs
            Q, qh = split_values(scene, lambda s: constrained(replace(disc, scene=s)).b[n:]
                                 if method.bc == "lagrange" else constrained(replace(disc, scene=s)).b)
            if method.bc == "lagrange":
                projection = Projection.build(csr_array(lin.blocks[1]), lin.b[n:], minv)
            else:  # the forcing of moving supports: load columns with their histories
                K, f_bc = lin.A, lin.b
                if Q is not None:
                    F, histories, Q = np.column_stack([F, Q]), histories + qh, None
    timings["constraints"] = time.perf_counter() - t0
    return Dynamics(disc, _int32(csr_array(K)), m, minv, F, histories, f_bc, projection, fixed,
                    fixed_values, method.bc, timings, Q, qh if Q is not None else ())


def local_dynamics(scene: Scene, method: MLPG, disc: Discretization | None = None,
                   enrichment_mass: str = "diagonal") -> Dynamics:
    """``M u'' + K u = f(t)`` of MLPG1 or of the Galerkin form of its trial functions
    (``method.explicit_form``; module docstring; called by :func:`dynamics`).
    ``enrichment_mass``: the Galerkin form's enrichment unknowns, as for EFG.

    Raises
    ------
    ValueError
        An enriched MLPG1 (its Galerkin enrichment rows have no sub-domain mass); the
        Galerkin form takes the enrichment.
    """
    refuse_grading(scene, "explicit MLPG")
    # "auto": the Galerkin form, its trial functions (before for_scene's enrichment), a warning
    method = resolve_form(method, cracked=bool(scene.cracks), trial=disc is None).for_scene(scene)
    if method.enrichment != "none" and method.explicit_form == "petrov_galerkin":
        raise ValueError(f"method.enrichment={method.enrichment!r}: explicit MLPG1 "
                         "(explicit_form='petrov_galerkin') runs without tip enrichment only "
                         "(its enrichment rows are Galerkin rows over the field quadrature and "
                         "have no lumped mass on the sub-domains); give MLPG(..., "
                         "enrichment='none'), the Galerkin form (explicit_form='galerkin', the "
                         "default of explicit runs) or EFG")
    if disc is None:  # the trial weight of explicit runs (MLPG.explicit_weight)
        method = explicit_mlpg(method)
    disc = discretize_local(scene, method) if disc is None else disc
    mat, timings = scene.material, {}
    t0 = time.perf_counter()
    alpha = None
    if method.bc == "penalty" and scene.supports:
        alpha = (method.penalty or DEFAULT_MLPG_PENALTY) * mat.E / method.spacing
    parts = _load_scenes(scene)
    histories = tuple(g for _, g in parts)
    if method.explicit_form == "galerkin":  # symmetric: efgkit.explicit.galerkin_form
        disc, K, m, F, f_bc, Q, qh = galerkin_system(scene, disc, parts, alpha, enrichment_mass)
        if Q is not None:  # moving penalty supports: load columns with their histories
            F, histories, Q, qh = np.column_stack([F, Q]), histories + qh, None, ()
        timings["stiffness"] = time.perf_counter() - t0  # with mass and loads
        alpha, t0 = None, time.perf_counter()
    else:
        K, _ = local_system(disc, alpha)
        timings["stiffness"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        m = row_sum_mass(disc.shape, disc.points.w, mat.rho, node_x=disc.nodes.x, test=disc.test)
        timings["mass"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        F = np.column_stack([local_loads(disc, None, s) for s, _ in parts]) if parts \
            else np.zeros((disc.n_dofs, 0))
        f_bc = np.zeros(disc.n_dofs)
        Q, qh = None, ()
    if alpha is not None:  # the prescribed values of the penalty term: forcing
        quiet = [replace(c, pressure=0.0) for c in scene.cracks]

        def pen(s):
            return local_loads(disc, alpha, replace(s, tractions=(), body_force=None, cracks=quiet))
        f_bc = pen(still_scene(scene))
        Q, qh = split_values(scene, pen)
        if Q is not None:  # moving supports: load columns with their histories
            F, histories, Q, qh = np.column_stack([F, Q]), histories + qh, None, ()
    timings["loads"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    minv = 1.0 / m
    projection, fixed, fixed_values = None, np.zeros(0, int), np.zeros(0)
    still = replace(disc, scene=still_scene(scene))
    if scene.supports and method.bc == "modified_mls":
        fixed, fixed_values = eliminated_dofs(still)
        minv[fixed] = 0.0
        Q, qh = split_values(scene, lambda s: eliminated_dofs(replace(disc, scene=s))[1])
    elif scene.supports and method.bc == "collocation":
        rows, vals, _ = collocation_rows(still)
        projection = Projection.build(csr_array(rows), vals, minv)
        Q, qh = split_values(scene, lambda s: collocation_rows(replace(disc, scene=s))[1])
    timings["constraints"] = time.perf_counter() - t0
    return Dynamics(disc, _int32(csr_array(K)), m, minv, F, histories, f_bc, projection, fixed,
                    fixed_values, method.bc, timings, Q, qh, form=method.explicit_form)


def _int32(K: csr_array) -> csr_array:
    """K with 32-bit column indices when they fit: ``K @ u`` reads a third less memory
    (the product bounds the step)."""
    if K.nnz >= 2**31 - 1 or K.indices.dtype == np.int32:
        return K
    return csr_array((K.data, K.indices.astype(np.int32), K.indptr.astype(np.int32)), shape=K.shape)


def solution_at(dyn: Dynamics, coeffs: np.ndarray, t: float, info: dict | None = None) -> MeshlessSolution:
    """The fields of coefficients ``coeffs (n_dofs,)`` as a :class:`MeshlessSolution`."""
    return MeshlessSolution(dyn.disc, np.asarray(coeffs, float), {"t": t, **(info or {})}, {})
