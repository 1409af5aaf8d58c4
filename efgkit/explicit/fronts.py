"""Wave-front arrival times picked from probe histories, and the front speeds they give.

A front is located at each probe by a stated rule on the recorded history ``f(t)`` of a
quantity that only the wanted wave carries there (the dilatation for P waves, the rotation
for S and head waves, ...), within a gate ``[lo, hi]`` about its expected arrival:

* :func:`peak_times`: the time of the largest ``f`` in the gate, refined by the parabola
  through that sample and its two neighbours;
* :func:`onset_times`: the first time ``|f|`` reaches ``frac`` of its largest value in the
  gate (linear interpolation between samples): the front itself, for waves whose shape
  changes with distance (diffracted and head waves);

then the speed is fitted over several probes: :func:`line_speed` (distance against time,
least squares) or :func:`plane_front` (a plane ``t = t0 + g . x`` through arrivals at
scattered points: the front's normal speed ``1 / |g|``, its normal direction and its trace
speeds along the axes, e.g. a head wave's speed along a free surface).

Examples
--------
A Gaussian pulse moving at 3 (length / time) past four probes:

>>> import numpy as np
>>> t = np.linspace(0.0, 20.0, 401)
>>> d = np.array([10.0, 20.0, 30.0, 40.0])
>>> f = np.exp(-((t[:, None] - 2.0 - d / 3.0) / 0.8) ** 2)
>>> tp = peak_times(t, f, d / 3.0, d / 3.0 + 4.0)
>>> round(line_speed(d, tp), 4)
3.0
>>> round(line_speed(d, onset_times(t, f, d / 3.0 - 1.0, d / 3.0 + 4.0, 0.1)), 4)
3.0
"""

from __future__ import annotations

import numpy as np

__all__ = ["line_speed", "lobe_signs", "onset_times", "peak_times", "plane_front", "rise_times"]


