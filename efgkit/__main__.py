"""``python -m efgkit``: the ``efgkit`` command line."""

from .cli import main

if __name__ == "__main__":  # not when pytest --doctest-modules imports this file
    raise SystemExit(main())
