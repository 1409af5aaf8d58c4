"""Dynamic stress intensity factors at the output instants of an explicit run: the hook.

:func:`~efgkit.explicit.integrate.integrate` calls ONE function at every output instant,
``dsif(dyn, u, v, a, t) -> {estimate: ndarray (n_tips, 2)}`` (one row per tip of
``scene.tips``), with the MLS coefficients of the displacement ``u``, velocity ``v`` and
acceleration ``a`` at ``t`` (each ``(n_dofs,)``).

The default, :data:`dynamic_dsif` (a :class:`DynamicDSIF`), evaluates for a stationary
crack, side by side (seed 002 Eqs. 31-38, seed 000 Eqs. 5.2-5.8):

* ``"J"``: ``K_I``, ``K_II`` from the dynamic ``J'_1``, ``J'_2`` (Nishioka and Atluri,
  domain form with the inertia term ``rho u''_i u_i,k q`` and the crack-face terms; at
  ``V = 0`` the kinetic terms cancel, so no velocity is needed) through the velocity
  functions at ``V = 0`` (:func:`~efgkit.fracture.dynamic_tip.dynamic_tip_result`);
* ``"interaction"``: the interaction integral with the inertia term;
* ``"stress_0"``, ``"stress_0_fit"``, ``"stress_90"``: the near-tip stresses on theta = 0
  (the seed's mean of the two nearest points, and a fit extrapolated to the tip) and 90
  degrees (:mod:`efgkit.explicit.near_tip`);
* ``"J_prime"``: ``(J'_1, J'_2)`` themselves (tip frame, mean over the domains);
* ``"spread"``: ``(spread_J, spread)``, the domain spreads of the ``J'`` and the
  interaction ``K`` (:class:`~efgkit.fracture.dynamic_tip.DynamicTipResult`).

The face ``W`` of ``J'_2`` within 1.5 spacings of the tip is the fitted face displacement's
(``face_fit``, :mod:`efgkit.fracture.face_fit`), with ``q="plateau_fit"``.

With ``decomposition=True`` also ``"J_decomposed"``: ``K_I``, ``K_II`` from ``J'_1`` of the
symmetric and antisymmetric parts of the field about the crack line
(:mod:`efgkit.fracture.decomposition`), which needs no ``J'_2`` and its face term.

:func:`quasi_static_dsif` keeps the static estimates on the current displacement (no
inertia term), for comparison.

The operators the estimates need (displacement gradients and values at the quadrature
points inside each tip's largest J domain, at the near-tip ray points and on loaded crack
faces) are built at the first call for a run and kept (:class:`TipOperators`): each later
call is a few sparse products and the domain integrals over those points, no search.

*Acceleration of the inertia term.* ``mass_iterations`` Jacobi steps move the driver's
lumped-mass acceleration towards the consistent-mass one, which balances the discrete
stresses in the weak sense the domain form of ``J'`` relies on
(:mod:`efgkit.explicit.acceleration_recovery`); MLPG1 keeps the driver's.

Crack-face pressure acts from ``t = 0`` on (a Heaviside step, like every load without a
history: ``explicit.system``), so the face traction of ``J'`` is the pressure itself.
"""

from __future__ import annotations

import warnings
import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy.sparse import csr_array, vstack

from ..fracture.decomposition import decomposed_tip_result, mirror_points
from ..fracture.dynamic_tip import dynamic_tip_result
from ..fracture.face_fit import FIT_WINDOW, N_FACE, face_fit_energy, face_operators, plateau_q
from ..fracture.integrals import FaceLoad
from ..fracture.sif import face_loads, tip_limits, tip_radii, tip_result
from ..problem.material import strain_from_gradient
from ..problem.scene import evaluate_vector
from .acceleration_recovery import AccelerationRecovery
from .near_tip import NEAR_TIP_ESTIMATES, NearTipRays

__all__ = ["DYNAMIC_ESTIMATES", "PLATEAU_FIT", "DynamicDSIF", "TipOperators", "dynamic_dsif",
           "quasi_static_dsif"]

DYNAMIC_ESTIMATES = ("J", "interaction", *NEAR_TIP_ESTIMATES, "J_prime", "spread")

_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
PLATEAU_FIT = "plateau_fit"  # the q of DynamicDSIF that goes with the face fit (its docstring)


def _grad_op(disc, x) -> csr_array:
    """Rows (d ux/dx, d ux/dy, d uy/dx, d uy/dy) x points -> coefficients, (4 m, n_dofs)."""
    return csr_array(vstack(list(disc.shape_at(x, derivatives=True).grad_operators()), format="csr"))


