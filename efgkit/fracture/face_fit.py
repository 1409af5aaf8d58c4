"""The near-tip strain energy on the crack faces from a fit of the face displacements.

The crack-face term of ``J'_2`` (seed 002 Eq. 31, :mod:`efgkit.fracture.dynamic`) holds the
strain energy density on both faces, ``-int [W] q ds`` with ``[W] = W(theta = +pi) -
W(theta = -pi)``. Near the tip each face's ``W`` grows like ``1/r`` (the ``K_II`` stress
``sigma_11 = -+2 K_II / sqrt(2 pi r)`` on the faces); the ``1/r`` parts cancel between the
faces and ``[W] = -4 K_II T / (E' sqrt(2 pi r)) + O(r^{1/2})`` is integrable (``T`` the T-stress).
A discretisation that does not represent the singularity (EFG without enrichment) has
bounded stresses at the tip that differ between the faces by ``O(K / sqrt(h))`` within a
few spacings ``h``: ``[W] ~ K^2 / h`` over a length ``~h``, an ``O(K^2 / E')`` error of
``J'_2`` that does not shrink as the grid is refined (measured: ``J'_2`` at 0.1-0.3 of its
exact value on the inclined Griffith crack at 2 to 8 spacings, and at 0.06-0.2 and 0.08-0.14
on the slanted crack of seed 002 Sect. 4.2 on 45 x 33 and 89 x 65 nodes, docs/verification.md).

Here the faces within ``r0`` of the tip take ``W`` from the asymptotic form of the face
displacement, fitted where the discretisation resolves it (Eischen, Eng. Fract. Mech. 26,
1987, fitted the near-tip expansion to the crack-face displacements for the same purpose).
On the faces ``theta = +-pi`` the Williams expansion gives, in the tip frame
(``x_1 = -r`` on the faces)::

    u_1(r, +-pi) = c_0 + c_2 r +- (c_1 r^{1/2} + c_3 r^{3/2}) + ...

(on the faces ``u_1`` of the half-integer terms is their mode-II part, opposite on the two
faces; that of the integer terms their mode-I part, the same on both: ``r`` is the
T-stress, ``c_0`` a translation; a rotation gives no ``u_1`` on the crack line). The fit on
``r`` in ``[r0, r1]`` (least squares, both faces together, ``FIT_WINDOW`` spacings) gives
``epsilon_11 = du_1/dx_1 = -du_1/dr`` on each face, and with the applied traction
(``sigma_22``, ``sigma_12`` on the face) the stress and ``W = sigma : C : sigma / 2``. The
``1/r`` parts of ``W`` cancel exactly between the faces (the same ``c_1^2``); on free faces
``[W] = 2 E' (c_1 / (2 sqrt r) + 3 c_3 sqrt(r) / 2) c_2``. (A free ``r^{3/2}`` coefficient
per face adds a spurious constant to ``[W]``: +10 % in ``J'_2``.)

The domain term goes with it: :data:`efgkit.explicit.dsif.PLATEAU_FIT`, ``q = 1`` within
``r0``, keeps the unresolved near-tip field out of it too. Measured on the inclined
Griffith crack (45 degrees, a uniform stress ``T0 = 0, +-1`` along the crack, EFG without
enrichment, ``h = 0.1 a`` and ``0.05 a``, discs of 4-8 spacings): ``J'_2`` within 0.97-1.01
of ``-2 K_I K_II / E'`` and path independent to 0.5-0.9 %, where the raw face ``W`` gives
0.1-0.3 of it (tests/test_face_fit.py, docs/theory.md).

Only ``W`` is taken from the fit: the traction term ``-t_i u_i,k`` and the kinetic energy
on the faces keep their point values (bounded integrands, errors that vanish with ``h``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array, vstack

from ..problem.crack import FACE_OFFSET, Tip
from ..problem.frames import rotate_vectors
from ..problem.material import Elastic
from .faces import FaceLoad
from .qfunctions import QFunction
from .sif import tip_limits

__all__ = ["FIT_WINDOW", "N_FACE", "N_FIT", "FaceFit", "face_energy", "face_fit_energy", "face_operators",
           "fit_face_displacement", "fit_operator", "near_tip_energy", "plateau_q"]

FIT_WINDOW = (1.5, 6.0)  # [r0, r1] in local spacings: W from the fit below r0 (measured, module doc)
N_FIT = 16  # sample points per face in the window
FIT_TERMS = (2, 2)  # (n_sym, n_anti): c_0 + c_2 r, +-(c_1 r^{1/2} + c_3 r^{3/2})
# Face points per face for J' with the fit (Gauss in sqrt(r) over the largest disc): the
# integrand breaks at r0 (fit / point values) and the plateau q there; measured J'_2 on the
# inclined crack (tests/test_face_fit.py): 0.87 of exact with 12 points, 0.97-0.98 with 24 to 96
N_FACE = 48


def _basis(r: np.ndarray, terms: tuple[int, int]) -> np.ndarray:
    """Columns of the fit (2 m, n_sym + n_anti) for ``r (m,)``: rows of the upper face, then
    the lower: ``r^0, r^1, ...`` (the same on both faces, ``n_sym``), then ``+-r^{1/2},
    +-r^{3/2}, ...`` (opposite, ``n_anti``)."""
    r = np.asarray(r, dtype=float)
    m = len(r)
    ns, na = terms
    A = np.zeros((2 * m, ns + na))
    for k in range(ns):
        A[:, k] = np.tile(r**k, 2)
    for k in range(na):
        p = r ** (k + 0.5)
        A[:m, ns + k], A[m:, ns + k] = p, -p
    return A


def fit_operator(r, terms: tuple[int, int] = None) -> np.ndarray:
    """The least-squares operator (n_sym + n_anti, 2 m) from the tip-frame ``u_1`` at ``r (m,)``
    on the upper face then the lower one, ``(2 m,)``, to the coefficients (module docstring;
    ``terms`` = ``(n_sym, n_anti)``, default :data:`FIT_TERMS`).

    Raises
    ------
    ValueError
        Fewer distinct radii than coefficients, or radii not finite and > 0.
    """
    terms = FIT_TERMS if terms is None else terms
    r = np.asarray(r, dtype=float).reshape(-1)
    if not np.all(np.isfinite(r) & (r > 0)) or len(np.unique(r)) < sum(terms):
        raise ValueError(f"r must hold at least {sum(terms)} distinct finite radii > 0 (the "
                         f"coefficients of the fit), got {r.tolist()}")
    return np.linalg.pinv(_basis(r, terms))


@dataclass(frozen=True)
class FaceFit:
    """The fitted face displacement ``u_1(r, +-pi)`` of a tip (module docstring).

    Attributes
    ----------
    coeffs : ndarray (n_sym + n_anti,)
        Of ``r^0, r^1, ...`` (the same on both faces), then of ``+-r^{1/2}, +-r^{3/2}, ...``
        (upper face +); the ``r^{1/2}`` one is the sliding ``K_II (kappa + 1) / (2 mu
        sqrt(2 pi))`` of the upper face.
    n_sym : int
        How many of ``coeffs`` are the symmetric ones.
    r0 : float
        Below ``r0`` the face ``W`` is taken from the fit.
    """

    coeffs: np.ndarray
    n_sym: int
    r0: float

    def strain(self, r, side) -> np.ndarray:
        """``epsilon_11 = -du_1/dr`` (tip frame) at ``r (m,)`` on the faces ``side (m,)`` (+1 upper)."""
        r = np.asarray(r, dtype=float)
        side = np.asarray(side, dtype=float)
        ns = self.n_sym
        d = np.zeros_like(r)
        for k in range(1, ns):
            d += k * self.coeffs[k] * r ** (k - 1)
        for k, c in enumerate(self.coeffs[ns:]):
            d += side * (k + 0.5) * c * r ** (k - 0.5)
        return -d


def fit_face_displacement(r, u1_upper, u1_lower, r0: float, terms: tuple[int, int] = None) -> FaceFit:
    """:class:`FaceFit` from the tip-frame ``u_1`` at ``r (m,)`` on the upper and lower face
    (each ``(m,)``); ``r0``: below it the fit gives the face ``W``; ``terms``: ``(n_sym,
    n_anti)`` (default :data:`FIT_TERMS`)."""
    terms = FIT_TERMS if terms is None else terms
    op = fit_operator(r, terms)
    u = np.concatenate([np.asarray(u1_upper, float).reshape(-1), np.asarray(u1_lower, float).reshape(-1)])
    if u.shape != (op.shape[1],) or not np.all(np.isfinite(u)):
        raise ValueError(f"u1_upper and u1_lower must be finite, one value per radius ({len(r)}), "
                         f"got {u.shape[0]} values")
    if not (math.isfinite(r0) and r0 > 0):
        raise ValueError(f"r0 must be finite and > 0, got {r0!r}")
    return FaceFit(op @ u, terms[0], float(r0))


def face_energy(eps11, traction, side, material: Elastic) -> np.ndarray:
    """``W`` (m,) on crack-face points from ``epsilon_11`` (m,) along the face and the applied
    traction ``(m, 2)`` (tip frame; the body's outward normal is ``-side e_2``), so that
    ``sigma_12 = -side t_1``, ``sigma_22 = -side t_2`` and ``sigma_11`` follows from Hooke's
    law (``material.D``, plane stress or strain): ``W = sigma . C sigma / 2``."""
    C = np.linalg.inv(material.D)  # Voigt compliance (engineering shear)
    side = np.asarray(side, dtype=float)
    s22, s12 = -side * traction[:, 1], -side * traction[:, 0]
    s11 = (eps11 - C[0, 1] * s22 - C[0, 2] * s12) / C[0, 0]
    sig = np.column_stack([s11, s22, s12])
    return 0.5 * np.einsum("mi,ij,mj->m", sig, C, sig)


def near_tip_energy(fit: FaceFit, faces: FaceLoad, tip: Tip, material: Elastic) -> np.ndarray:
    """``W`` (m,) at the face points of ``faces`` closer than ``fit.r0`` to ``tip`` from the fit
    (:func:`face_energy` with their tractions), NaN at the others: the ``energy`` of a
    :class:`~efgkit.fracture.faces.FaceLoad`."""
    d = (faces.x - tip.x) @ tip.rotation.T
    r = np.hypot(d[:, 0], d[:, 1])
    near = r < fit.r0
    out = np.full(len(r), np.nan)
    if np.any(near):
        t = rotate_vectors(faces.traction[near], -tip.angle)
        out[near] = face_energy(fit.strain(r[near], faces.side[near]), t, faces.side[near], material)
    return out


def face_operators(disc, scene, tip: Tip, crack, h: float):
    """``(r (N_FIT,), r0, (upper, lower))``: the radii of the face-displacement fit of a tip,
    its ``r0`` and the value operators ``(2 N_FIT, n_dofs)`` (x components, then y) of the
    discretisation ``disc`` on the upper and lower face; None when the free distance about
    the tip (:func:`~efgkit.fracture.sif.tip_limits`, and the crack's length) leaves no room
    for two spacings of window beyond ``r0``."""
    r0 = FIT_WINDOW[0] * h
    r1 = min(FIT_WINDOW[1] * h, 0.9 * min(min(tip_limits(scene, tip).values()), crack.length))
    if r1 < r0 + 2 * h:
        return None
    r = np.linspace(r0, r1, N_FIT)
    x, left = crack.points_along(r, end=tip.end)
    up = 1.0 if tip.end == 1 else -1.0  # the polyline's left face is the tip's upper face
    ops = tuple(csr_array(vstack(list(disc.shape_at(x + s * up * FACE_OFFSET * h * left,
                                                    derivatives=False).u_operators()), format="csr"))
                for s in (1.0, -1.0))
    return r, r0, ops


def plateau_q(h: float):
    """``radius -> QFunction``: the plateau q that goes with the fit at a tip of spacing ``h``,
    ``q = 1`` within ``min(FIT_WINDOW[0] h, R / 2)`` (``DynamicDSIF(q="plateau_fit")``)."""
    return lambda R: QFunction("plateau", R, r_in=min(FIT_WINDOW[0] * h, 0.5 * R))


def face_fit_energy(operators, u: np.ndarray, faces: FaceLoad, tip: Tip, material: Elastic) -> np.ndarray:
    """:func:`near_tip_energy` of the fit of the face displacement of the coefficients ``u``
    ``(n_dofs,)``, sampled by ``operators`` (:func:`face_operators`): ``W`` (m,) at the face
    points of ``faces`` within ``r0`` of ``tip``, NaN at the others."""
    r, r0, ops = operators
    u1 = [rotate_vectors((op @ u).reshape(2, -1).T, -tip.angle)[:, 0] for op in ops]
    return near_tip_energy(fit_face_displacement(r, u1[0], u1[1], r0), faces, tip, material)
