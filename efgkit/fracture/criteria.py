"""Growth criteria: the maximum hoop stress kink angle, K_Ic and the Paris law.

Seed 003 Sect. 6 grows cracks without stating the direction criterion (seed README);
efgkit uses the maximum hoop (circumferential) stress criterion of Erdogan and Sih
(1963, J. Basic Eng. 85, 519-525). Near a tip, in the tip frame (x1 ahead, angles
counter-clockwise, radians),

    sigma_tt sqrt(2 pi r) = cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)],

and the crack kinks to the angle theta_c where sigma_tt is largest,
``K_I sin(theta) + K_II (3 cos(theta) - 1) = 0``. With ``t = tan(theta/2)`` this is
``2 K_II t^2 - K_I t - K_II = 0``, whose root of the maximum is the textbook

    theta_c = 2 atan((K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)),

0/0 at K_II = 0 and cancelling for |K_II / K_I| < 1e-8. Multiplying numerator and
denominator by ``K_I + S``, ``S = sqrt(K_I^2 + 8 K_II^2)``, gives the equal form without
cancellation used here,

    theta_c = -2 atan(2 K_II / (K_I + S)),

exact for K_II = 0 (theta_c = 0), ``-sign(K_II) 70.5288 degrees`` in pure mode II, and
with the sign of ``-K_II`` (a positive K_II kinks the crack clockwise). The hoop stress
there defines the equivalent mode-I factor

    K_eq = cos^2(theta_c/2) [K_I cos(theta_c/2) - 3 K_II sin(theta_c/2)]

(``2 / sqrt(3) |K_II|`` in pure mode II). A negative K_I means the faces press on each
other: the tip is *closed*, not fed to the formula (angle 0, K_eq 0).

Fatigue: the Paris law ``da/dN = C dK^m`` with ``dK = (1 - R) K_max`` (K from the
solve at the maximum load, load ratio ``0 <= R < 1``) and no growth at or below a
threshold ``dK_th`` (Paris and Erdogan 1963). Lives are integrated over a piecewise
power law of dK between samples (:func:`paris_cycles`), exact when K is a power of a
(``K = Y sigma sqrt(pi a)`` with constant Y), with adaptive steps in
:func:`paris_life`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["FatigueLife", "HoopStress", "critical_load_factor", "delta_k", "hoop_stress",
           "kink_angle", "paris_cycles", "paris_life", "paris_rate"]


def _finite(name: str, v) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {v!r}; check the solve that produced it")
    return a


def kink_angle(KI, KII) -> np.ndarray:
    """Maximum hoop stress kink angle (radians, tip frame, counter-clockwise positive).

    Parameters
    ----------
    KI, KII : float or array_like (n,)
        Stress intensity factors; ``KI >= 0`` (a negative K_I is closure: use
        :func:`hoop_stress`, which flags it). ``KI = KII = 0`` gives 0.

    Returns
    -------
    ndarray, the broadcast shape of the inputs: ``-2 atan(2 KII / (KI + S))``,
    ``S = sqrt(KI^2 + 8 KII^2)`` (module docstring).

    Raises
    ------
    ValueError
        Non-finite K, or a negative K_I.

    Examples
    --------
    >>> float(kink_angle(1.0, 0.0)), float(kink_angle(1.0, 1e-12))
    (0.0, -2e-12)
    >>> round(float(np.degrees(kink_angle(0.0, 1.0))), 4)
    -70.5288
    """
    KI, KII = np.broadcast_arrays(_finite("KI", KI), _finite("KII", KII))
    if np.any(KI < 0):
        k = int(np.argmax(np.ravel(KI) < 0))
        raise ValueError(f"KI must be >= 0 for a kink angle, got {np.ravel(KI)[k]!r} (element {k}): "
                         "a negative K_I closes the crack; use hoop_stress, which reports closure")
    # hypot avoids overflow of KI^2 + 8 KII^2; the denominator is 0 only for KI = KII = 0
    S = np.hypot(KI, math.sqrt(8.0) * KII)
    den = KI + S
    with np.errstate(invalid="ignore", divide="ignore"):
        theta = 0.0 - 2.0 * np.arctan(np.where(den > 0, 2.0 * KII / np.where(den > 0, den, 1.0), 0.0))
    return theta


@dataclass(frozen=True)
class HoopStress:
    """The maximum hoop stress criterion at n tips.

    Attributes
    ----------
    angle : ndarray (n,)
        Kink angle theta_c (radians, tip frame), 0 where closed.
    K_eq : ndarray (n,)
        Equivalent mode-I factor ``sigma_tt(theta_c) sqrt(2 pi r)``, 0 where closed.
    closed : ndarray (n,) bool
        K_I < 0 (faces in contact), or K_I = K_II = 0 (nothing drives the tip).
    """

    angle: np.ndarray
    K_eq: np.ndarray
    closed: np.ndarray


def hoop_stress(KI, KII) -> HoopStress:
    """Kink angle and equivalent K of the maximum hoop stress criterion (Erdogan-Sih).

    Closure: K_I < 0 is not fed to the formula (``closed=True``, angle 0, K_eq 0).
    K_I = 0 with K_II != 0 is pure mode II (faces touching without pressure), for
    which the criterion gives ``-sign(K_II) 70.53`` degrees and ``K_eq = 2 |K_II| /
    sqrt(3)``; K_I = K_II = 0 is reported closed.

    Parameters
    ----------
    KI, KII : float or array_like (n,)

    Returns
    -------
    HoopStress with arrays of shape (n,) (a scalar input gives shape (1,)).

    Examples
    --------
    >>> h = hoop_stress([1.0, -1.0, 0.0], [0.0, 0.5, 1.0])
    >>> h.closed.tolist(), np.round(np.degrees(h.angle), 4).tolist()
    ([False, True, False], [0.0, 0.0, -70.5288])
    >>> np.round(h.K_eq, 6).tolist()   # K_I; closed; 2 / sqrt(3)
    [1.0, 0.0, 1.154701]
    """
    KI, KII = (np.atleast_1d(a).astype(float) for a in
               np.broadcast_arrays(_finite("KI", KI), _finite("KII", KII)))
    closed = (KI < 0) | ((KI == 0) & (KII == 0))
    ki = np.where(closed, 0.0, KI)
    kii = np.where(closed, 0.0, KII)
    theta = kink_angle(ki, kii)
    c, s = np.cos(theta / 2), np.sin(theta / 2)
    K_eq = np.where(closed, 0.0, c * c * (ki * c - 3.0 * kii * s))
    return HoopStress(theta, K_eq, closed)


def critical_load_factor(K_eq, K_Ic: float) -> float:
    """Load factor ``lambda = K_Ic / max K_eq`` that brings the most critical tip to K_Ic.

    Linear elasticity: every K scales with the load, so the scene's loads times lambda
    bring the largest equivalent factor (:attr:`HoopStress.K_eq`, closed tips 0) to the
    toughness.

    Raises
    ------
    ValueError
        ``K_Ic`` not finite and > 0, or no tip with ``K_eq > 0`` (every tip closed: no
        load factor makes the crack grow).

    Examples
    --------
    >>> critical_load_factor([2.0, 4.0], K_Ic=10.0)
    2.5
    """
    if isinstance(K_Ic, bool) or not isinstance(K_Ic, (int, float, np.number)) \
            or not (math.isfinite(K_Ic) and K_Ic > 0):
        raise ValueError(f"K_Ic must be a finite number > 0 (the toughness), got {K_Ic!r}")
    K = _finite("K_eq", K_eq)
    top = float(np.max(K, initial=0.0))
    if top <= 0:
        raise ValueError(f"no tip has K_eq > 0 (K_eq = {np.ravel(K).tolist()}): every tip is "
                         "closed, no load factor brings one to K_Ic; check the load direction")
    return float(K_Ic) / top


def _check_paris(C, m, R, dK_th) -> None:
    for name, v in (("C", C), ("m", m)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.number)) \
                or not (math.isfinite(v) and v > 0):
            raise ValueError(f"Paris {name} must be a finite number > 0, got {v!r}")
    if not (isinstance(R, (int, float, np.number)) and 0 <= R < 1):
        raise ValueError(f"load ratio R = K_min / K_max must lie in [0, 1), got {R!r}; "
                         "R < 0 (compression in the cycle) is not modelled")
    if not (isinstance(dK_th, (int, float, np.number)) and math.isfinite(dK_th) and dK_th >= 0):
        raise ValueError(f"threshold dK_th must be a finite number >= 0, got {dK_th!r}")


def delta_k(K_max, R: float = 0.0) -> np.ndarray:
    """Range ``dK = (1 - R) K_max`` for K computed at the maximum load; 0 where
    ``K_max <= 0`` (closed). Shape of ``K_max``."""
    _check_paris(1.0, 1.0, R, 0.0)
    return (1.0 - R) * np.maximum(_finite("K_max", K_max), 0.0)


def paris_rate(dK, C: float, m: float, dK_th: float = 0.0) -> np.ndarray:
    """Paris law ``da/dN = C dK^m`` where ``dK > dK_th``, else 0 (never negative).

    Examples
    --------
    >>> paris_rate([5.0, 10.0], C=1e-3, m=2.0, dK_th=6.0).tolist()
    [0.0, 0.1]
    """
    _check_paris(C, m, 0.0, dK_th)
    dK = _finite("dK", dK)
    return np.where(dK > dK_th, C * np.maximum(dK, 0.0) ** m, 0.0)


def paris_cycles(a, dK, C: float, m: float) -> np.ndarray:
    """Cycles to grow through the samples ``a (n,)`` with ranges ``dK (n,)``, cumulative (n,).

    Between samples dK is taken as a power law, ``dK = dK_i (a / a_i)^p`` with
    ``p = ln(dK_i+1 / dK_i) / ln(a_i+1 / a_i)``, so that

        N_i+1 - N_i = a_i / (C dK_i^m) ln(r) expm1(x) / x,  r = a_i+1 / a_i,  x = (1 - p m) ln r,

    (``ln r`` when ``x = 0``, the m = 2 log form of ``K ~ sqrt(a)``): exact for K
    proportional to a power of a, second order otherwise. The threshold is not applied
    here (give samples above it).

    Raises
    ------
    ValueError
        ``a`` not positive and increasing, or ``dK`` not positive.
    """
    _check_paris(C, m, 0.0, 0.0)
    a, dK = _finite("a", a), _finite("dK", dK)
    if a.ndim != 1 or a.shape != dK.shape or len(a) < 1:
        raise ValueError(f"a and dK must have the same shape (n,), got {a.shape} and {dK.shape}")
    if np.any(a <= 0) or np.any(np.diff(a) <= 0):
        raise ValueError("crack lengths a must be > 0 and increasing (measure a from the mouth "
                         f"or the centre), got {a.tolist()}")
    if np.any(dK <= 0):
        raise ValueError(f"dK must be > 0 at every sample (no growth at or below the threshold), "
                         f"got {dK.tolist()}")
    lr = np.log(a[1:] / a[:-1])
    p = np.log(dK[1:] / dK[:-1]) / lr
    x = (1.0 - p * m) * lr
    small = np.abs(x) < 1e-8
    ratio = np.where(small, 1.0 + x / 2, np.expm1(x) / np.where(small, 1.0, x))
    dN = a[:-1] / (C * dK[:-1] ** m) * lr * ratio
    return np.concatenate([[0.0], np.cumsum(dN)])


@dataclass(frozen=True)
class FatigueLife:
    """a(N) of a Paris-law integration.

    Attributes
    ----------
    a, N, dK : ndarray (n,)
        Crack length, cycles and stress-intensity range at each accepted step.
    reason : str
        Why the integration stopped (``"a_end reached"``, ``"below threshold"``).
    n_evaluations : int
        Calls of the K function.
    """

    a: np.ndarray
    N: np.ndarray
    dK: np.ndarray
    reason: str
    n_evaluations: int

    @property
    def cycles(self) -> float:
        """Total cycles ``N[-1]``."""
        return float(self.N[-1])


def paris_life(K: Callable[[float], float], a0: float, a_end: float, C: float, m: float,
               R: float = 0.0, dK_th: float = 0.0, rtol: float = 1e-6,
               da0: float | None = None) -> FatigueLife:
    """Integrate the Paris law from ``a0`` to ``a_end`` with adaptive increments.

    Each step from ``a`` to ``a + h`` is integrated once (:func:`paris_cycles` over
    ``a, a + h``) and as two halves; ``err = |N_2 - N_1| / 3`` estimates the error of
    the halves (a second-order rule). A step is accepted when ``err <= rtol N_2`` (so
    the relative error of the life is below about ``rtol``); the accepted value is the
    extrapolation ``N_2 + (N_2 - N_1) / 3``, and the next ``h`` scales by
    ``0.9 (rtol N_2 / err)^(1/2)`` (the relative local error grows like h^2; limits 0.2
    and 5).

    Parameters
    ----------
    K : callable ``a -> K_max`` (float)
        Stress intensity factor at the maximum load, for a crack of length a.
    a0, a_end : float
        Initial and final lengths, ``0 < a0 < a_end``.
    C, m, R, dK_th : float
        Paris constants, load ratio and threshold (:func:`paris_rate`).
    rtol : float
        Relative tolerance of the life.
    da0 : float, optional
        First increment (default ``(a_end - a0) / 20``).

    Returns
    -------
    FatigueLife; stops early with ``reason="below threshold"`` when dK at the current
    length is at or below ``dK_th`` (no growth: the life is infinite from there).

    Examples
    --------
    >>> life = paris_life(lambda a: math.sqrt(math.pi * a), 1.0, 2.0, C=1.0, m=2.0)
    >>> round(life.cycles * math.pi, 12)   # closed form: ln(a_end / a0) / (C pi sigma^2)
    0.69314718056
    """
    _check_paris(C, m, R, dK_th)
    if not (math.isfinite(a0) and math.isfinite(a_end) and 0 < a0 < a_end):
        raise ValueError(f"need 0 < a0 < a_end (finite), got a0={a0!r}, a_end={a_end!r}")
    if not (math.isfinite(rtol) and 0 < rtol < 1):
        raise ValueError(f"rtol must lie in (0, 1), got {rtol!r}")
    count = [0]

    def dk(a):
        count[0] += 1
        v = float(delta_k(K(a), R))
        if not math.isfinite(v):
            raise ValueError(f"K({a!r}) is not finite; check the K function")
        return v

    h = (a_end - a0) / 20 if da0 is None else float(da0)
    if not (math.isfinite(h) and h > 0):
        raise ValueError(f"da0 must be finite and > 0, got {da0!r}")
    a, dK = [a0], [dk(a0)]
    N = [0.0]
    reason = "a_end reached"
    while a[-1] < a_end * (1 - 1e-15):
        if dK[-1] <= dK_th:
            reason = "below threshold"
            break
        h = min(h, a_end - a[-1])
        x0 = a[-1]
        xm, x1 = x0 + h / 2, x0 + h
        km, k1 = dk(xm), dk(x1)
        if km <= dK_th or k1 <= dK_th:  # the range falls to the threshold inside the step
            if h <= 1e-12 * a_end:
                reason = "below threshold"
                break
            h /= 2
            continue
        n1 = paris_cycles(np.array([x0, x1]), np.array([dK[-1], k1]), C, m)[-1]
        n2 = paris_cycles(np.array([x0, xm, x1]), np.array([dK[-1], km, k1]), C, m)[-1]
        err = abs(n2 - n1) / 3  # the error of n2 for a second-order rule
        if err <= rtol * n2 or h <= 1e-12 * a_end:
            a.append(x1)
            dK.append(k1)
            N.append(N[-1] + n2 + (n2 - n1) / 3)
        h *= min(5.0, max(0.2, 0.9 * (rtol * n2 / err) ** 0.5 if err > 0 else 5.0))
    return FatigueLife(np.array(a), np.array(N), np.array(dK), reason, count[0])