def _grad(op: csr_array, u: np.ndarray) -> np.ndarray:
    """(m, 2, 2) displacement gradients from an operator of :func:`_grad_op`."""
    m = op.shape[0] // 4
    return (op @ u).reshape(2, 2, m).transpose(2, 0, 1)


class TipOperators:
    """For every tip of a discretisation: its J-domain radii (``radii`` as in
    :func:`~efgkit.fracture.sif.tip_radii`; None: the defaults of :meth:`Solution.sifs`),
    the quadrature points within the largest, and the gradient and value operators there,
    on the rays theta = 0, 90 degrees (1-6 spacings, within the free disc) and on loaded faces."""

    def __init__(self, dyn, radii=None):
        disc = dyn.disc
        scene = disc.scene
        x, w = disc.post_points.x, disc.post_points.w  # the field quadrature (MLPG: not the discs)
        self.D = scene.material.D
        self.tips = []
        for tip in scene.tips:
            k = int(np.argmin(np.hypot(*(disc.nodes.x - tip.x).T)))
            h = float(disc.nodes.radius[k] / disc.method.d_max)  # as MeshlessSolution.tip_spacing
            rs = tuple(float(r) for r in tip_radii(scene, tip, radii, h))
            sel = np.flatnonzero(np.hypot(*(x - tip.x).T) <= max(rs) * (1 + 1e-9))
            nodal = disc.post_shape  # rows of the domain points: products restricted to ``sel``
            ops = [csr_array(g[sel]) for g in nodal.grad_operators()]
            vals = [csr_array(g[sel]) for g in nodal.u_operators()]
            rays = NearTipRays(disc, tip, h, min(tip_limits(scene, tip).values()), self.D)
            faces = {}

            def gradient(xs, side, faces=faces):  # records the face operators at the first call
                faces[side] = _grad_op(disc, xs)
                return np.zeros((len(xs), 2, 2))

            # Face points on every tip (J'_2 carries W on unloaded faces too): sampled as
            # for a unit pressure, the traction scaled by the crack's own pressure.
            crack = next(c for c in scene.cracks if c.name == tip.crack)
            unit = scene.with_cracks([replace(c, pressure=1.0) if c is crack else c
                                      for c in scene.cracks])
            f0 = face_loads(unit, tip, max(rs), gradient, h, n=N_FACE)
            f0 = replace(f0, traction=crack.pressure * f0.traction)
            self.tips.append(dict(tip=tip, h=h, rs=rs, x=x[sel], w=w[sel],
                                  op=csr_array(vstack(ops, format="csr")),
                                  val=csr_array(vstack(vals, format="csr")), rays=rays,
                                  faces=faces, face0=f0, loaded=crack.pressure != 0.0,
                                  crack=crack))
        self.scene = scene
        self.dyn = dyn
        self.fit_warned = False  # DynamicDSIF warns once per run about tips without the fit
        self.recovery = AccelerationRecovery(dyn, [d["tip"].x for d in self.tips],
                                             [max(d["rs"]) for d in self.tips])
        enr = disc.approx.enrichment
        self.n_nodes = disc.nodes.n
        self.extrinsic = enr is not None and enr.kind == "extrinsic_mls"

    def recovered_acceleration(self, a: np.ndarray, iterations: int) -> np.ndarray:
        """The driver's acceleration ``a (n_dofs,)`` after ``iterations`` Jacobi steps towards the
        consistent-mass one (:class:`~efgkit.explicit.acceleration_recovery.AccelerationRecovery`)."""
        return self.recovery(a, iterations)

    def _mirror(self, d: dict) -> tuple[csr_array, csr_array]:
        """Gradient and value operators at the reflections of the tip's domain points across
        its crack line (built at the first call); the domain must be clear of the boundary,
        kinks and other cracks, so that the reflections lie in the body on the other face."""
        if "mirror" not in d:
            lim = tip_limits(self.scene, d["tip"])
            if max(d["rs"]) > min(lim.values()):
                raise ValueError(f"tip {d['tip'].id}: the decomposition needs J domains clear of "
                                 f"the boundary, kinks and other cracks (largest radius "
                                 f"{max(d['rs']):.4g}, free distances {lim}); give smaller radii")
            sh = self.dyn.disc.shape_at(mirror_points(d["x"], d["tip"]), derivatives=True)
            d["mirror"] = (csr_array(vstack(list(sh.grad_operators()), format="csr")),
                           csr_array(vstack(list(sh.u_operators()), format="csr")))
        return d["mirror"]

    def fit_operators(self, d: dict):
        """The tip's face-fit operators (:func:`~efgkit.fracture.face_fit.face_operators`; None
        without room for the window), built at the first call: hooks without the fit skip them."""
        if "fit" not in d:
            d["fit"] = face_operators(self.dyn.disc, self.scene, d["tip"], d["crack"], d["h"])
        return d["fit"]

    def _faces(self, d: dict, u: np.ndarray, fit: bool = False) -> FaceLoad:
        """The tip's face points with their tractions and the gradients of ``u`` there; with
        ``fit`` also ``W`` near the tip from the fitted face displacement
        (:mod:`efgkit.fracture.face_fit`; where the tip has room for the fit window)."""
        grads = np.concatenate([_grad(d["faces"][s], u) for s in (1.0, -1.0)])
        f = replace(d["face0"], grad_u=grads)
        if fit and self.fit_operators(d) is not None:
            f = replace(f, energy=face_fit_energy(d["fit"], u, f, d["tip"], self.scene.material))
        return f

    def estimates(self, u: np.ndarray) -> dict:
        """``{"interaction", "stress_0", "stress_0_fit", "stress_90"}: (n_tips, 2)`` for
        coefficients ``u`` (static integrals, no inertia)."""
        n = len(self.tips)
        out = {k: np.zeros((n, 2)) for k in ("interaction", *NEAR_TIP_ESTIMATES)}
        for k, d in enumerate(self.tips):
            grad = _grad(d["op"], u)
            stress = strain_from_gradient(grad) @ self.D.T
            kk = None
            if self.extrinsic:
                i = 2 * self.n_nodes + 2 * k
                kk = tuple(u[i:i + 2])
            res = tip_result(self.scene, d["tip"], d["x"], d["w"], stress, grad, d["rs"],
                             faces=self._faces(d, u) if d["loaded"] else None, enriched=kk)
            out["interaction"][k] = (res.KI, res.KII)
            for key, v in d["rays"].estimates(u).items():
                out[key][k] = v
        return out

    def dynamic(self, u: np.ndarray, a: np.ndarray, t: float, q="wendland_c2",
                inertia: bool = True, face_terms: bool = True, domains: bool = False,
                mass_iterations: int = 0, decomposition: bool = False,
                face_fit: bool = True) -> dict:
        """The :data:`DYNAMIC_ESTIMATES` ``(n_tips, 2)`` each for displacement ``u`` and
        acceleration ``a`` (coefficients) at ``t``, stationary tips (``V = 0``); with
        ``domains`` also ``"J_prime_domains"`` ``(n_tips, n_radii, 2)``: ``J'_1``, ``J'_2``
        of each domain, by increasing radius (all tips need the same number of radii).

        ``inertia=False`` drops the acceleration (the static integrand) and
        ``face_terms=False`` the crack-face terms: both only to show what they contribute.
        ``face_fit``: ``W`` of the ``J'_2`` face term near the tip from the fitted face
        displacement (:mod:`efgkit.fracture.face_fit`); False: the raw point values.
        ``mass_iterations``: the acceleration recovery (:meth:`recovered_acceleration`).
        ``decomposition`` adds ``"J_decomposed"`` (K_I, K_II from ``J'_1`` of the symmetric
        and antisymmetric parts, :mod:`efgkit.fracture.decomposition`) and, with ``domains``,
        ``"J_decomposed_domains"`` ``(n_tips, n_radii, 2)``: ``J'_1(u^I)``, ``J'_1(u^II)``.
        """
        scene, mat = self.scene, self.scene.material
        n = len(self.tips)
        out = {k: np.zeros((n, 2)) for k in DYNAMIC_ESTIMATES}
        if decomposition:
            out["J_decomposed"] = np.zeros((n, 2))
        bf = None
        if scene.body_force is not None:
            g = scene.body_force_history
            bf = (1.0 if g is None else float(g(t)), scene.body_force)
        if inertia:
            a = self.recovered_acceleration(a, mass_iterations)
        for k, d in enumerate(self.tips):
            qk = plateau_q(d["h"]) if isinstance(q, str) and q == PLATEAU_FIT else q
            grad = _grad(d["op"], u)
            stress = strain_from_gradient(grad) @ self.D.T
            m = len(d["x"])
            acc = (d["val"] @ a).reshape(2, m).T if inertia else np.zeros((m, 2))
            b = None
            if bf is not None:
                b = bf[0] * evaluate_vector(bf[1], d["x"], np.zeros_like(d["x"]), mat)
            res = dynamic_tip_result(d["tip"], d["x"], d["w"], stress, grad, np.zeros((m, 2)), acc,
                                     None, d["rs"], mat, q=qk,
                                     faces=self._faces(d, u, face_fit) if face_terms else None,
                                     body_force=b)
            out["J"][k] = (res.KI_J, res.KII_J)
            out["interaction"][k] = (res.KI, res.KII)
            out["J_prime"][k] = (res.J1, res.J2)
            out["spread"][k] = (res.spread_J, res.spread)
            if domains:
                out.setdefault("J_prime_domains", []).append([(dd.J1, dd.J2) for dd in res.domains])
            for key, v in d["rays"].estimates(u).items():
                out[key][k] = v
            if decomposition:
                gop, vop = self._mirror(d)
                am = (vop @ a).reshape(2, m).T if inertia else np.zeros((m, 2))
                bm = None
                if bf is not None:
                    xm = mirror_points(d["x"], d["tip"])
                    bm = bf[0] * evaluate_vector(bf[1], xm, np.zeros_like(xm), mat)
                dec = decomposed_tip_result(d["tip"], d["x"], d["w"], grad, _grad(gop, u), acc, am,
                                            d["rs"], mat, q=qk, body_force=b, body_force_mirror=bm,
                                            faces=self._faces(d, u) if face_terms else None)
                out["J_decomposed"][k] = (dec.KI, dec.KII)
                if domains:
                    out.setdefault("J_decomposed_domains", []).append(
                        np.column_stack([dec.J1_I, dec.J1_II]))
        if domains:
            out["J_prime_domains"] = np.array(out["J_prime_domains"])
            if decomposition:
                out["J_decomposed_domains"] = np.array(out["J_decomposed_domains"])
        return out


