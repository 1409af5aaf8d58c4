"""The nodal release rules of seed 000 Sect. 5.2.1 (Fig. 15) on a line of nodes: which
segments open when nodes meet the criterion (used by :mod:`efgkit.growth.release`)."""

from __future__ import annotations

import numpy as np

__all__ = ["release_segments"]


def release_segments(open_: np.ndarray, sigma1: np.ndarray, sigma_c) -> list[tuple[int, bool]]:
    """Nodal release on a line (seed 000 Fig. 15), in place on ``open_``.

    Parameters
    ----------
    open_ : ndarray (m - 1,) bool
        Segment ``j`` joins nodes ``j`` and ``j + 1``; True: open (crack face). Modified.
    sigma1 : ndarray (m,)
        Maximum principal stress at the nodes.
    sigma_c : float or ndarray (m,)

    Returns
    -------
    list of (node index, new_crack)
        The released nodes, by increasing index: a bonded node (both segments closed, not
        an end of the line) with ``sigma1 >= sigma_c``. Next to a tip on one side (node
        ``k - 1`` ends an open stretch: segment ``k - 2`` open) it becomes the new tip
        (segment ``k - 1`` opens; mirrored for a tip at ``k + 1``); otherwise both its
        segments open (a new crack, ``new_crack`` True, or two cracks joined when tips
        lie on both sides). Then a bonded segment between two tips (no bonded node left
        on it) opens when either tip reaches ``sigma_c``: the cracks join.

    Examples
    --------
    >>> op = np.array([True, False, False, False, False, False])
    >>> release_segments(op, np.array([0, 0, 5.0, 0, 0, 5.0, 0]), 1.0)
    [(2, False), (5, True)]
    >>> op.astype(int).tolist()
    [1, 1, 0, 0, 1, 1]
    """
    out, m = [], len(open_) + 1
    for k in np.flatnonzero(np.asarray(sigma1) >= sigma_c):  # sigma_c: a number or (m,)
        if k == 0 or k == m - 1 or open_[k - 1] or open_[k]:
            continue  # an end of the line, a tip or a face node: not bonded
        tip_left = k >= 2 and bool(open_[k - 2])
        tip_right = k + 1 < m - 1 and bool(open_[k + 1])
        if tip_left and not tip_right:
            open_[k - 1] = True
        elif tip_right and not tip_left:
            open_[k] = True
        else:
            open_[k - 1] = open_[k] = True
        out.append((int(k), not (tip_left or tip_right)))
    # a one-segment ligament between two tips (left by a new crack two nodes from a tip)
    # has no bonded node: it opens when either of its tips reaches sigma_c
    for j in np.flatnonzero(~open_[1:-1]) + 1:
        over = np.asarray(sigma1)[j:j + 2] >= np.broadcast_to(sigma_c, (m,))[j:j + 2]
        if open_[j - 1] and open_[j + 1] and over.any():
            open_[j] = True
            out.append((int(j if over[0] else j + 1), False))
    return out
