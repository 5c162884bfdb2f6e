"""What differs between the JAX and equinox versions jaxcontact supports (`pyproject.toml`'s lower
bounds), and the only places that read or set their private state."""

from __future__ import annotations

import importlib
import sys

import jax
import jax.numpy as jnp
import numpy as np


def x64(enabled: bool):
    """A context in which float64 is on (`True`) or off: `jax.enable_x64` where it exists (newer
    JAX), `jax.experimental.enable_x64` before that."""
    context = getattr(jax, "enable_x64", None)
    if context is None:
        from jax.experimental import enable_x64 as context
    return context(enabled)


try:  # JAX has no public test for "not inside a trace"; its private one, where it exists
    from jax._src.core import trace_state_clean as _trace_state_clean
except ImportError:
    _trace_state_clean = None


def top_level() -> bool:
    """Whether no transformation (`jit`, `grad`, `vmap`, ...) is tracing; `False` where this JAX
    cannot say (callers then take the path that also works inside a trace)."""
    return _trace_state_clean is not None and _trace_state_clean()


try:  # likewise for "a program is being staged" (`jit`, `make_jaxpr`, a loop's body)
    from jax._src.core import unsafe_am_i_under_a_jit as _staging
except ImportError:
    _staging = None


def staging() -> bool:
    """Whether the caller's program is being staged (under `jit`, whatever transformations sit
    above it); `False` where this JAX cannot say (callers then take the path that works eagerly)."""
    return _staging is not None and _staging()


def namespace(*arrays):
    """`numpy` where every argument is a host value (numpy array or scalar, Python number), else
    `jax.numpy`: the properties of a result held on the host (`solve_sweep`'s) stay on the host,
    with no dispatch (and, in a new process, no compilation) per property."""
    host = all(isinstance(x, (np.ndarray, np.generic, int, float, bool)) for x in arrays)
    return np if host else jnp


# Equinox reads `EQX_ON_ERROR` when it is imported, into its private `_errors` module; the two
# functions below are the only places that touch it.
_CALLBACK_FREE = ("nan", "off")


def checks_without_host_callbacks() -> bool:
    """Whether equinox's run-time checks (`error_if`, which diffrax uses to check its save times)
    trace without a host callback: `EQX_ON_ERROR` "nan" or "off". JAX can neither export a program
    holding a host callback nor keep it in its persistent compilation cache."""
    errors = sys.modules.get("equinox._errors")
    return getattr(errors, "EQX_ON_ERROR", "raise") in _CALLBACK_FREE


def avoid_host_callbacks_in_checks() -> None:
    """Make equinox's run-time checks give NaN instead of raising through a host callback, for the
    rest of the process (as `EQX_ON_ERROR=nan` would, had it been set before equinox's import).
    Process-wide: equinox caches its traced checks, so a setting restored later would still leak
    into programs traced afterwards. An equinox without the private module is left as it is."""
    try:
        errors = importlib.import_module("equinox._errors")
    except ImportError:
        return
    if getattr(errors, "EQX_ON_ERROR", None) == "raise":
        errors.EQX_ON_ERROR = "nan"


def complex_dtype(dtype):
    """The complex dtype of a real one's precision (complex128 for float64, complex64 for float32),
    without the implicit promotion that JAX's strict mode refuses."""
    return jnp.complex128 if jnp.dtype(dtype) == jnp.float64 else jnp.complex64


def standard_promotion():
    """A context with JAX's standard dtype promotion, around the third-party code this package calls
    that is not clean under strict promotion (blackjax's warm-up schedule, quadax's adaptive
    rule): a user who runs with `jax_numpy_dtype_promotion="strict"` gets results, not their
    errors. This package's own code is strict-clean; the setting is restored on leaving."""
    return jax.numpy_dtype_promotion("standard")
