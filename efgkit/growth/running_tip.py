"""What a running crack needs from an explicit run: state transfer, moving-tip SIFs, speed.

* :func:`transfer_state`: after the crack gains a segment the discretisation is rebuilt
  (nodes do not move); the displacement and velocity coefficients of the new
  discretisation are re-fitted so that its fields interpolate the old fields at the nodes
  (seed 002 Sect. 3.1: only the nodes the new segment influences change; here every
  coefficient is re-fitted, which leaves the others unchanged up to the fit tolerance).
  Split nodes are evaluated on their own face (``Nodes.face_positions``).
* :class:`MovingTipDSIF`: ``K_I``, ``K_II`` from the dynamic ``J'`` of a tip moving at speed
  ``V`` (seed 002 Eqs. 31-38, the ``W + T`` form with the velocity gradient,
  :func:`~efgkit.fracture.dynamic_tip.dynamic_tip_result`), the branch of Eq. 38 from the
  crack-opening and sliding displacements one spacing behind the tip.
* :func:`speed_fit`: crack speed as the slope of the least-squares line through 11 points,
  5 before and 5 after each (seed 000 Sect. 5.2.2).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.sparse import csc_array, csr_array
from scipy.sparse.linalg import splu

from ..explicit.dsif import TipOperators
from ..fracture.dynamic_tip import dynamic_tip_result
from ..problem.material import strain_from_gradient

__all__ = ["MovingTipDSIF", "check_speed", "copy_state", "speed_fit", "transfer_state"]

FACE_FRACTION = 1e-3  # as explicit.system.fit_coefficients: split nodes moved onto their face


def check_speed(speed: float, material, name: str = "speed") -> float:
    """``speed`` as a float after checking ``0 <= V < c_R`` (the Rayleigh speed of
    ``material``, :attr:`Elastic.c_rayleigh`): a mode-I crack cannot run at or above it
    (Freund 1990, Sect. 6.4; seed 000 Sect. 5.2.2)."""
    if isinstance(speed, bool) or not isinstance(speed, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {speed!r}")
    v = float(speed)
    cr = material.c_rayleigh
    if not (math.isfinite(v) and 0 <= v < cr):
        raise ValueError(f"{name} = {v!r} must lie in [0, c_R) with the Rayleigh speed c_R = "
                         f"{cr:.6g} of the material (same units): a crack cannot run at or above "
                         "c_R. Remedy: a smaller speed")
    return v


def transfer_state(old_disc, new_disc, *coeffs: np.ndarray) -> tuple[np.ndarray, ...]:
    """Re-fit coefficients of ``old_disc`` on ``new_disc``: for each ``c (n_dofs_old,)`` the
    ``c' (n_dofs_new,)`` with ``Phi' c' = u(x_I)``, ``u`` the old field at the new nodes
    ``x_I`` (split nodes on their own face), enrichment coefficients 0.

    One evaluation of the old shape functions and one sparse LU of the new nodal matrix
    ``Phi'_IJ = phi'_J(x_I)`` serve all fields (displacement and velocity).

    Examples
    --------
    >>> from efgkit import EFG, Crack, Domain, Elastic, Scene
    >>> from efgkit.methods.discretize import discretize
    >>> crack = Crack([[0, 1.05], [1.5, 1.05]], tips=(False, True))     # an edge crack
    >>> sc = Scene(Domain.rectangle(0, 0, 4, 2), Elastic(1.0, 0.3), cracks=(crack,))
    >>> m = EFG(spacing=0.5, enrichment="none", zones=())
    >>> old = discretize(sc, m)
    >>> new = discretize(sc.with_cracks([sc.cracks[0].extended(0.5)]), m)
    >>> c = np.zeros(old.n_dofs); c[0::2][: old.nodes.n] = 1.0    # u = (1, 0) everywhere
    >>> (c2,) = transfer_state(old, new, c)
    >>> bool(np.allclose(new.shape_at(new.nodes.x, derivatives=False).displacement(c2), [1.0, 0.0]))
    True
    """
    x = new_disc.nodes.face_positions(new_disc.approx.lines, FACE_FRACTION)
    old_shape = old_disc.shape_at(x, derivatives=False)
    n = len(x)
    phi = csc_array(csr_array(new_disc.shape_at(x, derivatives=False).phi)[:, :n])
    lu = splu(phi)
    out = []
    for c in coeffs:
        vals = old_shape.displacement(np.asarray(c, float))
        new = np.zeros(new_disc.n_dofs)
        new[0:2 * n:2] = lu.solve(vals[:, 0])
        new[1:2 * n:2] = lu.solve(vals[:, 1])
        out.append(new)
    return tuple(out)


def copy_state(old_disc, new_disc, *coeffs: np.ndarray) -> tuple[np.ndarray, ...]:
    """Carry coefficients over node by node: each node of ``new_disc`` takes the coefficients
    of the node of ``old_disc`` at its place (a node newly split by the segment: both copies
    take the coefficients of the node it was), enrichment coefficients 0. The fields change
    only where the shape functions do, near the new segment (seed 002 Sect. 3.1: only the
    nodes the new segment influences change); no solve, so no amplification by the
    conditioning of the nodal matrix ``Phi'`` (:func:`transfer_state`)."""
    from scipy.spatial import cKDTree

    xo = old_disc.nodes.face_positions(old_disc.approx.lines, FACE_FRACTION)
    xn = new_disc.nodes.face_positions(new_disc.approx.lines, FACE_FRACTION)
    d, j = cKDTree(xo).query(xn)
    tol = 2 * FACE_FRACTION * new_disc.nodes.radius
    if np.any(d > tol):
        k = int(np.argmax(d - tol))
        raise ValueError(f"node {k} at {xn[k].tolist()} of the new discretisation has no node of "
                         "the old one at its place: the nodes must not move between rebuilds")
    out = []
    for c in coeffs:
        c = np.asarray(c, float)
        new = np.zeros(new_disc.n_dofs)
        new[0:2 * len(xn):2] = c[2 * j]
        new[1:2 * len(xn):2] = c[2 * j + 1]
        out.append(new)
    return tuple(out)