def _operators(dyn, radii) -> TipOperators:
    per_run = _CACHE.get(dyn)
    if per_run is None:
        per_run = _CACHE[dyn] = {}
    key = radii if radii is None or callable(radii) else tuple(radii)
    ops = per_run.get(key)
    if ops is None:
        ops = per_run[key] = TipOperators(dyn, radii)
    return ops


@dataclass(frozen=True, eq=False)
class DynamicDSIF:
    """The dynamic SIF hook of an explicit run: ``J'``, interaction with inertia and near-tip
    stresses side by side (module docstring), for stationary cracks.

    Parameters
    ----------
    radii : sequence of float, callable or None
        J-domain radii of every tip (at least three), or ``tip -> radii``; None: 10, 12.5
        and 15 local spacings (:func:`~efgkit.fracture.sif.default_radii`).
    q : str or callable
        The q-function (:func:`~efgkit.fracture.dynamic_tip.dynamic_tip_result`), or
        ``"plateau_fit"`` (:data:`PLATEAU_FIT`): ``"plateau"`` with ``q = 1`` within ``r_in =
        min(FIT_WINDOW[0] h, r_out / 2)`` (``h`` the tip's spacing), where ``face_fit`` gives
        the face ``W``: path dependence of ``J'_2`` 0.5-0.9 % on 4-8 spacings without
        enrichment (``"wendland_c2"``: 0.4-7 %; docs/theory.md).
    domains : bool
        Also record ``"J_prime_domains"`` ``(n_tips, n_radii, 2)``, ``J'_1``, ``J'_2`` of every
        domain (path independence); default False.
    inertia, face_terms : bool
        Keep the inertia term ``rho u''_i u_i,k q`` and the crack-face terms of ``J'``
        (default). Setting either to False gives a wrong ``J'`` under dynamic load or
        loaded faces: only to show what the terms contribute (``verification/freund.py``).
    mass_iterations : int
        Jacobi steps of the acceleration recovery of the inertia term (module docstring;
        default 4; 0: the driver's lumped-mass acceleration; 16 with PU enrichment and
        ``enrichment_mass="abs_row_sum"`` on coarse grids). EFG and MLPG's Galerkin form
        (MLPG1 keeps the driver's).
    decomposition : bool
        Also give ``"J_decomposed"``: K_I, K_II from ``J'_1`` of the symmetric and
        antisymmetric parts of the field about the crack line (no ``J'_2``;
        :mod:`efgkit.fracture.decomposition`), with ``domains`` also
        ``"J_decomposed_domains"``; straight cracks, domains clear of the boundary. Default False.
    face_fit : bool
        Face ``W`` of ``J'_2`` within ``FIT_WINDOW[0]`` spacings of the tip from the fitted
        face displacement (:mod:`efgkit.fracture.face_fit`; default True); the raw values
        (False) leave an ``O(K^2 / E')`` error that refinement does not remove. A tip with
        a free distance below ``FIT_WINDOW[0] + 2`` spacings keeps the raw values (with a
        ``UserWarning`` naming the tips, once per run).

    Calling it as ``hook(dyn, u, v, a, t)`` returns ``{estimate: ndarray (n_tips, 2)}``
    for :data:`DYNAMIC_ESTIMATES`; the operators are built at the first call for a run.

    Examples
    --------
    >>> from efgkit.explicit import DynamicDSIF, integrate
    >>> hook = DynamicDSIF(radii=(0.3, 0.4, 0.5))     # integrate(..., dsif=hook)
    >>> hook.q
    'wendland_c2'
    """

    radii: Callable | tuple | None = None
    q: str | Callable = "wendland_c2"
    inertia: bool = True
    face_terms: bool = True
    domains: bool = False
    mass_iterations: int = 4
    decomposition: bool = False
    face_fit: bool = True

    def __post_init__(self):
        k = self.mass_iterations
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k <= 100:
            raise ValueError(f"mass_iterations must be an integer in 0..100 (Jacobi steps of the "
                             f"acceleration recovery; 0 keeps the lumped-mass acceleration), got {k!r}")
        if self.radii is not None and not callable(self.radii):
            try:
                rs = tuple(float(r) for r in self.radii)
            except (TypeError, ValueError) as err:
                raise TypeError(f"radii must be a sequence of numbers, a callable tip -> radii or "
                                f"None, got {self.radii!r}") from err
            if len(rs) < 3 or not all(np.isfinite(r) and r > 0 for r in rs):
                raise ValueError(f"radii must be at least three finite radii > 0 (domain "
                                 f"independence), got {list(rs)}")
            object.__setattr__(self, "radii", rs)

    def __call__(self, dyn, u: np.ndarray, v: np.ndarray, a: np.ndarray, t: float) -> dict:
        if not dyn.disc.scene.tips:
            return {}
        ops = _operators(dyn, self.radii)
        if self.face_fit and self.face_terms and not ops.fit_warned:
            ops.fit_warned = True
            short = [d["tip"].id for d in ops.tips if ops.fit_operators(d) is None]
            if short:
                warnings.warn(
                    f"DynamicDSIF(face_fit=True): tip(s) {', '.join(short)} have less than "
                    f"{FIT_WINDOW[0] + 2:g} local spacings of free distance for the fit of the "
                    "face displacement: their J'_2 face term takes the raw face W, whose error "
                    "does not shrink with refinement without enrichment "
                    "(efgkit.fracture.face_fit). Remedy: a finer spacing near the tip, or K from "
                    "the interaction integral", UserWarning, stacklevel=2)
        with warnings.catch_warnings():  # near-tip fits before the waves arrive (K = 0)
            warnings.simplefilter("ignore")
            return ops.dynamic(np.asarray(u, float), np.asarray(a, float), t, self.q,
                               self.inertia, self.face_terms, self.domains,
                               int(self.mass_iterations), bool(self.decomposition),
                               bool(self.face_fit))


