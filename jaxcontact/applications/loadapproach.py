"""The load–approach curve (MODEL.md §6), integrated with diffrax.

The stiffness is the slope of the load–approach curve, so between a reference preload F0 and F

    δ(F) - δ(F0) = ∫_{F0}^{F} dF' / K_t(F'),   i.e.   dδ/d(ln F) = F / K_t(F).

The absolute approach from zero load diverges for D ≥ 1.5 (K_t → 0 too fast as F → 0), so the
curve is always relative to a preload. Integrated in dimensionless form, `dδ*/d ln F* = F*/K*`
with `δ* = δ / sqrt(A_a)`, from the smallest to the largest of the loads and F0 in one adaptive
Tsit5 solve; differentiable (reverse mode) with respect to every float field of the scene.
"""

from __future__ import annotations

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float, Int

from ..core.loadcontrol import point_solver, prepare
from ..core.scales import Scales
from ..core.scene import Scene
from ..core.status import Status


class Approach(eqx.Module):
    """Result of `approach`: per load, the approach δ(F) − δ(F0) (m) and a status (0 = ok).

    A point is flagged (approach NaN) when the model is invalid at that load or at the preload;
    the other points are integrated along a path that avoids it.
    """

    load: Float[Array, "*loads"]
    reference_load: Float[Array, ""]
    approach: Float[Array, "*loads"]
    status: Int[Array, "*loads"]


@eqx.filter_jit
def _approach(scene: Scene, loads, reference_load, rtol: float, max_steps: int):
    scales = Scales.of(scene)
    one_point = point_solver(scene)
    log_F = jnp.log(loads.reshape(-1) / scales.load)
    log_F0 = jnp.log(reference_load / scales.load)

    def stiffness_star(log_F_star):
        return one_point(jnp.exp(log_F_star)).stiffness_star

    def slope(t, y, args):
        return jnp.exp(t) / stiffness_star(t)  # dδ*/d ln F*

    point_status = jax.vmap(lambda t: one_point(jnp.exp(t)).status)(log_F)
    reference = one_point(jnp.exp(log_F0))
    # Flagged loads sit at the preload during the solve (and are masked after it), so that the
    # path only spans valid loads: one bad point must not stop the integration for the others.
    ts = jnp.concatenate([jnp.where(point_status == Status.OK, log_F, log_F0), log_F0[None]])
    order = jnp.argsort(ts)
    ts_sorted = ts[order]
    scale = jnp.exp(log_F0) / reference.stiffness_star  # δ* per unit ln F* near the preload
    scale = jnp.where(jnp.isfinite(scale), scale, 1.0)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(slope),
        diffrax.Tsit5(),
        t0=ts_sorted[0],
        t1=ts_sorted[-1],
        dt0=None,
        y0=jnp.zeros_like(log_F0),
        saveat=diffrax.SaveAt(ts=ts_sorted),
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=1e-3 * rtol * scale),
        max_steps=max_steps,
        throw=False,
    )
    delta_sorted = jnp.where(sol.result == diffrax.RESULTS.successful, sol.ys, jnp.nan)
    delta = jnp.zeros_like(ts).at[order].set(delta_sorted)
    delta = (delta[:-1] - delta[-1]) * scales.length
    status = jnp.where(point_status != Status.OK, point_status, reference.status)
    status = jnp.where((status == Status.OK) & ~jnp.isfinite(delta), Status.NOT_CONVERGED, status)
    delta = jnp.where(status == Status.OK, delta, jnp.nan)
    return Approach(loads, reference_load, delta.reshape(loads.shape), status.reshape(loads.shape).astype(jnp.int32))


def approach(
    scene: Scene,
    loads: Float[ArrayLike, "*loads"],
    reference_load: float,
    *,
    rtol: float | None = None,
    max_steps: int = 4096,
) -> Approach:
    """Normal approach of the joint relative to a preload, MODEL.md §6.

    **Arguments:**

    - `scene`: the joint and the model choices.
    - `loads`: loads F (N), any shape; they may lie above or below the preload.
    - `reference_load`: the preload F0 (N) at which the approach is zero.
    - `rtol`: relative tolerance of the adaptive ODE solve (default 1e-10 in float64, 1e-5 in float32).
    - `max_steps`: cap on ODE steps.

    **Returns:** an `Approach`; `approach[i] = δ(F_i) − δ(F0)` in metres (negative below F0).
    """
    if not isinstance(reference_load, jax.core.Tracer):
        prepare(scene, reference_load)  # the same checks as a load: positive and finite
    scene, loads = prepare(scene, loads)
    reference_load = jnp.asarray(reference_load, loads.dtype)
    if rtol is None:
        rtol = 1e-10 if loads.dtype == jnp.float64 else 1e-5
    return _approach(scene, loads, reference_load, rtol, max_steps)
