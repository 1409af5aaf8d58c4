"""The command line's errors: one line on stderr, an exit status that says whose it is."""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

__all__ = ["EXIT_STATUS", "FAILED", "REFUSED", "CLIError", "check_out", "failures", "message", "stage"]

FAILED, REFUSED = 1, 2
EXIT_STATUS = """exit status:
  0  success
  1  the computation failed: a numerical failure (singular matrix, no convergence,
     non-finite results, out of memory), a failed verification, or a study point that
     failed or was lost
  2  the input was refused: usage, the scene file (missing, malformed, unknown keys),
     a scene or discretisation that cannot be solved as given (rigid-body modes,
     unsupported options, too large for the memory), the output directory
errors are one line on stderr, "efgkit: error: ..."; --debug adds the traceback"""


class CLIError(Exception):
    """An error reported as one line on stderr; ``status`` is the exit status."""

    def __init__(self, message: str, status: int = REFUSED):
        super().__init__(message)
        self.status = status


def message(err: BaseException) -> str:
    # KeyError quotes its argument; the others read as written
    return str(err.args[0]) if isinstance(err, KeyError) and err.args else str(err)


def failures() -> tuple[type[BaseException], ...]:
    """Exceptions that mean "the numbers failed" (exit 1) rather than "the input was refused"."""
    import numpy as np

    from ..approx.mls import SingularMomentMatrix
    from ..system.linalg import SolverError

    return (SolverError, SingularMomentMatrix, np.linalg.LinAlgError, ArithmeticError, MemoryError)


@contextmanager
def stage(refused: str, failed: str):
    """Turn the errors of one stage of ``run`` into CLIError: ``failed: ...`` (exit 1) for
    numerical failures, ``refused: ...`` (exit 2) for input errors; others propagate (bugs)."""
    try:
        yield
    except CLIError:
        raise
    except failures() as err:
        msg = message(err) or type(err).__name__
        if isinstance(err, MemoryError):
            msg = "out of memory; use a coarser spacing or zones only where they are needed"
        raise CLIError(f"{failed}: {msg}", FAILED) from err
    except (ValueError, TypeError, KeyError) as err:
        raise CLIError(f"{refused}: {message(err)}", REFUSED) from err


def check_out(out: Path, given: bool) -> None:
    """Refuse, before the solve, an output directory that cannot be created or written."""
    what = f"--out {str(out)!r}" if given else f"the output directory {str(out)!r}"
    if out.exists() and not out.is_dir():
        raise CLIError(f"{what} is an existing file, not a directory; give a directory (it is "
                       "created if missing) or remove the file")
    base = out
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise CLIError(f"{what} cannot be created: {str(base)!r} is a file; give another --out")
    if not os.access(base, os.W_OK | os.X_OK):
        raise CLIError(f"{what}: no permission to write in {str(base)!r}; give another --out")
