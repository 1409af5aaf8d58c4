"""Tables read from TOML files (scenes, studies, growth settings, method tables): a key
that is not one of the table's is named with the nearest valid key."""

from __future__ import annotations

import difflib

__all__ = ["check_known_keys"]


def check_known_keys(d: dict, valid, where: str, note: str = "") -> None:
    """Raise ValueError for the first key of ``d`` not in ``valid``.

    The message reads ``unknown key 'k' in <where><note>; did you mean 'v'?`` (or lists the
    valid keys when none is close).

    Examples
    --------
    >>> check_known_keys({"spacin": 0.1}, ("spacing", "order"), "table 'efg'")
    Traceback (most recent call last):
    ...
    ValueError: unknown key 'spacin' in table 'efg'; did you mean 'spacing'?
    """
    valid = tuple(valid)
    for k in d:
        if k not in valid:
            near = difflib.get_close_matches(str(k), valid, n=1)
            hint = f"did you mean {near[0]!r}?" if near else f"valid keys: {', '.join(valid)}"
            raise ValueError(f"unknown key {k!r} in {where}{note}; {hint}")
