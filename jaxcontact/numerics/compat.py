"""What differs between the JAX versions jaxcontact supports (`pyproject.toml`'s lower bounds)."""

from __future__ import annotations

import jax


def x64(enabled: bool):
    """A context in which float64 is on (`True`) or off: `jax.enable_x64` where it exists (newer
    JAX), `jax.experimental.enable_x64` before that."""
    context = getattr(jax, "enable_x64", None)
    if context is None:
        from jax.experimental import enable_x64 as context
    return context(enabled)
