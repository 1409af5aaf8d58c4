"""Loaded crack faces near a tip: :class:`FaceLoad` (points, weights, tractions and
displacement gradients on the faces) and their terms in J and in the interaction integrals
(:func:`face_terms`, the line integrals of :mod:`efgkit.fracture.integrals`); and
:func:`real_array`, the shape check of the arrays the domain integrals take.
Re-exported by :mod:`efgkit.fracture.integrals`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..problem.crack import Tip
from ..problem.frames import rotate_gradient, rotate_vectors
from ..problem.material import Elastic
from .auxiliary_fields import auxiliary_fields
from .qfunctions import QFunction

__all__ = ["AT_TIP", "FaceLoad", "face_terms", "real_array"]

AT_TIP = 1e-12  # points closer than this times r_out to the tip are at the tip


def real_array(name: str, v, shape: tuple) -> np.ndarray:
    """``v`` as a float array of ``shape`` (-1: any length, checked by the caller)."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError) as err:
        raise TypeError(f"{name} must be a real array of shape {shape}, got {type(v).__name__}") from err
    if a.ndim != len(shape) or any(s not in (-1, t) for s, t in zip(shape, a.shape, strict=True)):
        want = "(" + ", ".join("n" if s == -1 else str(s) for s in shape) + ")"
        raise ValueError(f"{name} must have shape {want}, got {a.shape}")
    return a


@dataclass(frozen=True, eq=False)
class FaceLoad:
    """Quadrature points on loaded crack faces near a tip.

    Attributes
    ----------
    x : ndarray (m, 2)
        Points on the tip's crack faces (behind the tip, on its crack line).
    w : ndarray (m,)
        Line weights (lengths).
    traction : ndarray (m, 2)
        Traction applied to the body, global components: ``sigma . n`` with
        ``n`` the body's outward normal (a pressure ``p`` on the upper face is
        ``+p e2`` of the tip frame, on the lower face ``-p e2``).
    grad_u : ndarray (m, 2, 2)
        Displacement gradient of the solution on that face, global (used by
        J; the interaction integrals need only the traction).
    side : ndarray (m,) of +1 / -1
        +1 for the upper face (``theta = +pi``, left of the crack seen from
        behind the tip), -1 for the lower face.
    energy : ndarray (m,) or None
        Strain energy density ``W`` to use at the points where it is finite
        (NaN elsewhere) instead of ``W`` of ``grad_u``: the near-tip face ``W``
        of the ``J'_2`` face term from :mod:`efgkit.fracture.face_fit`. None: from
        ``grad_u`` everywhere.

    Notes
    -----
    The face integrands behave like ``r^{-1/2}`` at the tip: use a rule that
    integrates that well. Measured for the pressurised Griffith crack
    (``r_out = a / 2``): Gauss-Legendre in ``s`` with ``r = s^2`` gives K to
    1e-14 with 8 points per face; plain Gauss-Legendre in ``r`` converges
    like ``1 / n`` (K off by 3.3% with 8 points, 0.9% with 30, 0.46% with 60).
    """

    x: np.ndarray
    w: np.ndarray
    traction: np.ndarray
    grad_u: np.ndarray
    side: np.ndarray
    energy: np.ndarray | None = None

    def __post_init__(self):
        x = real_array("FaceLoad.x", self.x, (-1, 2))
        m = len(x)
        arrays = {"x": x, "w": real_array("FaceLoad.w", self.w, (m,)),
                  "traction": real_array("FaceLoad.traction", self.traction, (m, 2)),
                  "grad_u": real_array("FaceLoad.grad_u", self.grad_u, (m, 2, 2)),
                  "side": real_array("FaceLoad.side", self.side, (m,))}
        for name, a in arrays.items():
            if not np.all(np.isfinite(a)):
                raise ValueError(f"FaceLoad.{name} must be finite; entry {np.argwhere(~np.isfinite(a))[0]}"
                                 " is not")
            object.__setattr__(self, name, a)
        if self.energy is not None:
            e = real_array("FaceLoad.energy", self.energy, (m,))
            if np.any(np.isinf(e)):
                raise ValueError("FaceLoad.energy must be finite where given (NaN: W from grad_u)")
            object.__setattr__(self, "energy", e)
        if not np.all(np.isin(arrays["side"], (-1.0, 1.0))):
            raise ValueError("FaceLoad.side must hold +1 (upper face) or -1 (lower face), got "
                             f"{np.unique(arrays['side']).tolist()}")


def face_terms(faces: FaceLoad, tip: Tip, material: Elastic, q: QFunction):
    """The crack-face terms of one tip over the domain of ``q``: the J face term
    ``-int t_i u_{i,1} q ds``, the interaction face terms (3,) ``-int t_i u^a_{i,1} q ds`` of
    the auxiliary fields (unit K_I, unit K_II, unit point force; :mod:`efgkit.fracture.integrals`)
    and ``sigma_22^0`` at the tip from the face traction nearest to it.

    Returns
    -------
    J : float
    I : ndarray (3,)
    s22 : float
    """
    Q = tip.rotation
    d = (faces.x - tip.x) @ Q.T
    r = np.hypot(d[:, 0], d[:, 1])
    inside = r < q.r_out
    tol = 1e-6 * q.r_out
    bad = inside & ((d[:, 0] > tol) | (np.abs(d[:, 1]) > tol))
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ValueError(f"face point {i} {faces.x[i].tolist()} is not on the crack line behind tip "
                         f"{tip.id} (tip-frame position {d[i].round(12).tolist()}); give crack-face "
                         "points of this tip's last segment")
    if not np.any(inside):
        return 0.0, np.zeros(3), 0.0
    qv = q.value(faces.x[inside], tip)
    t = rotate_vectors(faces.traction[inside], -tip.angle)
    g = rotate_gradient(faces.grad_u[inside], -tip.angle)
    w = faces.w[inside] * qv
    J = -np.sum(w * np.einsum("mi,mi->m", t, g[:, :, 0]))
    ri, side = r[inside], faces.side[inside]
    ok = ri > AT_TIP * q.r_out  # at the tip itself the auxiliary fields are singular
    _, ga = auxiliary_fields(ri[ok], side[ok] * np.pi, material)
    I = -np.einsum("m,mi,kmi->k", w[ok], t[ok], ga[:, :, :, 0])
    # normal stress at the tip from the face pressure nearest to it, both faces averaged
    near = [np.flatnonzero(side == s_) for s_ in (1.0, -1.0)]
    s22 = [-s_ * t[k[np.argmin(ri[k])], 1] for s_, k in zip((1.0, -1.0), near, strict=True) if len(k)]
    return J, I, float(np.mean(s22))
