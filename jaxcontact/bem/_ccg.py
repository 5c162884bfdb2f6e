"""Load-controlled contact by constrained conjugate gradients (Polonsky & Keer 1999; Bugnicourt,
Sainsot, Dureisseix & Lubrecht 2018), with the pressure capped at a hardness (the saturated
"perfectly plastic" surface of Almqvist et al. 2007).

The pressure p ≥ 0 (≤ H) on the grid minimises `½ pᵀCp − pᵀh` at a fixed total `Σp`: the gap
`g = Cp − h − δ` vanishes where `0 < p < H`, is ≥ 0 where `p = 0` and ≤ 0 where `p = H` (plastic
flow), and δ, the rigid offset, is the constraint's multiplier. Conjugate-gradient steps run on the
points strictly between the bounds; a bound point whose gap says it should move inward joins them
and (in Polonsky & Keer's plain iteration) restarts the conjugacy; after each step the pressure is
clipped to its bounds and shifted on the free points so that the total stays the load. Everything
is in the grid units of `_operator`.

Preconditioned (the default), each step searches along the gap multiplied by the periodic
compliance's inverse `|q|/2` (`Compliance.inverse`, two FFTs), held to zero mean on the set it
moves: the inverse of C on the whole grid stands in for the inverse of C on the free set. Bound
points whose gap says they should move inward then join the search set itself, so that the line
search weighs how they press on each other (moved one by one, thousands of them in a step overshoot
together). Their joining does not restart the conjugacy: near convergence one or two points at the
edge of a contact patch join in most steps, and restarting at each makes the iteration a
preconditioned steepest descent (84 steps on a 512² map at 21 % contact, where this one takes 45).
Powell's test restarts it instead, when the gap has lost its orthogonality to the last direction
(joins, leaves and clipping at the bounds all do that). Where more points sit at the cap than
between the bounds, joins still restart it, as in the plain iteration: kept through them there, the
iteration cycles on some nearly all-capped contacts. The iterations then grow with the grid about as
n^0.4 where the plain ones grow as n: 45, 58, 75 at 11-22 % contact on 512², 1024², 2048², against
293, 426, 851 (docs/validation.md).

Where nearly every contact point sits at the cap (the free set below 1 % of the contact area, e.g. a
rough surface whose elastic pixel pressures exceed H fifty-fold), the CG has nothing left to
steer and cycles. There, as ContactMechanics's plastic system does, the iteration switches to
*mixing* steps: the bearing-area solution of the current gap (the `F/H` points of smallest gap at
p = H) is blended into the pressure with a weight that decays geometrically, the total restored
by a multiplicative rescale, for at least `_MIX_STEPS` steps before CG steps resume.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from ._operator import Compliance

# Shifts that restore the total after clipping (each can push a few small pressures below zero or
# above the cap). Without a cap one shift per step suffices: a pressure it pushes below zero is
# clipped, and the next step's shift restores the total (the same contact sets and offsets, to
# round-off, with about a tenth less time per step).
_LOAD_PASSES = 3
# ContactMechanics's mixing rule (`constrained_conjugate_gradients`: mixfac, mixdecfac, minmixsteps),
# and its switch: mix when the CG-controlled set is below this share of the contact area.
_MIX_FACTOR, _MIX_DECAY, _MIX_STEPS, _MIN_FREE_SHARE = 0.1, 0.95, 10, 0.01
# Powell's (1977) restart test: the conjugacy restarts when the gap is no longer nearly orthogonal to
# the last direction, |g·t_prev| > this × g·z, which exact line searches on a fixed set keep at 0.
_POWELL = 0.2


class ContactState(eqx.Module):
    """Where the iteration stands: pressure, search direction, conjugacy, count, and the result."""

    pressure: Float[Array, "n n"]
    direction: Float[Array, "n n"]
    previous_norm: Float[Array, ""]
    restart: Bool[Array, ""]
    iterations: Int[Array, ""]
    converged: Bool[Array, ""]
    offset: Float[Array, ""]
    residual: Float[Array, ""]
    mix_factor: Float[Array, ""]
    mix_steps: Int[Array, ""]


def _masked_sum(mask, x):
    return jnp.sum(jnp.where(mask, x, 0.0))


def _masked_mean(mask, x):
    return _masked_sum(mask, x) / jnp.maximum(jnp.sum(mask, dtype=x.dtype), 1.0)


def _with_total(pressure, total, hardness, passes: int = _LOAD_PASSES):
    """Clip to [0, H] and shift the points strictly inside so that the sum is `total` (in `passes`)."""
    for _ in range(passes):
        pressure = jnp.clip(pressure, 0.0, hardness)
        inside = (pressure > 0) & (pressure < hardness)
        count = jnp.sum(inside, dtype=pressure.dtype)
        shift = (total - jnp.sum(pressure)) / jnp.maximum(count, 1.0)
        pressure = jnp.where(inside, pressure + shift, pressure)
    return jnp.clip(pressure, 0.0, hardness)


def _bearing_mix(raw, pressure, total, hardness, factor):
    """One mixing step: toward the bearing-area solution of the gap `raw` (the `total / H` points of
    smallest gap at p = H), by `factor`, then rescaled to `total` and capped."""
    count = jnp.clip(jnp.ceil(total / hardness).astype(jnp.int32), 1, raw.size)
    threshold = jnp.sort(raw.reshape(-1))[count - 1]
    bearing = jnp.where(raw <= threshold, hardness, 0.0)
    mixed = (1 - factor) * pressure + factor * bearing
    return jnp.minimum(mixed * (total / jnp.maximum(jnp.sum(mixed), jnp.finfo(raw.dtype).tiny)), hardness)


def gaps(compliance: Compliance, heights, pressure, hardness):
    """The gap without offset, the set strictly between the bounds, and the offset that makes the
    gap's mean over that set zero (the load-control multiplier)."""
    raw = compliance(pressure) - heights
    free = (pressure > 0) & (pressure < hardness)
    offset = _masked_mean(free, raw)
    return raw - offset, free, offset


