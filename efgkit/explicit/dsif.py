"""Dynamic stress intensity factors at the output instants of an explicit run: the hook.

:func:`~efgkit.explicit.integrate.integrate` calls ONE function at every output instant,
``dsif(dyn, u, v, a, t) -> {estimate: ndarray (n_tips, 2)}`` (K_I, K_II of every tip of
``scene.tips``), with the MLS coefficients of the displacement ``u``, velocity ``v`` and
acceleration ``a`` at ``t`` (each ``(n_dofs,)``). The dynamic J' of seed 002 Eqs. (31)-(38)
plugs in here (it needs ``v`` and ``a`` for the kinetic and inertia terms). Until then
:func:`quasi_static_dsif` evaluates the static estimates on the current displacement,
which omit the inertia terms.

The operators the estimates need (displacement gradients at the quadrature points inside
each tip's largest J domain, at the near-tip ray points and on loaded crack faces) are
built at the first call for a run and kept (:class:`TipOperators`): each later call is a
few sparse products and the domain integrals over those points, no search.
"""

from __future__ import annotations

import warnings
import weakref

import numpy as np
from scipy.sparse import csr_array, vstack

from ..fracture.extrapolation import near_tip_sif, ray_points
from ..fracture.sif import face_loads, tip_radii, tip_result
from ..problem.material import strain_from_gradient

__all__ = ["TipOperators", "quasi_static_dsif"]

_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _grad_op(disc, x) -> csr_array:
    """Rows (d ux/dx, d ux/dy, d uy/dx, d uy/dy) x points -> coefficients, (4 m, n_dofs)."""
    return csr_array(vstack(list(disc.shape_at(x, derivatives=True).grad_operators()), format="csr"))


def _grad(op: csr_array, u: np.ndarray) -> np.ndarray:
    """(m, 2, 2) displacement gradients from an operator of :func:`_grad_op`."""
    m = op.shape[0] // 4
    return (op @ u).reshape(2, 2, m).transpose(2, 0, 1)


class TipOperators:
    """For every tip of a discretisation: its J-domain radii (the defaults of
    :meth:`Solution.sifs`), the quadrature points within the largest, and the gradient
    operators there, on the rays theta = 0, 90 degrees (1-6 spacings) and on loaded faces."""

    def __init__(self, dyn):
        disc = dyn.disc
        scene = disc.scene
        x, w = disc.points.x, disc.points.w
        self.D = scene.material.D
        self.tips = []
        for tip in scene.tips:
            k = int(np.argmin(np.hypot(*(disc.nodes.x - tip.x).T)))
            h = float(disc.nodes.radius[k] / disc.method.d_max)  # as MeshlessSolution.tip_spacing
            rs = tip_radii(scene, tip, None, h)
            sel = np.flatnonzero(np.hypot(*(x - tip.x).T) <= max(rs) * (1 + 1e-9))
            nodal = disc.shape  # rows of the domain points: products restricted to ``sel``
            ops = [csr_array(g[sel]) for g in nodal.grad_operators()]
            r = h * np.arange(1.0, 7.0)
            rays = {th: _grad_op(disc, ray_points(tip, r, th)) for th in (0.0, np.pi / 2)}
            faces = {}

            def gradient(xs, side, faces=faces):  # records the face operators at the first call
                faces[side] = _grad_op(disc, xs)
                return np.zeros((len(xs), 2, 2))

            has_faces = face_loads(scene, tip, max(rs), gradient, h) is not None
            self.tips.append(dict(tip=tip, h=h, rs=rs, x=x[sel], w=w[sel],
                                  op=csr_array(vstack(ops, format="csr")), r=r, rays=rays,
                                  faces=faces if has_faces else None))
        self.scene = scene
        enr = disc.approx.enrichment
        self.n_nodes = disc.nodes.n
        self.extrinsic = enr is not None and enr.kind == "extrinsic_mls"

    def estimates(self, u: np.ndarray) -> dict:
        """``{"interaction", "stress_0", "stress_90"}: (n_tips, 2)`` for coefficients ``u``."""
        n = len(self.tips)
        out = {k: np.zeros((n, 2)) for k in ("interaction", "stress_0", "stress_90")}
        for k, d in enumerate(self.tips):
            grad = _grad(d["op"], u)
            stress = strain_from_gradient(grad) @ self.D.T
            faces = None
            if d["faces"] is not None:
                faces = face_loads(self.scene, d["tip"], max(d["rs"]),
                                   lambda xs, side, d=d: _grad(d["faces"][side], u), d["h"])
            kk = None
            if self.extrinsic:
                i = 2 * self.n_nodes + 2 * k
                kk = tuple(u[i:i + 2])
            res = tip_result(self.scene, d["tip"], d["x"], d["w"], stress, grad, d["rs"],
                             faces=faces, enriched=kk)
            out["interaction"][k] = (res.KI, res.KII)
            for key, th in (("stress_0", 0.0), ("stress_90", np.pi / 2)):
                s = strain_from_gradient(_grad(d["rays"][th], u)) @ self.D.T
                out[key][k] = near_tip_sif(d["tip"], d["r"], s, th)
        return out


def quasi_static_dsif(dyn, u: np.ndarray, v: np.ndarray, a: np.ndarray, t: float) -> dict:
    """Quasi-static K_I, K_II of every tip from the displacement ``u`` at ``t``.

    Estimates (each ndarray (n_tips, 2)):

    * ``"interaction"``: the static interaction integral over the default domains of
      :meth:`Solution.sifs` (10, 12.5, 15 spacings, :func:`efgkit.fracture.sif.tip_result`,
      without the error estimate); no inertia term;
    * ``"stress_0"``, ``"stress_90"``: from the near-tip stresses on theta = 0 and 90
      degrees, mean of the two points nearest the tip (seed 000 Eqs. 5.2-5.5).

    ``v`` and ``a`` are unused here (the dynamic J' needs them). The domain-spread warnings
    of the static integral are silenced: they fire at every instant before the waves
    arrive, where K is zero.
    """
    if not dyn.disc.scene.tips:
        return {}
    ops = _CACHE.get(dyn)
    if ops is None:
        ops = _CACHE[dyn] = TipOperators(dyn)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ops.estimates(np.asarray(u, float))
