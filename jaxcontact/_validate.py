"""Checks of configuration values that are known at construction time.

Values that are JAX tracers (inside `jit`, `grad`, `vmap`) cannot be checked here; the model
reports value-dependent failures per point through `Solution.status` instead.
"""

from __future__ import annotations

import math

import jax
import numpy as np


def as_float(value):
    """Python numbers become floats (so that `jax.grad` can target them); arrays pass through."""
    if isinstance(value, bool):
        raise ValueError(f"expected a number, got the boolean {value!r}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value)
    return value


def concrete(value) -> np.ndarray | None:
    """The value as a float64 numpy array, or None while it is being traced."""
    if isinstance(value, jax.core.Tracer):
        return None
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"expected a number, got {value!r}") from exc


def _describe(values: np.ndarray) -> str:
    if values.ndim == 0:
        return f"{float(values):.6g}"
    return f"{np.array2string(values, precision=6, threshold=6)}"


def check_range(name: str, value, low: float = -math.inf, high: float = math.inf, *,
                low_open: bool = True, high_open: bool = True, meaning: str = "") -> None:
    """Raise `ValueError` unless every element of a concrete `value` lies in the interval."""
    values = concrete(value)
    if values is None:
        return
    ok = np.isfinite(values)
    ok &= (values > low) if low_open else (values >= low)
    ok &= (values < high) if high_open else (values <= high)
    if not np.all(ok):
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        interval = f"{left}{low:g}, {high:g}{right}"
        what = f" ({meaning})" if meaning else ""
        raise ValueError(f"{name}{what} = {_describe(values)} is outside its valid range {interval}")


def check_choice(name: str, value, choices: tuple[str, ...]) -> None:
    if value not in choices:
        allowed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} = {value!r} is not one of {allowed}")
