"""Compile options for programs compiled once and run a few dozen times: the fit's.

XLA's CPU backend has two code generators for fused loops. The classic one compiles this package's
derivative programs in about half the time of the newer one (MLIR fusion emitters): the "paper"
Jacobian of 10 loads in 2.2–2.6 s against 4.9–5.1 s, the same arithmetic to ~1e-14. Its loops
run slower where the newer one vectorises better: the "paper" solve of 4096 loads 2.2x slower. So
the fit's program, which a first fit waits for and then runs ~10–100 times on 30 points, asks for
it, and so does the command line's solve of fewer loads than a chunk (a process that calls it a
few times); the library's solve, which users time and sweep over millions of loads, does not.
Executables of the classic emitters also survive serialisation (`exported.executable`).

A per-program option, so that no global setting changes; other backends ignore it.
"""

from __future__ import annotations

import functools

import jax
import numpy as np

from ..numerics.compat import top_level

FAST_COMPILE = {"xla_cpu_use_fusion_emitters": False}


@functools.cache
def compiler_options() -> dict:
    """`FAST_COMPILE` where this jaxlib knows the option, else none (checked once per process)."""
    try:
        jax.jit(lambda x: x + 1, compiler_options=FAST_COMPILE).lower(np.float32(0)).compile()
    except Exception:  # noqa: BLE001 (an unknown option only costs compile time)
        return {}
    return dict(FAST_COMPILE)


class FastCompile:
    """`jax.jit(function)`, compiled with `compiler_options()` when called outside any trace.

    JAX takes compile options for top-level programs only; inside a caller's `jit`, `grad` or
    `vmap` it is the caller's program that gets compiled, and `plain` (the same function under a
    plain `jax.jit`) is called.
    """

    def __init__(self, function):
        self.top_level = jax.jit(function, compiler_options=compiler_options())
        self.plain = jax.jit(function)

    def __call__(self, *args):
        return (self.top_level if top_level() else self.plain)(*args)
