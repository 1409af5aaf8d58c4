"""``efgkit sweep STUDY.toml``: a parameter study (:mod:`efgkit.study`)."""

from __future__ import annotations

import sys
from pathlib import Path

from .errors import FAILED, CLIError, check_out, message

__all__ = ["cmd_sweep"]


def cmd_sweep(args) -> int:
    """Run a study file (efgkit.study): its points on dask, a table and figures; 1 unless
    every point of the study has succeeded (in this run or an earlier one)."""
    from ..io import file_name
    from ..study import TerminalProgress, read_study, run_study

    try:
        sf = read_study(args.study)
    except (OSError, ValueError, TypeError) as err:
        raise CLIError(message(err)) from err
    out = Path(args.out or sf.out or Path("out") / file_name(sf.study.name))
    check_out(out, args.out is not None)
    workers = sf.workers if args.workers is None else args.workers
    try:
        run = run_study(sf.study, out=out, scheduler=args.scheduler or sf.scheduler or "local",
                        workers=workers, retry_failed=args.retry_failed,
                        progress=TerminalProgress(sys.stderr))
    except (ValueError, TypeError) as err:
        raise CLIError(f"{args.study}: {message(err)}") from err
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    print(run.summary())
    return 0 if run.ok else FAILED
