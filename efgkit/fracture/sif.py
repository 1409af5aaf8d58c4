"""Stress intensity factors of a tip with a domain-independence verdict.

:func:`tip_result` evaluates the domain integrals of
:mod:`efgkit.fracture.integrals` over several domains about a tip and reports
their mean and spread, with warnings when a domain leaves the body, crosses
another crack, holds another tip or a kink, or when the spread is large.
:func:`default_radii` chooses the domains (seed 001 Sects. 7 and 10: >= 10 spacings).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace

import numpy as np

from ..problem.crack import FACE_OFFSET, Tip
from .integrals import SIF, FaceLoad, contract, domain_integrands
from .qfunctions import QFunction

__all__ = ["TipResult", "default_radii", "face_loads", "tip_radii", "tip_result"]


# measured on examples/edge_crack.toml against the tip's interaction-integral KI, KII
ENRICHMENT_NOTE = (
    "KI, KII here are the coefficients of the extrinsic MLS enrichment fields (seed 003 Eq. 46), "
    "not stress intensity factors: once enrich_radius is set they differ from the tip's "
    "interaction-integral KI, KII by several per cent (edge_crack example: up to 6.5 % in KI and "
    "12 % in KII for enrich_radius 0.5-2). Use the tip's KI and KII.")


@dataclass(frozen=True)
class TipResult:
    """K_I, K_II, J and T of one tip, averaged over several domains.

    Attributes
    ----------
    tip : Tip
    KI, KII, J, T : float
        Means over the domains.
    spread : float
        ``max(ptp(K_I), ptp(K_II)) / |K|`` over the domains, with ``|K|`` the
        norm ``hypot(K_I, K_II)`` of the means (of the largest domain value if
        the means vanish; 0 if every K is 0): the relative max-minus-min of the
        stress intensity factors, 0 for a domain-independent result.
    domains : tuple of SIF
        Per-domain results, by increasing radius.
    warnings : tuple of str
        Texts of the warnings issued while computing this result.
    enriched : (float, float) or None
        The coefficients of the extrinsic MLS enrichment fields (seed 003 Eq. 46):
        K_I, K_II only without a ramp; once ``enrich_radius`` is set they differ from
        the integral values by several per cent (:data:`ENRICHMENT_NOTE`).
    error : float or None
        Estimated relative discretisation error of K,
        ``max(|dK_I|, |dK_II|) / |K|`` against a solve at twice the spacing, and at
        least ``spread`` (:meth:`efgkit.solution.Solution.sifs`); None when not
        estimated.
    """

    tip: Tip
    KI: float
    KII: float
    J: float
    T: float
    spread: float
    domains: tuple[SIF, ...]
    warnings: tuple[str, ...] = ()
    enriched: tuple[float, float] | None = None
    error: float | None = None

    def as_dict(self) -> dict:
        """JSON-ready: ``id, x, y, KI, KII, J, T, spread, error, domains, warnings`` and,
        with extrinsic MLS enrichment, ``enrichment_coefficients`` (``KI``, ``KII`` and a
        note that they are not stress intensity factors)."""
        out = {"id": self.tip.id, "x": float(self.tip.x[0]), "y": float(self.tip.x[1]),
               "KI": self.KI, "KII": self.KII, "J": self.J, "T": self.T, "spread": self.spread,
               "error": self.error,
               "domains": [{"radius": d.radius, "KI": d.KI, "KII": d.KII, "J": d.J, "T": d.T,
                            "n_points": d.n_points} for d in self.domains],
               "warnings": list(self.warnings)}
        if self.enriched is not None:
            out["enrichment_coefficients"] = {"KI": self.enriched[0], "KII": self.enriched[1],
                                              "note": ENRICHMENT_NOTE}
        return out


def _segment_distance(p: np.ndarray, segs: np.ndarray) -> float:
    """Distance from a point (2,) to segments (m, 2, 2); inf when there are none."""
    if len(segs) == 0:
        return math.inf
    a, ab = segs[:, 0], segs[:, 1] - segs[:, 0]
    t = np.clip(np.sum((p - a) * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
    return float(np.linalg.norm(p - a - t[:, None] * ab, axis=-1).min())


def scene_tip(scene, tip: Tip) -> Tip:
    from ..problem.scene import Scene

    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(tip, Tip):
        raise TypeError(f"tip must be an efgkit.problem.crack.Tip, got {type(tip).__name__}; take it from "
                        "scene.tips")
    for t in scene.tips:
        if t.id == tip.id and np.allclose(t.x, tip.x, rtol=0, atol=1e-12 * scene.domain.size):
            return t
    raise ValueError(f"tip {tip.id} at {tip.x.tolist()} is not a tip of the scene; its tips are "
                     f"{[(t.id, t.x.tolist()) for t in scene.tips]}")


def tip_limits(scene, tip: Tip) -> dict[str, float]:
    """Distances from the tip to what a J domain must not reach."""
    own = next(c for c in scene.cracks if c.name == tip.crack)
    segs = own.segments[:-1] if tip.end == 1 else own.segments[1:]
    loc = (segs - tip.x) @ tip.rotation.T  # segments collinear with the tip's, behind it, are fine
    straight = np.all((np.abs(loc[..., 1]) <= 1e-9 * scene.domain.size) & (loc[..., 0] <= 0), axis=1)
    others = [c for c in scene.cracks if c.name != tip.crack]
    tips = [t for t in scene.tips if t.id != tip.id]
    return {"boundary": float(scene.domain.distance_to_boundary(tip.x[None])[0]),
            "kink": _segment_distance(tip.x, segs[~straight]),
            "crack": min([float(c.distance(tip.x[None])[0]) for c in others], default=math.inf),
            "tip": min([float(np.linalg.norm(t.x - tip.x)) for t in tips], default=math.inf)}


def default_radii(scene, tip: Tip, h: float, multiples=(10.0, 12.5, 15.0)) -> tuple[float, ...]:
    """J-domain radii ``multiples * h``, shrunk to fit the free disc about the tip.

    Seed 001 (Sects. 7 and 10) advises a radius of at least 10 spacings (or ~500
    points). The free radius is the distance from the tip to the domain
    boundary, another crack or tip, or a kink of its own crack; if
    ``max(multiples) h`` exceeds 0.9 of it, all radii are scaled down in
    proportion. Fewer than 10 spacings in a domain is no warning by itself: the
    error estimate of :meth:`Solution.sifs <efgkit.solution.Solution.sifs>` says
    whether the K is accurate (2.4 spacings with the automatic tip zones gave K within
    3e-5 on the singular patch; the SENT without enrichment or zones at W/40 was 1.8 %
    off with every domain over 10 spacings).

    Parameters
    ----------
    scene : Scene
    tip : Tip
    h : float
        Local node spacing (or cell size) at the tip.
    multiples : sequence of float, at least three

    Returns
    -------
    tuple of float, increasing

    Examples
    --------
    >>> from efgkit import Crack, Domain, Elastic, Scene
    >>> sc = Scene(Domain.rectangle(0, -1, 2, 1), Elastic(1.0, 0.3),
    ...            cracks=(Crack([[0.0, 0.0], [1.0, 0.0]], tips=(False, True)),))
    >>> default_radii(sc, sc.tips[0], 0.02)
    (0.2, 0.25, 0.3)
    """
    tip = scene_tip(scene, tip)
    if isinstance(h, bool) or not isinstance(h, (int, float, np.floating)) or not (
            math.isfinite(h) and h > 0):
        raise ValueError(f"h must be a finite spacing > 0, got {h!r}")
    m = np.sort(np.asarray(multiples, dtype=float))
    if m.ndim != 1 or len(m) < 3 or not np.all(np.isfinite(m) & (m > 0)):
        raise ValueError(f"multiples must be at least three positive numbers, got {multiples!r}")
    free = min(tip_limits(scene, tip).values())
    radii = m * h
    if radii[-1] > 0.9 * free:
        radii = radii * (0.9 * free / radii[-1])
    return tuple(float(r) for r in radii)


def tip_radii(scene, tip: Tip, radii, h: float):
    """The J-domain radii of one tip for ``sifs``: ``radii`` as given (a sequence, or a
    callable ``tip -> sequence``), or :func:`default_radii` with spacing ``h`` when None."""
    if radii is None:
        return default_radii(scene, tip, h)
    return radii(tip) if callable(radii) else radii


def face_loads(scene, tip: Tip, radius: float, gradient, h: float, n: int = 12) -> FaceLoad | None:
    """The pressure on the tip's crack faces within ``radius`` as a :class:`FaceLoad`.

    The faces are sampled with Gauss-Legendre in ``s`` on ``arc = s^2``
    (``n`` points per face), which integrates the ``r^-1/2`` face integrands
    of the J integral to rounding (see :class:`FaceLoad`). ``gradient(x, side)``
    returns the displacement gradient (m, 2, 2) at points ``x (m, 2)`` on the
    polyline's left (``side = +1``) or right (-1) face; ``h`` is the local
    spacing (points sit ``FACE_OFFSET h`` off the line on their face).
    Returns None when the crack carries no pressure.
    """
    crack = next(c for c in scene.cracks if c.name == tip.crack)
    if crack.pressure == 0.0:
        return None
    g, gw = np.polynomial.legendre.leggauss(n)
    smax = math.sqrt(min(radius, crack.length))
    s_ = (g + 1) / 2 * smax
    arc, w = s_**2, gw / 2 * smax * 2 * s_  # d arc = 2 s ds
    x, left = crack.points_along(arc, end=tip.end)
    up = 1.0 if tip.end == 1 else -1.0  # the polyline's left face is the tip's upper face
    parts = []
    for side in (1.0, -1.0):
        xs = x + side * FACE_OFFSET * h * left
        parts.append((xs, w, side * crack.pressure * left, gradient(xs, side),
                      np.full(n, side * up)))
    return FaceLoad(*(np.concatenate([p[i] for p in parts]) for i in range(5)))


def _q_for(q, radius: float) -> QFunction:
    if callable(q):
        out = q(radius)
        if not isinstance(out, QFunction):
            raise TypeError(f"q(radius) must return a QFunction, got {type(out).__name__}")
        return out
    return QFunction(q, radius, n=2.0 if q == "power" else None)


def _checked_radii(tip: Tip, radii) -> np.ndarray:
    """The J-domain radii sorted, ndarray (n_radii,); raises unless at least three, finite and > 0."""
    try:
        rs = np.sort(np.asarray(radii, dtype=float).reshape(-1))
    except (TypeError, ValueError) as err:
        raise TypeError(f"radii must be a sequence of numbers, got {radii!r}") from err
    if len(rs) < 3:
        raise ValueError(f"tip {tip.id}: domain independence needs at least three radii, got "
                         f"{len(rs)} ({rs.tolist()}); see default_radii")
    if not np.all(np.isfinite(rs) & (rs > 0)):
        raise ValueError(f"tip {tip.id}: radii must be finite and > 0, got {rs.tolist()}")
    return rs


def _geometry_notes(scene, tip: Tip, rs: np.ndarray) -> list[str]:
    """Warning texts (list of str) for the domains of radii ``rs (n_radii,)`` that leave the body,
    cross another crack, hold another tip or reach a kink of the tip's own crack."""
    notes = []
    lim = tip_limits(scene, tip)
    what = {"boundary": "leaves the body (reaches the domain boundary at {d:.4g})",
            "crack": "crosses another crack (at {d:.4g})", "tip": "holds another tip (at {d:.4g})",
            "kink": "reaches a kink of its own crack (at {d:.4g}); the auxiliary fields assume a "
                    "straight crack"}
    if lim["tip"] <= lim["crack"] * (1 + 1e-9):  # the other crack is reached at its tip
        lim["crack"] = math.inf
    for key, text in what.items():
        bad = rs[rs > lim[key]]
        if len(bad):
            notes.append(f"tip {tip.id}: J domain of radius {bad[0]:.4g} " + text.format(d=lim[key]))
    return notes