def speed_fit(t, a, half: int = 5) -> np.ndarray:
    """Crack speed at each point of a crack-length history: the slope of the least-squares
    line through the ``2 half + 1`` points centred on it (seed 000 Sect. 5.2.2: 11 points,
    5 before and 5 after); the window is shifted inwards near the ends (it keeps
    ``2 half + 1`` points when there are that many). Exact for a linear ``a(t)``.

    Parameters
    ----------
    t, a : array_like (n,)
        Times (strictly increasing) and crack lengths, ``n >= 2``.
    half : int

    Returns
    -------
    ndarray (n,)

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 20)
    >>> bool(np.allclose(speed_fit(t, 3.0 + 2.5 * t), 2.5))
    True
    """
    t, a = np.asarray(t, float).ravel(), np.asarray(a, float).ravel()
    if t.shape != a.shape or len(t) < 2:
        raise ValueError(f"t and a must be 1-D of the same length >= 2, got {t.shape} and {a.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a)) and np.all(np.diff(t) > 0)):
        raise ValueError("t must be finite and strictly increasing and a finite")
    if isinstance(half, bool) or not isinstance(half, (int, np.integer)) or half < 1:
        raise ValueError(f"half must be an int >= 1 (points each side), got {half!r}")
    n = len(t)
    k = min(2 * half + 1, n)
    start = np.clip(np.arange(n) - half, 0, n - k)
    idx = start[:, None] + np.arange(k)[None, :]  # (n, k) windows
    T, A = t[idx], a[idx]
    Tc = T - T.mean(axis=1, keepdims=True)
    return (Tc * (A - A.mean(axis=1, keepdims=True))).sum(axis=1) / (Tc**2).sum(axis=1)


class MovingTipDSIF:
    """DSIF hook for ``integrate(..., dsif=...)`` with each tip moving at its own speed.

    ``hook(dyn, u, v, a, t) -> {"J": (n_tips, 2), "J_prime": (n_tips, 2), "spread":
    (n_tips, 2)}``: ``K_I``, ``K_II`` from ``J'_1``, ``J'_2`` at the speeds ``speeds[tip id]``
    (0 when absent: the stationary form, as :data:`~efgkit.explicit.dsif.dynamic_dsif`).
    A moving tip uses the ``W + T`` form of ``J'`` with the velocity and its gradient at the
    domain points; the crack faces carry no traction in the scenes it serves, so the face
    term of ``J'_1`` vanishes and is not evaluated (``J'_2`` then lacks its face term: mode I
    only, which is what the prescribed-speed and criterion runs drive). ``spread`` holds
    ``(spread_J, 0)``.

    Parameters
    ----------
    dyn : Dynamics
        The system of the current crack (operators built once per rebuild).
    speeds : dict
        ``{tip id: V}``, each checked by :func:`check_speed`.
    radii : sequence of float, optional
        J-domain radii (at least three); None: the defaults of :func:`~efgkit.fracture.sif.tip_radii`.
    """

    def __init__(self, dyn, speeds: dict | None = None, radii=None):
        self.material = dyn.disc.scene.material
        self.set_speeds(speeds or {})
        self.ops = TipOperators(dyn, radii)
        self.jump = []  # per tip: value operator at two points astride the faces, 1 spacing behind
        for d in self.ops.tips:
            tip, h = d["tip"], d["h"]
            e1 = np.array([math.cos(tip.angle), math.sin(tip.angle)])
            e2 = np.array([-e1[1], e1[0]])
            behind = tip.x - h * e1
            x = np.vstack([behind + 1e-3 * h * e2, behind - 1e-3 * h * e2])
            self.jump.append((dyn.disc.shape_at(x, derivatives=False), e1, e2))

    def set_speeds(self, speeds: dict) -> None:
        """Replace the tip speeds ``{tip id: V}`` (the operators are kept)."""
        self.speeds = {k: check_speed(v, self.material, f"speeds[{k!r}]") for k, v in speeds.items()}

    def __call__(self, dyn, u, v, a, t) -> dict:
        n = len(self.ops.tips)
        out = {k: np.zeros((n, 2)) for k in ("J", "J_prime", "spread")}
        D = self.material.D
        for k, d in enumerate(self.ops.tips):
            m = len(d["x"])
            grad = (d["op"] @ u).reshape(2, 2, m).transpose(2, 0, 1)
            stress = strain_from_gradient(grad) @ D.T
            acc = (d["val"] @ a).reshape(2, m).T
            V = self.speeds.get(d["tip"].id, 0.0)
            kw = {}
            vel = np.zeros((m, 2))
            if V > 0:
                vel = (d["val"] @ v).reshape(2, m).T
                shape, e1, e2 = self.jump[k]
                du = shape.displacement(u)
                jump = du[0] - du[1]
                kw = dict(grad_v=(d["op"] @ v).reshape(2, 2, m).transpose(2, 0, 1),
                          opening=float(jump @ e2), sliding=float(jump @ e1))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = dynamic_tip_result(d["tip"], d["x"], d["w"], stress, grad, vel, acc, None,
                                         d["rs"], self.material, speed=V, **kw)
            out["J"][k] = (res.KI_J, res.KII_J)
            out["J_prime"][k] = (res.J1, res.J2)
            out["spread"][k] = (res.spread_J, 0.0)
        return out
