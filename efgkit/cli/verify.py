"""``efgkit verify [NAME ...]``: the verification scripts of ``verification/``."""

from __future__ import annotations

import importlib.util
import sys
import time
import warnings
from pathlib import Path

from .errors import CLIError, message

__all__ = ["cmd_verify"]


def _verification_dir() -> Path:
    """``./verification`` or, failing that, the one next to the installed package."""
    import efgkit

    tried = [Path.cwd() / "verification",
             Path(efgkit.__file__).resolve().parents[1] / "verification"]
    for d in tried:
        if d.is_dir():
            return d
    raise CLIError("no verification directory: looked for " + " and ".join(map(str, tried)))


def _scripts(directory: Path) -> dict[str, Path]:
    return {p.stem: p for p in sorted(directory.glob("*.py")) if not p.name.startswith("_")}


def _run_script(name: str, path: Path, quick: bool) -> dict:
    """Import ``path`` as a module and return its ``main(quick=quick)``.

    Warnings raised by the script are collected (their count goes on the summary line).
    """
    spec = importlib.util.spec_from_file_location(f"_efgkit_verification_{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.parent))  # scripts may import their siblings
    try:
        spec.loader.exec_module(module)
        result = module.main(quick=quick)
    finally:
        sys.path.remove(str(path.parent))
    if not isinstance(result, dict) or "passed" not in result:
        raise TypeError(f"main() must return a dict with 'passed', got {type(result).__name__}")
    return result


def cmd_verify(args) -> int:
    """List or run verification scripts; 1 if any failed."""
    directory = _verification_dir()
    scripts = _scripts(directory)
    if args.list:
        print("\n".join(scripts) if scripts else f"(no scripts in {directory})")
        return 0
    unknown = [n for n in args.names if n not in scripts]
    if unknown:
        raise CLIError(f"unknown verification script(s) {', '.join(map(repr, unknown))}; "
                       f"available: {', '.join(scripts) or 'none'} (in {directory})")
    names = args.names or list(scripts)
    failed = 0
    for name in names:
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("default")
            try:
                res = _run_script(name, scripts[name], args.quick)
            except Exception as err:  # a crashing script is a failed verification
                ok, detail = False, f"error: {type(err).__name__}: {message(err)}"
            else:
                ok = bool(res["passed"])
                checks = res.get("checks")
                detail = (f"{sum(bool(c.get('passed')) for c in checks)}/{len(checks)} checks"
                          if isinstance(checks, list) else "")
        if caught:
            kinds = sorted({w.category.__name__ for w in caught})
            n = len(caught)
            detail += f" ({n} warning{'s' * (n != 1)}: {', '.join(kinds)})"
        failed += not ok
        elapsed = time.perf_counter() - t0
        print(f"{'PASS' if ok else 'FAIL'}  {name:<24} {elapsed:7.1f} s  {detail}".rstrip())
    return 1 if failed else 0
