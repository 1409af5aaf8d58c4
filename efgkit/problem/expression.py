"""Loads and prescribed displacements as expressions of x and y, parsed safely.

An :class:`Expression` is a formula in ``x`` and ``y`` (the point's coordinates) written as
text, as a scene file holds it (``uy = "1e-3 * x"``, ``t = ["0", "p0 * (1 - (x / b)**2)"]``
with ``p0`` and ``b`` given as numbers). It is parsed with :mod:`ast` and evaluated by walking
the tree: nothing is passed to ``eval`` or ``compile``, and only these nodes are accepted

* numbers, the names ``x``, ``y``, ``pi``, ``e`` and the constants given with the
  expression;
* ``+ - * / ** %`` and unary ``+ -``;
* calls of the functions in :data:`FUNCTIONS` (numpy's, element-wise) with positional
  arguments.

Anything else (attributes, subscripts, comparisons, keywords, lambdas, other names) is a
ValueError naming the offending piece. Values are evaluated in float64 with the
floating-point warnings silenced; a NaN or inf result is refused where the value is used
(:func:`~efgkit.problem.scene.evaluate_component`, :func:`~efgkit.problem.scene.evaluate_vector`).
"""

from __future__ import annotations

import ast
import math

import numpy as np

__all__ = ["FUNCTIONS", "Expression", "VectorExpression"]

FUNCTIONS = {name: getattr(np, name) for name in (
    "sin", "cos", "tan", "arcsin", "arccos", "arctan", "arctan2", "sinh", "cosh", "tanh", "exp",
    "log", "log10", "sqrt", "abs", "hypot", "minimum", "maximum", "sign", "floor", "ceil")}
_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide,
           ast.Pow: np.power, ast.Mod: np.mod}
_UNARY = {ast.UAdd: np.positive, ast.USub: np.negative}
MAX_LENGTH = 1000  # characters of one expression


def _check(node, names: set, text: str) -> None:
    """Raise ValueError unless every node of the tree is allowed."""
    called = {id(c.func) for c in ast.walk(node) if isinstance(c, ast.Call)}
    for sub in ast.walk(node):
        if isinstance(sub, (ast.Expression, ast.Load, ast.operator, ast.unaryop)):
            if isinstance(sub, ast.operator) and type(sub) not in _BINARY:
                raise ValueError(f"expression {text!r}: operator {type(sub).__name__} is not allowed "
                                 "(allowed: + - * / ** %)")
            continue
        if isinstance(sub, ast.Constant):
            if isinstance(sub.value, bool) or not isinstance(sub.value, (int, float)):
                raise ValueError(f"expression {text!r}: constant {sub.value!r} is not a number")
        elif isinstance(sub, ast.Name):
            if sub.id not in names and not (sub.id in FUNCTIONS and id(sub) in called):
                raise ValueError(f"expression {text!r}: unknown name {sub.id!r}; allowed: x, y, pi, "
                                 f"e and calls of the functions {sorted(FUNCTIONS)}")
        elif isinstance(sub, ast.Call):
            if not isinstance(sub.func, ast.Name) or sub.func.id not in FUNCTIONS or sub.keywords:
                raise ValueError(f"expression {text!r}: only calls of {sorted(FUNCTIONS)} with "
                                 "positional arguments are allowed")
        elif not isinstance(sub, (ast.BinOp, ast.UnaryOp)):
            raise ValueError(f"expression {text!r}: {type(sub).__name__} is not allowed (only "
                             "numbers, x, y, arithmetic and numpy functions)")


def _eval(node, env: dict):
    if isinstance(node, ast.Expression):
        return _eval(node.body, env)
    if isinstance(node, ast.Constant):
        return np.float64(node.value)
    if isinstance(node, ast.Name):
        return env[node.id]
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](_eval(node.left, env), _eval(node.right, env))
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_eval(node.operand, env))
    return FUNCTIONS[node.func.id](*(_eval(a, env) for a in node.args))  # a checked Call


class Expression(str):
    """A scalar formula in ``x``, ``y``: called with points ``x (n, 2)`` it returns ``(n,)``.

    An immutable string (the formula as written, which is what a scene file stores) that
    checks itself when made and evaluates itself when called.

    Parameters
    ----------
    source : str
        The formula, e.g. ``"1e-3 * x + sin(pi * y)"``.

    Examples
    --------
    >>> f = Expression("3 * (1 - (x / 2)**2)")
    >>> f(np.array([[0.0, 5.0], [1.0, 0.0], [2.0, 0.0]])).tolist()
    [3.0, 2.25, 0.0]
    >>> Expression("__import__('os')")
    Traceback (most recent call last):
    ...
    ValueError: expression "__import__('os')": only calls of [...] with positional arguments are allowed
    """

    def __new__(cls, source: str):
        if isinstance(source, Expression):
            return source
        if not isinstance(source, str):
            raise TypeError(f"an expression must be a string, got {type(source).__name__}")
        if len(source) > MAX_LENGTH:
            raise ValueError(f"expression of {len(source)} characters: at most {MAX_LENGTH}")
        self = super().__new__(cls, source)
        try:
            tree = ast.parse(source.strip(), mode="eval")
            _check(tree, {"x", "y", "pi", "e"}, source)
            self._tree = tree
            self(np.zeros((1, 2)))  # nested too deeply to evaluate: refused here, not at the solve
        except SyntaxError as err:
            raise ValueError(f"expression {source!r} is not a formula: {err.msg}") from err
        except (RecursionError, MemoryError) as err:
            raise ValueError(f"expression {source[:40]!r}...: nested too deeply") from err
        return self

    def __call__(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        env = {"x": x[:, 0], "y": x[:, 1], "pi": np.float64(math.pi), "e": np.float64(math.e)}
        with np.errstate(all="ignore"):  # NaN / inf are refused where the value is used
            out = _eval(self._tree, env)
        return np.broadcast_to(np.asarray(out, dtype=float), (len(x),)).copy()

    def __repr__(self) -> str:
        return f"Expression({str(self)!r})"


class VectorExpression(tuple):
    """Two formulas ``(f_x, f_y)`` (strings or numbers): ``x (n, 2) -> (n, 2)``, for
    tractions and body forces; an immutable pair of :class:`Expression`.

    Examples
    --------
    >>> t = VectorExpression(("0", "-2 * x"))
    >>> t(np.array([[1.0, 0.0]])).tolist()
    [[0.0, -2.0]]
    """

    def __new__(cls, sources):
        if not isinstance(sources, (tuple, list)) or len(sources) != 2:
            raise ValueError(f"a vector expression needs two formulas [f_x, f_y], got {sources!r}")
        for s in sources:
            if isinstance(s, bool) or not isinstance(s, (str, int, float)):
                raise TypeError(f"a vector expression holds formulas or numbers, got {s!r}")
        return super().__new__(cls, tuple(Expression(s if isinstance(s, str) else repr(float(s)))
                                          for s in sources))

    def __call__(self, x) -> np.ndarray:
        return np.column_stack([f(x) for f in self])

    @classmethod
    def read(cls, v) -> VectorExpression | None:
        """``v`` as a VectorExpression when it is a pair holding a formula (a string), else
        None (scene-file values: ``["0", "-2 * x"]``)."""
        if isinstance(v, (list, tuple)) and len(v) == 2 and any(isinstance(s, str) for s in v):
            return cls(v)
        return None

    def __repr__(self) -> str:
        return f"VectorExpression({tuple(map(str, self))!r})"

