"""The load–approach curve (docs/model.md §6), integrated with diffrax.

The stiffness is the slope of the load–approach curve, so between a reference preload F0 and F

    δ(F) - δ(F0) = ∫_{F0}^{F} dF' / K_t(F'),   i.e.   dδ/d(ln F) = F / K_t(F).

The absolute approach from zero load diverges for D ≥ 1.5 (K_t → 0 too fast as F → 0), so the
curve is always relative to a preload. Integrated in dimensionless form, `dδ*/d ln F* = F*/K*`
with `δ* = δ / sqrt(A_a)`, by adaptive Tsit5 solves from F0 upwards and downwards;
differentiable (reverse mode) with respect to every float field of the scene.
"""

from __future__ import annotations

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp

from .. import programs
from ..core import Scene, kink_log_loads, point_solver, prepare
from ..numerics import LoadsLike
from ..numerics._compat import checks_without_host_callbacks, top_level
from ..programs import padded, unpadded
from ..quantities import Scales, Status
from ._approach_sum import Approach


@eqx.filter_jit
def _approach(scene: Scene, loads, reference_load, rtol: float, max_steps: int):
    scales = Scales.of(scene)
    one_point = point_solver(scene)
    log_F = jnp.log(loads.reshape(-1) / scales.load)
    log_F0 = jnp.log(reference_load / scales.load)

    def stiffness_star(log_F_star):
        return one_point(jnp.exp(log_F_star)).stiffness_star

    point_status = jax.vmap(lambda t: one_point(jnp.exp(t)).status)(log_F)
    reference = one_point(jnp.exp(log_F0))
    scale = jnp.exp(log_F0) / reference.stiffness_star  # δ* per unit ln F* near the preload
    scale = jnp.where(jnp.isfinite(scale), scale, 1.0)
    # Integrated outward from the preload, once upwards and once downwards: starting at the
    # smallest load instead would make δ(F) - δ(F0) the difference of two larger, equally
    # uncertain integrals, and lose the tolerance to cancellation for loads near F0. Flagged
    # loads sit at the preload (distance 0) and are masked after the solve, so that the path
    # only spans valid loads: one bad point must not stop the integration for the others.
    offsets = jnp.where(point_status == Status.OK, log_F - log_F0, 0.0)

    directions = jnp.array([1.0, -1.0], log_F.dtype)
    distance = jnp.maximum(directions[:, None] * offsets[None, :], 0.0)  # (branch, load)
    reach = distance.max(axis=1)

    def slope(tau, y, args):
        # Both branches in one solve (one compiled ODE, not a vmapped pair); each stops at its
        # farthest load, where its slope drops to zero (a jump the controller steps to).
        inside = tau <= reach
        log_F_star = log_F0 + directions * jnp.minimum(tau, reach)
        return jnp.where(inside, directions * jnp.exp(log_F_star) / jax.vmap(stiffness_star)(log_F_star), 0.0)

    # A step across a kink of K(F) (a_l crossing a regime boundary) loses Tsit5's order and its
    # error estimate; stepping to each kink keeps the solve within its tolerance.
    kinks = directions[:, None] * (kink_log_loads(scene)[None, :] - log_F0)
    kinks = jnp.where(jnp.isfinite(kinks) & (kinks > 0), kinks, -1.0)
    times = distance.reshape(-1)
    order = jnp.argsort(times)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(slope),
        diffrax.Tsit5(),
        t0=jnp.zeros_like(log_F0),
        t1=reach.max(),
        dt0=None,
        y0=jnp.zeros_like(directions),
        saveat=diffrax.SaveAt(ts=times[order]),
        stepsize_controller=diffrax.PIDController(
            rtol=0.1 * rtol, atol=1e-4 * rtol * scale, jump_ts=jnp.sort(jnp.concatenate([kinks.reshape(-1), reach]))
        ),
        max_steps=max_steps,
        throw=False,
    )
    saved = jnp.where(sol.result == diffrax.RESULTS.successful, sol.ys, jnp.nan)  # (time, branch)
    by_time = jnp.zeros_like(saved).at[order].set(saved).reshape(2, -1, 2)  # (branch of the time, load, branch)
    upward, downward = by_time[0, :, 0], by_time[1, :, 1]
    delta = jnp.where(offsets >= 0, upward, downward) * scales.length
    status = jnp.where(point_status != Status.OK, point_status, reference.status)
    status = jnp.where((status == Status.OK) & ~jnp.isfinite(delta), Status.NOT_CONVERGED, status)
    delta = jnp.where(status == Status.OK, delta, jnp.nan)
    return Approach(loads, reference_load, delta.reshape(loads.shape), status.reshape(loads.shape).astype(jnp.int32))


def approach(
    scene: Scene,
    loads: LoadsLike,
    reference_load: float,
    *,
    rtol: float | None = None,
    max_steps: int = 4096,
) -> Approach:
    """Normal approach of the joint relative to a preload, docs/model.md §6.

    **Arguments:**

    - `scene`: the joint and the model choices.
    - `loads`: loads F (N), any shape; they may lie above or below the preload.
    - `reference_load`: the preload F0 (N) at which the approach is zero.
    - `rtol`: relative accuracy asked of each δ(F) − δ(F0) (default 1e-10 in float64, 1e-5 in
      float32). The adaptive solve controls its local error at `rtol / 10`, because the global
      error of a local-error controller grows to a few times its tolerance.
    - `max_steps`: cap on ODE steps.

    **Returns:** an `Approach`; `approach[i] = δ(F_i) − δ(F0)` in metres (negative below F0).
    """
    if not isinstance(reference_load, jax.core.Tracer):
        prepare(scene, reference_load)  # the same checks as a load: positive and finite
    scene, loads = prepare(scene, loads)
    reference_load = jnp.asarray(reference_load, loads.dtype)
    if rtol is None:
        rtol = 1e-10 if loads.dtype == jnp.float64 else 1e-5
    # Concrete loads padded to the solve's buckets: a new number of loads is not a new compilation.
    padded_loads = padded(loads)
    # Exported only where it can be (no host callback in diffrax's checks), else it would be traced
    # for nothing.
    if programs.keeping() and top_level() and checks_without_host_callbacks():
        result = _kept_approach(scene, padded_loads, reference_load, rtol, max_steps)
    else:
        result = _approach(scene, padded_loads, reference_load, rtol, max_steps)
    if padded_loads is loads:
        return result
    load, delta, status = unpadded((result.load, result.approach, result.status), padded_loads.size, loads.shape)
    return Approach(load, result.reference_load, delta, status)


def _kept_approach(scene: Scene, loads, reference_load, rtol: float, max_steps: int) -> Approach:
    """`_approach` through its program in the current store (the command line's on disk): a later
    process neither traces nor compiles it (tracing alone is ~4 s)."""
    leaves, treedef = jax.tree_util.tree_flatten(scene)

    def flat(leaves, loads, reference_load):
        scene = jax.tree_util.tree_unflatten(treedef, leaves)
        return jax.tree_util.tree_leaves(_approach(scene, loads, reference_load, rtol, max_steps))

    args = (leaves, loads, reference_load)
    run = programs.program("approach", f"{rtol!r}-{max_steps}", flat, args, closed_over=(treedef,))
    return Approach(*run(*args))