def _domain_sifs(x, w, stress, grad_u, tip: Tip, material, rs: np.ndarray, q, q_T,
                 faces: FaceLoad | None) -> list[SIF]:
    """The SIF of each radius of ``rs (n_radii,)`` (list of n_radii), T from ``q_T`` unless None
    or ``q``; one pass over the points of the largest disc serves every domain."""
    qs = [_q_for(q, float(R)) for R in rs]
    qs_T = [_q_for(q_T, float(R)) for R in rs] if q_T is not None and q_T != q else None
    r_max = max(f.r_out for f in qs + (qs_T or []))
    terms = domain_integrands(x, w, stress, grad_u, tip, material, r_max)
    doms = [contract(terms, f, faces) for f in qs]
    if qs_T is not None:
        doms = [replace(d, T=contract(terms, f, faces).T) for d, f in zip(doms, qs_T, strict=True)]
    return doms


def _k_spread(doms: list[SIF]) -> tuple[np.ndarray, np.ndarray, float]:
    """K_I and K_II of the domains, ndarray (n_domains,) each, and their spread (:attr:`TipResult.spread`)."""
    KI = np.array([d.KI for d in doms])
    KII = np.array([d.KII for d in doms])
    norm = math.hypot(np.mean(KI), np.mean(KII)) or float(np.max(np.hypot(KI, KII)))
    rng = max(float(np.ptp(KI)), float(np.ptp(KII)))
    spread = rng / norm if norm > 0 else 0.0
    return KI, KII, spread


