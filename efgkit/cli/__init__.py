"""Command line: ``efgkit run SCENE.toml``, ``efgkit verify [NAME ...]``, ``efgkit sweep STUDY.toml``.

Thin by design (design rule 11): one function per subcommand over the public
API, testable as ``main(argv)``. Every error is one line on stderr,
``efgkit: error: ...`` (``--debug`` adds the traceback); the exit status says
whose it is (:data:`EXIT_STATUS`, shown by ``--help``): 1 when the computation
failed, 2 when the input was refused.
"""

from __future__ import annotations

import argparse
import sys
import traceback
import warnings

from .errors import EXIT_STATUS, REFUSED, CLIError
from .run import cmd_run
from .sweep import cmd_sweep
from .verify import cmd_verify

__all__ = ["main"]


def _sample_count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 100:
        raise argparse.ArgumentTypeError(f"must be an integer >= 100, got {text!r}")
    return n


def _parser() -> argparse.ArgumentParser:
    from .. import __version__

    p = argparse.ArgumentParser(prog="efgkit", description=__doc__.splitlines()[0],
                                epilog=EXIT_STATUS,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"efgkit {__version__}")
    p.add_argument("--debug", action="store_true", help="show the traceback of an error")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    r = sub.add_parser("run", help="solve a scene file and write fields, figures and a report",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("scene", metavar="SCENE.toml")
    r.add_argument("--out", metavar="DIR", help="output directory (default: out/<scene name>); "
                   "checked before the solve")
    r.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    r.add_argument("--samples", type=_sample_count, default=20000, metavar="N",
                   help="approximate number of field sample points (default: 20000)")
    r.add_argument("--vtu-steps", action="store_true",
                   help="with a [growth] table: write the fields of every step as VTU")
    r.set_defaults(func=cmd_run)
    v = sub.add_parser("verify", help="run verification scripts (verification/<name>.py)",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    v.add_argument("names", nargs="*", metavar="NAME", help="scripts to run (default: all)")
    v.add_argument("--quick", action="store_true", help="quick mode (coarse, for CI)")
    v.add_argument("--list", action="store_true", help="list the available scripts")
    v.set_defaults(func=cmd_verify)
    w = sub.add_parser("sweep", help="run a parameter study (docs/studies.md) on a dask cluster",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    w.add_argument("study", metavar="STUDY.toml")
    w.add_argument("--scheduler", metavar="ADDR", help="'local' (default: one worker per core), "
                   "'synchronous', tcp://host:8786 or a scheduler file *.json")
    w.add_argument("--workers", type=int, metavar="N", help="local cluster: worker processes")
    w.add_argument("--out", metavar="DIR", help="output directory (default: out/<study name>)")
    w.add_argument("--retry-failed", action="store_true", help="run failed points again")
    w.set_defaults(func=cmd_sweep)
    for s in (r, v, w):  # also after the subcommand; SUPPRESS keeps a --debug given before it
        s.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show the traceback of an error")
    return p


def _warning_lines(caught) -> list[str]:
    """Warnings raised during a command, one line each, without repeats."""
    seen = dict.fromkeys(" ".join(str(w.message).split()) for w in caught)
    return [f"efgkit: warning: {m}" for m in seen]


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``efgkit`` command; returns the exit status (module docstring).

    Warnings raised on the way are printed after the command, one line each
    (``efgkit: warning: ...``); after an error only with ``--debug``, and then with
    the traceback before the error line.

    Examples
    --------
    >>> main(["run", "no/such/scene.toml"])  # one line on stderr: scene file ... not found
    2
    """
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors (argparse printed them)
        return exc.code if isinstance(exc.code, int) else REFUSED
    error = None
    with warnings.catch_warnings(record=True) as caught:  # the filters in force stay
        try:
            status = args.func(args)
        except CLIError as err:
            error, status = err, err.status
    if error is None or args.debug:
        for line in _warning_lines(caught):
            print(line, file=sys.stderr)
    if error is not None:
        if args.debug:
            traceback.print_exception(error, file=sys.stderr)
        print(f"efgkit: error: {error}", file=sys.stderr)
    return status
