"""What differs between the JAX versions jaxcontact supports (`pyproject.toml`'s lower bounds)."""

from __future__ import annotations

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


def namespace(*arrays):
    """`numpy` where every argument is a host value (numpy array or scalar, Python number), else
    `jax.numpy`: the properties of a result held on the host (`solve_sweep`'s) stay on the host,
    with no dispatch (and, in a new process, no compilation) per property."""
    host = all(isinstance(x, (np.ndarray, np.generic, int, float, bool)) for x in arrays)
    return np if host else jnp