def _quality_notes(scene, tip: Tip, rs: np.ndarray, doms: list[SIF], KI: np.ndarray, KII: np.ndarray,
                   spread: float, spread_tol: float, mismatch_tol: float) -> list[str]:
    """Warning texts (list of str) for a spread over ``spread_tol`` and a stress / grad_u
    mismatch over ``mismatch_tol``; ``rs, KI, KII`` ndarray (n_domains,)."""
    notes = []
    if spread > spread_tol:
        notes.append(f"tip {tip.id}: K depends on the domain: spread {spread:.3g} > spread_tol "
                     f"{spread_tol:g} over radii {np.round(rs, 6).tolist()} (K_I "
                     f"{np.round(KI, 6).tolist()}, K_II {np.round(KII, 6).tolist()})")
    worst = max(d.mismatch for d in doms)
    if worst > mismatch_tol:
        notes.append(f"tip {tip.id}: stress and grad_u disagree through the material by "
                     f"{worst:.3g} (> mismatch_tol {mismatch_tol:g}); check the plane "
                     f"({scene.material.plane!r}) and that the stress comes from grad_u")
    return notes


def tip_result(scene, tip: Tip, x, w, stress, grad_u, radii, q="wendland_c2",
               faces: FaceLoad | None = None, spread_tol: float = 0.01,
               mismatch_tol: float = 0.01, q_T="plateau",
               enriched: tuple[float, float] | None = None) -> TipResult:
    """K_I, K_II, J and T of a tip over several domains, with a domain-independence verdict.

    The domain integrals (:func:`~efgkit.fracture.integrals.domain_integrals`) of
    every radius come from one pass over the points of the largest disc
    (:func:`~efgkit.fracture.integrals.domain_integrands`, then
    :func:`~efgkit.fracture.integrals.contract` per q), and the results are
    averaged. A warning (``warnings.warn`` and :attr:`TipResult.warnings`) is
    issued when the spread exceeds ``spread_tol``, when a domain disc leaves
    the body (reaches the domain boundary), crosses another crack, holds
    another tip or a kink of the tip's own crack (the auxiliary fields assume
    a straight, isolated crack), or when the stress and ``grad_u`` disagree
    through the material by more than ``mismatch_tol`` (:attr:`SIF.mismatch`).

    Parameters
    ----------
    scene : Scene
        Gives the domain, the cracks and the material.
    tip : Tip
        One of ``scene.tips``.
    x, w, stress, grad_u :
        As in :func:`~efgkit.fracture.integrals.domain_integrals`.
    radii : sequence of float
        At least three domain radii (:func:`default_radii`).
    q : str or callable
        A :class:`QFunction` kind (``"plateau"`` with ``r_in = r_out / 2``,
        ``"power"`` with ``n = 2``), or ``radius -> QFunction``.
    faces : FaceLoad, optional
        Loaded crack faces (:func:`face_loads`).
    spread_tol, mismatch_tol : float
    q_T : str, callable or None
        Weight of the T-stress integral (None: ``q``). Its auxiliary field is
        ``O(1/r)``, so a ``q`` whose gradient is not zero near the tip makes T
        depend on the quadrature there. Measured on square 4 x 4 Gauss cells
        (20-41 cells across ``[-1, 1]^2``, ``r_out = 0.6``, ``K_I = 1``,
        ``K_II = 0.5``): T errors 3e-3 to 2e-2 with ``"wendland_c2"``,
        3e-5 to 4e-4 with ``"plateau"`` (``q = 1`` near the tip); see
        ``tests/test_integrals.py::test_cell_quadrature_accuracy``. With
        cells split at the crack and a fan rule in the tip cell both give
        ~1e-4.

    Returns
    -------
    TipResult

    Raises
    ------
    ValueError
        Fewer than three radii, a radius that is not finite and > 0, a
        domain without points (names the tip and the radius), a tip not in
        the scene.

    Examples
    --------
    The exact field ``K_I = 1``, ``K_II = 0.5`` of an edge crack's tip on a
    polar Gauss rule (as in :func:`~efgkit.fracture.integrals.domain_integrals`):

    >>> from efgkit import Crack, Domain, Elastic, Scene
    >>> from efgkit.problem.exact.williams import williams_gradient, williams_stress
    >>> sc = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
    ...            cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True)),))
    >>> t, tw = np.polynomial.legendre.leggauss(24)
    >>> s = (t + 1) / 2 * np.sqrt(0.8); r = s**2; th = np.pi * t
    >>> R, TH = [a.ravel() for a in np.meshgrid(r, th, indexing="ij")]
    >>> W = np.outer(s**3 * np.sqrt(0.8) * tw, np.pi * tw).ravel()
    >>> x = np.column_stack([R * np.cos(TH), R * np.sin(TH)])
    >>> m = sc.material
    >>> res = tip_result(sc, sc.tips[0], x, W, williams_stress(R, TH, 1.0, 0.5),
    ...                  williams_gradient(R, TH, 1.0, 0.5, m.mu, m.kappa), [0.4, 0.6, 0.8])
    >>> round(res.KI, 3), round(res.KII, 3), bool(res.spread < 1e-3), res.warnings
    (1.0, 0.5, True, ())

    (The rule is one Gauss block over ``r < 0.8``, so the kink of ``q`` at
    ``r_out < 0.8`` costs ~3e-4; tests split the rule there and get 1e-12.)
    """
    tip = scene_tip(scene, tip)
    rs = _checked_radii(tip, radii)
    notes = _geometry_notes(scene, tip, rs)
    doms = _domain_sifs(x, w, stress, grad_u, tip, scene.material, rs, q, q_T, faces)
    KI, KII, spread = _k_spread(doms)
    notes += _quality_notes(scene, tip, rs, doms, KI, KII, spread, spread_tol, mismatch_tol)
    for text in notes:
        warnings.warn(text, UserWarning, stacklevel=2)
    return TipResult(tip=tip, KI=float(np.mean(KI)), KII=float(np.mean(KII)),
                     J=float(np.mean([d.J for d in doms])), T=float(np.mean([d.T for d in doms])),
                     spread=float(spread), domains=tuple(doms), warnings=tuple(notes),
                     enriched=None if enriched is None else tuple(float(k) for k in enriched))
