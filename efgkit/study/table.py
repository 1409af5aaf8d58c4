"""The rows of a study on disk, and the one table made of them.

Each finished point is one JSON file ``<out>/points/<key>.json`` (the row of
:func:`efgkit.study.point.run_point`), written atomically (a temporary file in the
same directory, then renamed) as soon as its point finishes: a crash of the client
loses at most the points in flight, never a written row, and never leaves half a file.
(No fsync: a crash of the operating system may lose the last rows it had not flushed, or
leave one unreadable; an unreadable row counts as missing and its point runs again.)
A rerun reads these files and runs only the points without one.

:func:`study_table` flattens the rows of a study's points, in the study's order, into
a :class:`pandas.DataFrame` with one row per point:

=========================  ==================================================
``key``, ``status``        the point's key; ``ok``, ``failed``, or ``missing``
                           (no row yet: not run, or its worker died)
``<parameter name>``       one column per parameter (arrays as JSON text)
``KI[<tip>]`` ...          ``KI, KII, J, T, spread, error`` of each tip (tip id
                           ``<crack name>:<end>``)
``n_nodes, n_dofs, ...``   the scalar results (``values`` of the row)
``time_<stage>``           seconds: ``time_total`` and the solve's stages
``error_type``,            the failure of a failed point
``error_message``
``n_warnings``,            the warnings of the point, joined with `` | ``
``warnings``
``worker``, ``finished``   where and when it ran
=========================  ==================================================
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from .point import TIP_KEYS

__all__ = ["DONE", "read_row", "row_path", "study_table", "write_row", "write_table"]

DONE = ("ok", "failed")  # statuses a rerun skips (failed only without retry_failed)


def row_path(out, key: str) -> Path:
    """``<out>/points/<key>.json``."""
    return Path(out) / "points" / f"{key}.json"


def write_row(out, row: dict) -> Path:
    """Write ``row`` to :func:`row_path` atomically; returns the path."""
    path = row_path(out, row["key"])
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / f".{row['key']}.{os.getpid()}.tmp"  # one per client process
    try:
        tmp.write_text(json.dumps(row, indent=1, allow_nan=False))
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def read_row(out, key: str) -> dict | None:
    """The row of ``key``, or None when there is none (or it cannot be read: then the
    point is run again)."""
    try:
        with open(row_path(out, key)) as f:
            row = json.load(f)
    except (OSError, ValueError):
        return None
    return row if isinstance(row, dict) and row.get("key") == key else None


def _cell(v):
    return json.dumps(v) if isinstance(v, (list, dict)) else v


def _flat(point, row: dict | None) -> dict:
    rec = {"key": point.key, "status": row["status"] if row else "missing"}
    rec.update({k: _cell(v) for k, v in point.params.items()})
    if row is None:
        return rec
    for tip in row.get("tips", ()):
        for q in ("x", "y", *TIP_KEYS):
            rec[f"{q}[{tip['id']}]"] = tip.get(q)
    rec.update(row.get("values", {}))
    rec.update({f"time_{k}": v for k, v in row.get("timings", {}).items()})
    warns = row.get("warnings", [])
    rec.update({"error_type": row.get("error_type"), "error_message": row.get("error_message"),
                "n_warnings": len(warns), "warnings": " | ".join(warns),
                "worker": row.get("worker"), "finished": row.get("finished")})
    return rec


def study_table(study, out, rows: dict | None = None):
    """One row per point of ``study`` (module docstring), as a pandas DataFrame.

    Parameters
    ----------
    study : Study
    out : path
        The study's output directory (rows read from ``<out>/points``).
    rows : dict, optional
        key -> row already in memory (read from disk where missing).
    """
    import pandas as pd

    rows = rows or {}
    recs = [_flat(p, rows.get(p.key) or read_row(out, p.key)) for p in study.points()]
    df = pd.DataFrame.from_records(recs)
    first = ["key", "status", *(p.label for p in study.parameters)]
    tips = [c for c in df.columns if "[" in c and c not in first]
    tail = ["error_type", "error_message", "n_warnings", "warnings", "worker", "finished"]
    tail = [c for c in tail if c in df.columns]
    times = [c for c in df.columns if c.startswith("time_")]
    rest = [c for c in df.columns if c not in {*first, *tips, *tail, *times}]
    return df[first + tips + rest + times + tail]


def write_table(df, out, name: str) -> tuple[Path, Path]:
    """Write ``df`` as ``<out>/<name>.csv`` and ``<out>/<name>.parquet``; returns both paths."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    csv, parquet = out / f"{name}.csv", out / f"{name}.parquet"
    df.to_csv(csv, index=False)
    df.to_parquet(parquet, index=False)
    return csv, parquet
