"""How `solve` solves and what it returns: options of the call, as diffrax takes `saveat=` and
`max_steps=` on `diffeqsolve`, never fields of the `Scene` (the joint and its model)."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp

from ..numerics import InputError


class Outputs(eqx.Module):
    """What `solve` returns beside the stiffness, the largest spot and the real area.

    **Arguments:** `regime_shares`, whether to split load and stiffness by the model's regimes
    (`Solution.load_share`, `stiffness_share`); with False those fields are None and nothing is
    spent on them. Static: changing it compiles a different program.
    """

    regime_shares: bool = eqx.field(static=True, default=True)

    def __check_init__(self):
        if not isinstance(self.regime_shares, bool):
            raise InputError(f"regime_shares = {self.regime_shares!r} must be true or false")


class NewtonBisection(eqx.Module):
    """The solve for each load's state (the largest spot a_l, or GW's separation): Newton's method
    safeguarded by bisection inside a bracket, differentiated by the implicit function theorem
    (`numerics.solve_increasing`).

    **Arguments:** `max_steps`, the cap on steps (1 to 10000; a point that reaches it is flagged
    `NOT_CONVERGED`); `tolerance` on the state's logarithm, None for 64 ε of the working dtype.
    Static: changing them compiles a different program.
    """

    max_steps: int = eqx.field(static=True, default=64)
    tolerance: float | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        steps = self.max_steps
        if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= 10_000:
            raise InputError(f"max_steps = {steps!r} must be an integer in [1, 10000]")
        if self.tolerance is not None and not 0.0 < self.tolerance < 1e-2:
            raise InputError(f"NewtonBisection: tolerance = {self.tolerance!r} must be None or in (0, 0.01)")

    def tolerance_for(self, dtype) -> float:
        """The tolerance in the working `dtype`."""
        return self.tolerance or float(64 * jnp.finfo(dtype).eps)
