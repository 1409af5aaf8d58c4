"""Named closed-form 2D elasticity fields: exact solutions and boundary data.

A :class:`Field` is a name from the registry :data:`FIELDS` plus its
parameters; it is evaluated with an :class:`~efgkit.problem.material.Elastic`, so one
field serves plane strain and plane stress. The fields are

``kirsch``
    infinite plate with a circular hole under remote uniaxial stress,
``williams``
    near-tip (singular) field of a straight crack, modes I and II,
``cantilever``
    Timoshenko beam with a parabolic end shear.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ..frames import rotate_vectors, rotate_voigt, tip_polar
from ..material import Elastic
from .williams import williams_displacement, williams_stress

__all__ = ["FIELDS", "Field", "field_errors"]

_REQUIRED = None  # default of a parameter that must be given


def _at_singularity(x: np.ndarray, r: np.ndarray, field: str, where: str) -> None:
    if np.any(r == 0):
        p = x[int(np.argmax(r == 0))].tolist()
        raise ValueError(f"{field} field: point {p} is at the {where}, where the field is "
                         "singular; evaluate it away from that point")


# --- kirsch -----------------------------------------------------------------------------

def _kirsch_polar(x, a, centre):
    d = x - np.asarray(centre)
    r = np.hypot(d[:, 0], d[:, 1])
    _at_singularity(x, r, "kirsch", "hole centre")
    return r / a, np.arctan2(d[:, 1], d[:, 0])


def _kirsch_displacement(x, material, a, centre, sigma):
    """Kirsch displacement (the form used in the XFEM/meshless literature), rho = r/a.

    u_x = sigma a / (8 mu) [rho (kappa + 1) cos t + 2/rho ((1 + kappa) cos t + cos 3t)
                            - 2/rho^3 cos 3t]
    u_y = sigma a / (8 mu) [rho (kappa - 3) sin t + 2/rho ((1 - kappa) sin t + sin 3t)
                            - 2/rho^3 sin 3t]
    Symmetric: u_y = 0 on y = y_c and u_x = 0 on x = x_c. Its strain equals the
    compliance times Eq. (35) (checked in tests/test_analytic.py).
    """
    rho, t = _kirsch_polar(x, a, centre)
    k, f = material.kappa, sigma * a / (8.0 * material.mu)
    c1, c3, s1, s3 = np.cos(t), np.cos(3 * t), np.sin(t), np.sin(3 * t)
    ux = f * (rho * (k + 1) * c1 + 2 / rho * ((1 + k) * c1 + c3) - 2 / rho**3 * c3)
    uy = f * (rho * (k - 3) * s1 + 2 / rho * ((1 - k) * s1 + s3) - 2 / rho**3 * s3)
    return np.column_stack([ux, uy])


def _kirsch_stress(x, material, a, centre, sigma):
    """Kirsch stress, seed 003 Eq. (35a-c) times sigma, with rho = r/a.

    s_xx = sigma [1 - (3/2 cos 2t + cos 4t)/rho^2 + 3/2 cos 4t/rho^4]
    s_yy = sigma [-(1/2 cos 2t - cos 4t)/rho^2 - 3/2 cos 4t/rho^4]
    s_xy = sigma [-(1/2 sin 2t + sin 4t)/rho^2 + 3/2 sin 4t/rho^4]
    """
    rho, t = _kirsch_polar(x, a, centre)
    q2, q4 = rho**-2, rho**-4
    c2, c4, s2, s4 = np.cos(2 * t), np.cos(4 * t), np.sin(2 * t), np.sin(4 * t)
    sxx = 1 - q2 * (1.5 * c2 + c4) + 1.5 * q4 * c4
    syy = -q2 * (0.5 * c2 - c4) - 1.5 * q4 * c4
    sxy = -q2 * (0.5 * s2 + s4) + 1.5 * q4 * s4
    return sigma * np.column_stack([sxx, syy, sxy])


# --- williams ---------------------------------------------------------------------------

def _williams_displacement(x, material, tip, angle, KI, KII):
    """Williams displacement: williams.williams_displacement rotated by ``angle``."""
    r, t = tip_polar(x, tip, angle)
    u = williams_displacement(r, t, KI, KII, material.mu, material.kappa)
    return rotate_vectors(u, angle)


def _williams_stress(x, material, tip, angle, KI, KII):
    """Williams stress: williams.williams_stress, tensor-rotated by ``angle``."""
    r, t = tip_polar(x, tip, angle)
    _at_singularity(x, r, "williams", "crack tip")
    return rotate_voigt(williams_stress(r, t, KI, KII), angle)


# --- cantilever -------------------------------------------------------------------------

def _beam_moduli(material: Elastic) -> tuple[float, float]:
    if material.plane == "stress":
        return material.E, material.nu
    return material.E / (1 - material.nu**2), material.nu / (1 - material.nu)


def _cantilever_displacement(x, material, L, D, P):
    """Timoshenko & Goodier (1970) Sec. 21, in the form of Dolbow & Belytschko (1998).

    u_x = -P y / (6 E I) [(6L - 3x) x + (2 + nu)(y^2 - D^2/4)]
    u_y =  P / (6 E I) [3 nu y^2 (L - x) + (4 + 5 nu) D^2 x / 4 + (3L - x) x^2]
    with I = D^3/12 and (E, nu) -> (E/(1 - nu^2), nu/(1 - nu)) in plane strain.
    """
    E, nu = _beam_moduli(material)
    I = D**3 / 12.0
    X, Y = x[:, 0], x[:, 1]
    ux = -P * Y / (6 * E * I) * ((6 * L - 3 * X) * X + (2 + nu) * (Y**2 - D**2 / 4))
    uy = P / (6 * E * I) * (3 * nu * Y**2 * (L - X) + (4 + 5 * nu) * D**2 * X / 4
                            + (3 * L - X) * X**2)
    return np.column_stack([ux, uy])


def _cantilever_stress(x, material, L, D, P):
    """s_xx = -P (L - x) y / I, s_yy = 0, s_xy = P / (2 I) (D^2/4 - y^2), I = D^3/12."""
    I = D**3 / 12.0
    X, Y = x[:, 0], x[:, 1]
    return np.column_stack([-P * (L - X) * Y / I, np.zeros(len(x)),
                            P / (2 * I) * (D**2 / 4 - Y**2)])


# --- registry ---------------------------------------------------------------------------

@dataclass(frozen=True)
class _Impl:
    """A registered field: ``params`` maps name -> (kind, default or None if required);
    kind is "real", "positive" or "point". The evaluators take ``(x (n, 2), material,
    **params)`` and return displacement (n, 2) and stress (n, 3)."""

    params: Mapping[str, tuple[str, object]]
    displacement: Callable
    stress: Callable


FIELDS: dict[str, _Impl] = {
    "kirsch": _Impl({"a": ("positive", _REQUIRED), "centre": ("point", (0.0, 0.0)),
                     "sigma": ("real", 1.0)}, _kirsch_displacement, _kirsch_stress),
    "williams": _Impl({"tip": ("point", (0.0, 0.0)), "angle": ("real", 0.0),
                       "KI": ("real", 0.0), "KII": ("real", 0.0)},
                      _williams_displacement, _williams_stress),
    "cantilever": _Impl({"L": ("positive", _REQUIRED), "D": ("positive", _REQUIRED),
                         "P": ("real", 1.0)}, _cantilever_displacement, _cantilever_stress),
}


def _real(field: str, key: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise TypeError(f"field {field!r}: parameter {key!r} must be a real number, got {v!r}")
    if not math.isfinite(v):
        raise ValueError(f"field {field!r}: parameter {key!r} must be finite, got {v!r}")
    return float(v)


def _value(field: str, key: str, kind: str, v):
    if kind == "point":
        if isinstance(v, (str, bytes)) or np.ndim(v) != 1 or len(v) != 2:
            raise ValueError(f"field {field!r}: parameter {key!r} must be a point (x, y), "
                             f"got {v!r}")
        return tuple(_real(field, key, c) for c in v)
    v = _real(field, key, v)
    if kind == "positive" and v <= 0:
        raise ValueError(f"field {field!r}: parameter {key!r} must be > 0, got {v!r}")
    return v


def _normalise(name, params) -> tuple:
    if not isinstance(name, str) or name not in FIELDS:
        near = difflib.get_close_matches(str(name), FIELDS, n=1)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        raise ValueError(f"unknown field {name!r}{hint}; known fields: {sorted(FIELDS)}")
    spec = FIELDS[name].params
    pairs = list(params.items() if isinstance(params, Mapping) else params)
    if not all(isinstance(p, tuple) and len(p) == 2 and isinstance(p[0], str) for p in pairs):
        raise TypeError(f"field {name!r}: params must be (key, value) pairs, got {params!r}")
    given = dict(pairs)
    if len(given) != len(pairs):
        raise ValueError(f"field {name!r}: a parameter is given twice in {pairs!r}")
    for key in given:
        if key not in spec:
            near = difflib.get_close_matches(str(key), spec, n=1)
            hint = f" (did you mean {near[0]!r}?)" if near else ""
            raise ValueError(f"field {name!r} has no parameter {key!r}{hint}; "
                             f"valid parameters: {sorted(spec)}")
    missing = sorted(k for k, (_, d) in spec.items() if d is _REQUIRED and k not in given)
    if missing:
        raise ValueError(f"field {name!r} needs parameter(s) {missing}; "
                         f"valid parameters: {sorted(spec)}")
    out = {k: _value(name, k, kind, given.get(k, d)) for k, (kind, d) in spec.items()}
    return tuple(sorted(out.items()))


def _points(x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x must have shape (n, 2), got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x must be finite (no NaN or inf)")
    return x


@dataclass(frozen=True)
class Field:
    """A named closed-form field with parameters; evaluated with a material.

    Build with :meth:`named` (or ``Field(name, params)``; both validate). ``params``
    is normalised to a sorted tuple of ``(key, value)`` pairs including the
    defaults, with floats and ``(x, y)`` tuples, so equal fields compare equal.

    Fields and parameters (defaults in brackets):

    - ``kirsch``: ``a``, ``centre`` [(0, 0)], ``sigma`` [1]. Hole of radius ``a``
      at ``centre``, remote stress ``sigma`` along x; seed 003 Eq. (35). Singular
      at the centre (ValueError there).
    - ``williams``: ``tip`` [(0, 0)], ``angle`` [0], ``KI`` [0], ``KII`` [0]. Crack
      ahead of ``tip`` along ``angle``, faces at theta = +-pi (seed 003 Eq. (60)
      and Anderson's Tables 2.1-2.2, see :mod:`efgkit.problem.exact.williams`). The
      displacement at the tip is 0; the stress there raises ValueError.
    - ``cantilever``: ``L``, ``D``, ``P`` [1]. Beam [0, L] x [-D/2, D/2]; the
      traction on x = L integrates to (0, +P); u = 0 at (0, 0).

    The cantilever is the meshless-literature form (Dolbow & Belytschko 1998):
    P > 0 is an upward (+y) end load and the free end deflects upward; give a
    negative P for a downward load. Its fixed end x = 0 is modelled by
    prescribing this field's displacement there (it is not zero on the whole edge).

    Examples
    --------
    >>> import numpy as np
    >>> from efgkit.problem.material import Elastic
    >>> f = Field.named("kirsch", a=1.0)
    >>> f.params
    (('a', 1.0), ('centre', (0.0, 0.0)), ('sigma', 1.0))
    >>> s = f.stress(np.array([[0.0, 1.0]]), Elastic(E=1.0, nu=0.3))
    >>> round(float(s[0, 0]), 12)        # stress concentration factor 3
    3.0
    >>> Field.named("williams", KI=1.0).as_dict()["tip"]
    [0.0, 0.0]
    >>> Field.named("kirsch", radius=1.0)
    Traceback (most recent call last):
    ...
    ValueError: field 'kirsch' has no parameter 'radius'; valid parameters: ['a', 'centre', 'sigma']
    """

    name: str
    params: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "params", _normalise(self.name, self.params))

    @classmethod
    def named(cls, name: str, **params) -> Field:
        """The field ``name`` of :data:`FIELDS` with keyword parameters (validated)."""
        return cls(name, tuple(params.items()))

    def as_dict(self) -> dict:
        """``{"name": ..., **params}`` with points as lists; ``Field.named(**d)`` rebuilds it."""
        return {"name": self.name,
                **{k: list(v) if isinstance(v, tuple) else v for k, v in self.params}}

    def _eval(self, which: str, x, material) -> np.ndarray:
        if not isinstance(material, Elastic):
            raise TypeError(f"material must be an Elastic, got {type(material).__name__}")
        out = getattr(FIELDS[self.name], which)(_points(x), material, **dict(self.params))
        if not np.all(np.isfinite(out)):
            raise ValueError(f"{self.name} field: {which} overflowed to inf/NaN at some of x")
        return out

    def displacement(self, x: np.ndarray, material: Elastic) -> np.ndarray:
        """Displacement at ``x (n, 2)``, shape (n, 2) as (u_x, u_y)."""
        return self._eval("displacement", x, material)

    def stress(self, x: np.ndarray, material: Elastic) -> np.ndarray:
        """Stress at ``x (n, 2)``, shape (n, 3), Voigt (xx, yy, xy)."""
        return self._eval("stress", x, material)

    def strain(self, x: np.ndarray, material: Elastic) -> np.ndarray:
        """Strain at ``x (n, 2)``, shape (n, 3), Voigt with engineering shear: C sigma."""
        return self.stress(x, material) @ material.compliance().T


def field_errors(exact: Field | None, scene, x: np.ndarray, w: np.ndarray, u: np.ndarray,
                 strain: np.ndarray) -> dict:
    """Relative L2 displacement and energy-norm errors of a computed field against ``exact``
    (default ``scene.exact``), in ``scene.material``.

    ``x (n, 2)``, ``w (n,)`` a quadrature rule of the body, ``u (n, 2)`` and
    ``strain (n, 3)`` (Voigt, engineering shear) the computed field there. The energy
    norm is seed 003 Eq. (36), ``[1/2 int (sigma - sigma^h):(eps - eps^h)]^(1/2)``,
    divided by the same norm of the exact field.

    Returns
    -------
    dict with ``l2`` and ``energy`` (relative) and the absolute ``energy_abs``.
    """
    exact = scene.exact if exact is None else exact
    if exact is None:
        raise ValueError("no exact field: give errors(exact=Field) or Scene(exact=...)")
    material = scene.material
    ue, se = exact.displacement(x, material), exact.stress(x, material)
    ee = se @ material.compliance().T
    de = ee - strain
    e_abs = np.sqrt(0.5 * np.sum(w * np.einsum("ni,ij,nj->n", de, material.D, de)))
    e_ref = np.sqrt(0.5 * np.sum(w * np.einsum("ni,ni->n", se, ee)))
    l2 = np.sqrt(np.sum(w * ((u - ue) ** 2).sum(1)) / np.sum(w * (ue**2).sum(1)))
    return {"l2": float(l2), "energy": float(e_abs / e_ref), "energy_abs": float(e_abs)}
