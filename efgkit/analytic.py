"""Named analytic elasticity fields (PLACEHOLDER: being written)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Field"]


@dataclass(frozen=True)
class Field:
    """A named closed-form field with parameters; evaluated with a material.

    ``displacement(x (n, 2), material) -> (n, 2)``,
    ``stress(x (n, 2), material) -> (n, 3)`` Voigt (xx, yy, xy).
    """

    name: str
    params: tuple = ()

    def displacement(self, x: np.ndarray, material) -> np.ndarray:
        raise NotImplementedError

    def stress(self, x: np.ndarray, material) -> np.ndarray:
        raise NotImplementedError