dynamic_dsif = DynamicDSIF()
"""The default hook of :func:`~efgkit.explicit.integrate.integrate` (:class:`DynamicDSIF`)."""


def quasi_static_dsif(dyn, u: np.ndarray, v: np.ndarray, a: np.ndarray, t: float) -> dict:
    """Quasi-static K_I, K_II of every tip from the displacement ``u`` at ``t``.

    Estimates (each ndarray (n_tips, 2)):

    * ``"interaction"``: the static interaction integral over the default domains of
      :meth:`Solution.sifs` (10, 12.5, 15 spacings, :func:`efgkit.fracture.sif.tip_result`,
      without the error estimate); no inertia term;
    * ``"stress_0"``, ``"stress_0_fit"``, ``"stress_90"``: from the near-tip stresses on
      theta = 0 and 90 degrees, as :data:`dynamic_dsif` (:mod:`efgkit.explicit.near_tip`;
      seed 000 Eqs. 5.2-5.5).

    ``v`` and ``a`` are unused (:data:`dynamic_dsif` uses ``a``). The domain-spread warnings
    of the static integral are silenced: they fire at every instant before the waves
    arrive, where K is zero.
    """
    if not dyn.disc.scene.tips:
        return {}
    ops = _operators(dyn, None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ops.estimates(np.asarray(u, float))