def _histories(t, f, lo, hi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Validated (t (n_t,), f (n_t, n), gate mask (n_t, n))."""
    t = np.asarray(t, float)
    f = np.asarray(f, float)
    if t.ndim != 1 or t.size < 3 or np.any(np.diff(t) <= 0):
        raise ValueError(f"t must be increasing sample times (n_t >= 3,), got shape {t.shape}: "
                         "pass the output instants in order")
    if f.ndim == 1:
        f = f[:, None]
    if f.ndim != 2 or f.shape[0] != t.size:
        raise ValueError(f"f must have shape (n_t, n_probes) with n_t = {t.size}, got "
                         f"{f.shape}: one column per probe, one row per instant")
    if not np.all(np.isfinite(f)):
        raise ValueError("f has NaN or inf values: the run blew up or a probe lies outside "
                         "the body; check the probes and the step")
    lo = np.broadcast_to(np.asarray(lo, float), f.shape[1:])
    hi = np.broadcast_to(np.asarray(hi, float), f.shape[1:])
    inside = (t[:, None] >= lo) & (t[:, None] <= hi)
    few = np.flatnonzero(inside.sum(axis=0) < 3)
    if few.size:
        j = int(few[0])
        raise ValueError(f"gate of probe {j} ({lo[j]:.4g}, {hi[j]:.4g}) holds fewer than 3 "
                         f"samples of t in [{t[0]:.4g}, {t[-1]:.4g}]: widen the gate, record "
                         "more often or run longer")
    return t, f, inside


def peak_times(t, f, lo, hi) -> np.ndarray:
    """Time of the largest ``f`` within the gate of each probe.

    Parameters
    ----------
    t : (n_t,) increasing sample times.
    f : (n_t, n) histories, one column per probe (pass ``-f`` for the largest negative
        lobe).
    lo, hi : (n,) or scalars: the gates.

    Returns
    -------
    (n,) times: the largest sample ``k`` moved by the vertex of the parabola through
    ``f[k-1], f[k], f[k+1]`` (at most one sample either way; not moved when ``k`` is at
    the gate's end or the parabola is not concave).
    """
    t, f, inside = _histories(t, f, lo, hi)
    k = np.argmax(np.where(inside, f, -np.inf), axis=0)
    kc = np.clip(k, 1, t.size - 2)
    cols = np.arange(f.shape[1])
    y0, y1, y2 = f[kc - 1, cols], f[kc, cols], f[kc + 1, cols]
    den = y0 - 2.0 * y1 + y2
    edge = ~inside[np.clip(k - 1, 0, None), cols] | ~inside[np.clip(k + 1, None, t.size - 1), cols]
    ok = (den < 0) & ~edge & (k == kc)
    s = np.where(ok, np.clip(0.5 * (y0 - y2) / np.where(ok, den, 1.0), -1.0, 1.0), 0.0)
    step = np.where(s >= 0, t[np.minimum(kc + 1, t.size - 1)] - t[kc], t[kc] - t[kc - 1])
    return t[k] + np.where(ok, s * step, 0.0)


def onset_times(t, f, lo, hi, frac: float) -> np.ndarray:
    """First time ``|f|`` reaches ``frac`` of its largest value within each probe's gate.

    Parameters
    ----------
    t, f, lo, hi : as in :func:`peak_times`.
    frac : in (0, 1): the threshold as a fraction of the gate's largest ``|f|``.

    Returns
    -------
    (n,) times, interpolated linearly between the samples below and at the threshold (the
    gate's start when ``|f|`` is already there).
    """
    if not 0.0 < frac < 1.0:
        raise ValueError(f"frac must lie in (0, 1), got {frac!r}: a fraction of the peak "
                         "such as 0.1")
    t, f, inside = _histories(t, f, lo, hi)
    a = np.where(inside, np.abs(f), 0.0)
    thr = frac * a.max(axis=0)
    if np.any(thr <= 0):
        j = int(np.flatnonzero(thr <= 0)[0])
        raise ValueError(f"probe {j} records zero within its gate: no wave reached it; move "
                         "the probe or widen the gate")
    k = np.argmax(a >= thr, axis=0)  # first sample at or above the threshold
    first = np.argmax(inside, axis=0)
    cols = np.arange(f.shape[1])
    km = np.maximum(k - 1, 0)
    below = (k > first)
    a0, a1 = a[km, cols], a[k, cols]
    w = np.where(below, (thr - a0) / np.where(below, a1 - a0, 1.0), 0.0)
    return np.where(below, t[km] + w * (t[k] - t[km]), t[k])


def _lobes(t, f, inside, strict: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(n,) sample of the largest lobe of each column inside its gate: the largest sample
    not smaller than its neighbours, not on the gate's last sample (a lobe the gate cuts);
    and (n,) whether there is one (``strict``: an error where there is none)."""
    up = np.zeros(f.shape, bool)
    up[1:-1] = (f[1:-1] >= f[:-2]) & (f[1:-1] >= f[2:])
    last = inside & ~np.vstack([inside[1:], np.zeros((1, f.shape[1]), bool)])
    g = np.where(inside & up & ~last, f, -np.inf)
    k = np.argmax(g, axis=0)
    bad = ~np.isfinite(g[k, np.arange(f.shape[1])])
    if strict and np.any(bad):
        j = int(np.flatnonzero(bad)[0])
        raise ValueError(f"probe {j} has no lobe (local maximum) within its gate: pass -f for "
                         "a negative lobe, or move or widen the gate")
    return k, ~bad


def lobe_signs(t, f, lo, hi, lead: float = 0.5) -> np.ndarray:
    """(n,) sign (+1 or -1) of the leading lobe in each probe's gate: the first lobe (local
    maximum of ``|f|``, not on the gate's last sample) at least ``lead`` times as large as
    the largest such lobe. Which sign to pass :func:`rise_times` for the front's lobe.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 10.0, 201)
    >>> f = -0.8 * np.exp(-(t - 3.0) ** 2) + np.exp(-(t - 5.0) ** 2)
    >>> lobe_signs(t, f[:, None], 0.0, 10.0).tolist()
    [-1.0]
    """
    if not 0.0 < lead <= 1.0:
        raise ValueError(f"lead must lie in (0, 1], got {lead!r}: 0.5 takes the first lobe "
                         "at least half the largest")
    t, f, inside = _histories(t, f, lo, hi)
    a = np.abs(f)
    k_top, found = _lobes(t, a, inside, False)
    if np.any(~found):
        j = int(np.flatnonzero(~found)[0])
        raise ValueError(f"probe {j} has no lobe of either sign within its gate: move or "
                         "widen the gate")
    cols = np.arange(f.shape[1])
    up = np.zeros(f.shape, bool)
    up[1:-1] = (a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:])
    last = inside & ~np.vstack([inside[1:], np.zeros((1, f.shape[1]), bool)])
    big = inside & up & ~last & (a >= lead * a[k_top, cols])
    k = np.argmax(big, axis=0)
    return np.where(f[k, cols] >= 0, 1.0, -1.0)


def rise_times(t, f, lo, hi, frac: float = 0.5) -> np.ndarray:
    """Time the leading edge of the largest lobe in each probe's gate rises through ``frac``
    of that lobe's peak (half-maximum on the leading edge by default).

    The lobe is the largest local maximum of ``f`` in the gate (pass ``-f`` for a negative
    lobe), not on the gate's last sample; the time is the last upward crossing of
    ``frac * peak`` before it, interpolated linearly. Unlike the peak, this time sits on the
    front's rising edge, which changes less with distance where the pulse widens
    (cylindrical spreading, head and diffracted waves); unlike an onset at a small
    fraction, it is far above the numerical noise ahead of the front.

    Parameters
    ----------
    t, f, lo, hi : as in :func:`peak_times`.
    frac : in (0, 1).

    Returns
    -------
    (n,) times.
    """
    if not 0.0 < frac < 1.0:
        raise ValueError(f"frac must lie in (0, 1), got {frac!r}: 0.5 for the half-maximum")
    t, f, inside = _histories(t, f, lo, hi)
    k = _lobes(t, f, inside)[0]
    cols = np.arange(f.shape[1])
    peak = f[k, cols]
    if np.any(peak <= 0):
        j = int(np.flatnonzero(peak <= 0)[0])
        raise ValueError(f"probe {j} has no positive lobe within its gate: pass -f for a "
                         "negative lobe, or move the gate")
    thr = frac * peak
    idx = np.arange(t.size)[:, None]
    below = inside & (idx < k) & (f < thr)
    j = np.where(below.any(axis=0), np.max(np.where(below, idx, -1), axis=0), -1)
    if np.any(j < 0):
        p = int(np.flatnonzero(j < 0)[0])
        raise ValueError(f"probe {p}: the gate ({np.broadcast_to(lo, f.shape[1:])[p]:.4g}, ...) "
                         f"starts above {frac:g} of the peak: start the gate earlier")
    f0, f1 = f[j, cols], f[j + 1, cols]
    return t[j] + (thr - f0) / (f1 - f0) * (t[j + 1] - t[j])


def line_speed(distances, times) -> float:
    """Slope of ``distances`` against ``times`` (least squares): the speed of a front met at
    probes along a line. Both (n,), n >= 2."""
    d, tt = np.asarray(distances, float), np.asarray(times, float)
    if d.shape != tt.shape or d.ndim != 1 or d.size < 2:
        raise ValueError(f"distances and times must be (n,) arrays of the same length n >= 2, "
                         f"got shapes {d.shape} and {tt.shape}")
    if np.ptp(tt) <= 0:
        raise ValueError("times are all equal: the front was not resolved (check the gates)")
    return float(np.polyfit(tt, d, 1)[0])


def plane_front(points, times) -> dict:
    """Least-squares plane ``t = t0 + g . x`` through arrival ``times`` (n,) at ``points``
    (n, 2), n >= 3 not on one line.

    Returns
    -------
    dict with ``t0``, ``slowness`` g (2,), ``speed`` = 1 / |g| (the front's normal speed),
    ``normal`` = g / |g| (its direction of travel), ``trace`` (2,) = 1 / g (apparent speeds
    along x and y; inf where g is 0) and ``rms`` the residual (time).

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> r = plane_front(p, p @ np.array([0.6, 0.8]) / 5.0 + 1.0)
    >>> round(r["speed"], 9), np.round(r["normal"], 9).tolist(), round(r["t0"], 9)
    (5.0, [0.6, 0.8], 1.0)
    """
    p, tt = np.asarray(points, float), np.asarray(times, float)
    if p.ndim != 2 or p.shape[1] != 2 or tt.shape != (p.shape[0],) or p.shape[0] < 3:
        raise ValueError(f"points must be (n, 2) and times (n,) with n >= 3, got shapes "
                         f"{p.shape} and {tt.shape}")
    A = np.column_stack([np.ones(len(p)), p])
    if np.ptp(tt) <= 0:
        raise ValueError("the arrival times do not vary over the points: no front was resolved")
    if np.linalg.matrix_rank(A) < 3:
        raise ValueError("points lie on one line: a plane front needs points spread in "
                         "two directions")
    co, *_ = np.linalg.lstsq(A, tt, rcond=None)
    g = co[1:]
    s = float(np.hypot(*g))
    with np.errstate(divide="ignore"):
        trace = np.where(g != 0, 1.0 / np.where(g != 0, g, 1.0), np.inf)
    return {"t0": float(co[0]), "slowness": g, "speed": 1.0 / s, "normal": g / s,
            "trace": trace, "rms": float(np.sqrt(np.mean((tt - A @ co) ** 2)))}