def contact_cg(
    compliance: Compliance,
    heights: Float[Array, "n n"],
    total: Float[Array, ""],
    hardness: Float[Array, ""] | Float[Array, "n n"],
    initial: Float[Array, "n n"],
    tolerance: float,
    max_iterations: int,
    capped: bool = True,
    preconditioned: bool = True,
) -> ContactState:
    """The pressure that carries `total` on `heights` (grid units), from `initial`.

    Converged when the gap on the free points, the penetration where p = 0 and the separation where
    p = H are all below `tolerance` (in the height unit). `capped = False` (an infinite `hardness`,
    known before tracing) leaves the mixing branch out: under `vmap` a branch is computed whether
    taken or not, and the bearing-area step's sort costs several FFTs. `preconditioned`: search along
    the Fourier-preconditioned gap (above); False is Polonsky & Keer's plain iteration.
    """

    passes = _LOAD_PASSES if capped else 1
    # A cap per point (the tangential problem's μp, `_slip`): a point whose cap is 0 stays at 0, and
    # the bearing-area mixing, which spreads the load over the smallest gaps at one cap, does not apply.
    per_point = jnp.ndim(hardness) > 0
    mixes = capped and not per_point

    def movable(x):
        return (x & (hardness > 0)) if per_point else x

    def search(gap, moving):
        """The gap on the points that move, preconditioned (their load held: mean zero on them)."""
        if not preconditioned:
            return gap
        z = compliance.inverse(jnp.where(moving, gap, 0.0))
        return z - _masked_mean(moving, z)

    def residual_of(gap, pressure):
        free = (pressure > 0) & (pressure < hardness)
        at_zero, at_cap = movable(pressure <= 0), movable(pressure >= hardness)
        return jnp.max(jnp.where(free, jnp.abs(gap), jnp.where(at_zero, -gap, jnp.where(at_cap, gap, 0.0))).reshape(-1))

    def cg_step(state: ContactState, gap, free, norm):
        p, t = state.pressure, state.direction
        # Bound points whose gap says they should move inward: penetration where p = 0, separation
        # where p = H. They join the free set; the conjugacy restarts. Preconditioned, they join the
        # search set at once, so that the line search weighs how they press on each other.
        wrong = movable(((p <= 0) & (gap < 0)) | ((p >= hardness) & (gap > 0)))
        any_wrong = jnp.any(wrong)
        moving = free | wrong if preconditioned else free
        steepest = search(gap, moving)
        restart = state.restart | (state.previous_norm <= 0)
        # `held`: a join that restarts the conjugacy now and at the next step.
        if preconditioned:
            restart |= jnp.abs(_masked_sum(moving, gap * t)) > _POWELL * _masked_sum(moving, gap * steepest)
            # Only where more points sit at the cap than between the bounds: kept through joins
            # there, the iteration cycles on some nearly all-capped contacts.
            held = any_wrong & (jnp.sum(movable(p >= hardness)) > jnp.sum(free)) if capped else jnp.array(False)
            restart |= held
        else:
            held = any_wrong  # the plain iteration's rule
        beta = jnp.where(restart, 0.0, norm / state.previous_norm)
        t = jnp.where(moving, steepest + beta * t, 0.0)
        r = compliance(t)
        r = r - _masked_mean(moving, r)
        curvature = _masked_sum(moving, r * t)
        tau = jnp.where(curvature > 0, _masked_sum(moving, gap * t) / jnp.where(curvature > 0, curvature, 1.0), 0.0)
        moved = jnp.where(moving, p - tau * t, p)
        if not preconditioned:
            moved = jnp.where(wrong, p - jnp.where(tau > 0, tau, 1.0) * gap, moved)
        return _with_total(moved, total, hardness, passes), t, held

    def step(state: ContactState) -> ContactState:
        p = state.pressure
        gap, free, offset = gaps(compliance, heights, p, hardness)
        residual = residual_of(gap, p)
        converged = residual <= tolerance
        norm = _masked_sum(free, gap * search(gap, free))
        in_contact = jnp.sum(p > 0, dtype=p.dtype)
        if mixes:
            mixing = (state.mix_steps > 0) | (
                (in_contact > 0) & (jnp.sum(free, dtype=p.dtype) <= _MIN_FREE_SHARE * in_contact)
            )
            moved, t, restart = jax.lax.cond(
                mixing,
                lambda: (
                    _bearing_mix(gap + offset, p, total, hardness, state.mix_factor),
                    jnp.zeros_like(p),
                    jnp.array(True),
                ),
                lambda: cg_step(state, gap, free, norm),
            )
        else:
            mixing = jnp.array(False)
            moved, t, restart = cg_step(state, gap, free, norm)
        # A mixing run lasts `_MIX_STEPS` steps with a decaying weight; a CG step resets both.
        mix_steps = jnp.where(mixing, jnp.where(state.mix_steps > 0, state.mix_steps - 1, _MIX_STEPS - 1), 0)
        mix_factor = jnp.where(mixing, state.mix_factor * _MIX_DECAY, _MIX_FACTOR)
        keep = converged
        return ContactState(
            pressure=jnp.where(keep, p, moved),
            direction=jnp.where(keep, state.direction, t),
            previous_norm=jnp.where(keep, state.previous_norm, jnp.where(mixing, 0.0, norm)),
            restart=jnp.where(keep, state.restart, restart),
            iterations=state.iterations + jnp.where(keep, 0, 1),
            converged=converged,
            offset=offset,
            residual=residual,
            mix_factor=jnp.where(keep, state.mix_factor, mix_factor),
            mix_steps=jnp.where(keep, state.mix_steps, mix_steps),
        )

    def running(state: ContactState):
        return ~state.converged & (state.iterations < max_iterations)

    dtype = heights.dtype
    start = ContactState(
        pressure=_with_total(initial, total, hardness),
        direction=jnp.zeros_like(heights),
        previous_norm=jnp.zeros((), dtype),
        restart=jnp.array(True),
        iterations=jnp.zeros((), jnp.int32),
        converged=jnp.array(False),
        offset=jnp.zeros((), dtype),
        residual=jnp.full((), jnp.inf, dtype),
        mix_factor=jnp.asarray(_MIX_FACTOR, dtype),
        mix_steps=jnp.zeros((), jnp.int32),
    )
    state = jax.lax.while_loop(running, step, start)
    # The loop's last step may have moved p past the check: check the final pressure once more.
    gap, _, offset = gaps(compliance, heights, state.pressure, hardness)
    residual = residual_of(gap, state.pressure)
    return eqx.tree_at(lambda s: (s.converged, s.offset, s.residual), state, (residual <= tolerance, offset, residual))
