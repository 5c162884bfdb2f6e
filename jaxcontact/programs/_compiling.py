"""Compile options for programs compiled once and run a few dozen times: the fit's.

XLA's CPU backend has two code generators for fused loops. The classic one compiles this package's
derivative programs in about half the time of the newer one (MLIR fusion emitters): the "paper"
Jacobian of 10 loads in 2.2–2.6 s against 4.9–5.1 s, the same arithmetic to ~1e-14. Its loops
run slower where the newer one vectorises better: the "paper" solve of 4096 loads 2.2x slower. So
the fit's program, which a first fit waits for and then runs ~10–100 times on 30 points, asks for
it, and so does the command line's solve of fewer loads than a chunk (a process that calls it a
few times); the library's solve, which users time and sweep over millions of loads, does not.
Executables of the classic emitters also survive serialisation (`exported.executable`).

LLVM's optimisation level 1 (of 3; XLA's default is 2) takes another quarter off: the "paper"
Jacobian 3.6–3.7 → 2.7–2.8 s; the first fit in a fresh process 6.0–6.6 → 5.7–6.2 s, its later
fits ~8 % slower (LM on 30 points 0.067–0.069 → 0.072–0.079 s). Level 0 is never asked for: with
the classic emitters jaxlib 0.10.2 computes wrong numbers at that level.

Per-program options, so that no global setting changes; other backends ignore them.
"""

from __future__ import annotations

import jax
import numpy as np

from ..numerics import cached
from ..numerics._compat import top_level

FAST_COMPILE = {"xla_cpu_use_fusion_emitters": False, "xla_backend_optimization_level": 1}


@cached
def compiler_options() -> dict:
    """`FAST_COMPILE` where this jaxlib knows the options, else none (checked once per process)."""
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
