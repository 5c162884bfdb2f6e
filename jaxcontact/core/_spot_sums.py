"""Sums over a joint's spots of a law in `x = u/u*(a)`, each spot's `u*` its own (docs/in-service.md).

A spot of load P and normal unloading stiffness k, displaced tangentially, slides at
`u* = (μ/ratio)·3P/(2k)` with `ratio = k_t/k` (Cattaneo–Mindlin, `physics._mindlin`): `u* = factor ·
3P/(2k)`. In each family of `model.joint(s).spots(...)` u* grows with the spot's area (checked:
`monotone`), so at a displacement u the spots below one area have `x ≥ 1` and the rest `x < 1`:
each family is split there (by bisection; held, since the integrands agree there) and both parts
integrated by Gauss–Legendre, the part with `x < 1` in `t = t_s + L v²`, which makes its
`(t − t_s)^{3/2}` edge smooth.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ..models import SpotFamilies
from ..numerics._quadrature import integrate_log_area
from ..physics._mindlin import backbone, loop_energy, slip_displacement

_BISECTIONS = 60


def _split(families: SpotFamilies, log_slip_at, log_u):
    """The `t` in each family's range where `u*(t) = u` (clipped to the range), shape `log_u`'s
    broadcast against the families."""

    def step(_, bounds):
        low, high = bounds
        mid = 0.5 * (low + high)
        below = log_slip_at(mid) < log_u
        return jnp.where(below, mid, low), jnp.where(below, high, mid)

    shape = jnp.broadcast_shapes(log_u.shape, families.lower.shape)
    start = (jnp.broadcast_to(families.lower, shape), jnp.broadcast_to(families.upper, shape))
    low, high = jax.lax.fori_loop(0, _BISECTIONS, step, start)
    return jax.lax.stop_gradient(0.5 * (low + high))


def spot_sums(families: SpotFamilies, u, factor, nodes: int) -> dict:
    """Over the spots (dimensionless), at each displacement of the 1-D `u`, with `u* = factor · 3P/(2k)`:

    - `"force"`: `Σ P·B(u/u*)`, B the Cattaneo–Mindlin backbone `1 − (1 − x)^{3/2}` (1 beyond);
    - `"energy"`: `Σ P u* W(u/u*)`, W the Mindlin–Deresiewicz loop energy of one spot;
    - `"sliding"`: `Σ P` over the spots with `x ≥ 1`;

    and `"monotone"`, whether `u*` grows with the area in every family (checked on a grid).
    """

    def log_slip_at(t):
        _, load, stiffness = families.at(t)
        return jnp.log(slip_displacement(factor, load, stiffness))

    log_u = jnp.log(u)[:, None]
    split = _split(families, lambda t: log_slip_at(t[..., None])[..., 0], log_u)
    lower = jnp.broadcast_to(families.lower, split.shape)
    upper = jnp.broadcast_to(families.upper, split.shape)

    def g(t):
        """The three sums' integrands at t, stacked on a leading axis (one pass over the spots)."""
        count, load, stiffness = families.at(t)
        slip = slip_displacement(factor, load, stiffness)
        x = u[:, None, None] / slip
        per_spot = jnp.stack([load * backbone(x), load * slip * loop_energy(x), jnp.where(x >= 1.0, load, 0.0)])
        return count * per_spot

    # `integrate_log_area` weighs the integrand's trailing (node) axis: the stacked sums ride along.
    beyond = integrate_log_area(g, lower, split, nodes)
    length = (upper - split)[..., None]
    within = lambda v: g(split[..., None] + length * v * v) * 2.0 * length * v  # noqa: E731
    before = integrate_log_area(within, jnp.zeros_like(split), jnp.ones_like(split), nodes)
    force, energy, sliding = jnp.sum(beyond + before, axis=-1)

    grid = jnp.linspace(0.0, 1.0, 2 * nodes + 1)
    probe = families.lower[:, None] + (families.upper - families.lower)[:, None] * grid
    monotone = jnp.all(jnp.diff(log_slip_at(probe), axis=-1) >= 0.0)
    return {"force": force, "energy": energy, "sliding": sliding, "monotone": monotone}
