"""The outputs of `solve`."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, Int

from ..numerics._compat import namespace
from ..quantities import Scales, Status, StatusError


class Solution(eqx.Module):
    """Result of `jaxcontact.solve`, one entry per load (leading axes = the loads' shape).

    **Fields:**

    - `load`: normal load F, N.
    - `a_l`: area of the largest contact spot, m² (NaN where the load is out of range).
    - `stiffness`: normal contact stiffness K_t, N/m (NaN unless `status == 0`).
    - `real_area`: real contact area A_r, m².
    - `status`: int32 per point, see `jaxcontact.Status` (0 = ok).
    - `load_share`, `stiffness_share`: fraction of F and of K carried by each of the model's
      regimes, last axis ordered as `regimes` ((e, ep1, ep2, p) for "xia2024", (e, p) for
      "jzz2010"). None when the scene does not ask for them (`solve(..., outputs=Outputs(regime_shares=False))`).
    - `modulus`, `nominal_area`: the scene's E (Pa) and A_a (m²) that make the results
      dimensionless, shaped to broadcast against the loads (a trailing axis of 1 per load axis).
    - `regimes`: the names of the model's regimes (static).

    **Properties:** `load_star`, `stiffness_star`, `real_area_star`, `a_l_star`, the paper's
    dimensionless F* = F/(E A_a), K* = K/(E sqrt(A_a)), A_r* = A_r/A_a, a_l* = a_l/A_a (NaN where
    their dimensional twins are), `scales`, `ok` and `fully_plastic`. They are computed when asked for, not
    stored, so that a call does not pay for outputs it does not use; inside a jitted function
    they fuse with whatever uses them.
    """

    load: Float[Array, "*loads"]
    a_l: Float[Array, "*loads"]
    stiffness: Float[Array, "*loads"]
    real_area: Float[Array, "*loads"]
    status: Int[Array, "*loads"]
    load_share: Float[Array, "*loads regimes"] | None
    stiffness_share: Float[Array, "*loads regimes"] | None
    modulus: Float[Array, "*scales"]
    nominal_area: Float[Array, "*scales"]
    regimes: tuple[str, ...] = eqx.field(static=True, default=())

    @property
    def scales(self) -> Scales:
        """The units of the starred quantities (`Scales`), shaped to broadcast against the loads."""
        return Scales(self.modulus, self.nominal_area)

    @property
    def ok(self):
        """Boolean mask of the valid points."""
        return self.status == Status.OK

    @property
    def fully_plastic(self):
        """Valid points with K = 0 because every contact spot is fully plastic (plastic spots carry
        load but add no stiffness, Sec. 4.2): the number is right, and this says why it is zero."""
        return self.ok & (self.stiffness == 0)

    @property
    def solved(self):
        """Boolean mask of the points whose `a_l` was found (valid, or past interaction breakdown)."""
        return is_solved(self.status)

    @property
    def load_star(self):
        return self.load / self.scales.load

    @property
    def stiffness_star(self):
        return masked_rescale(self.ok, self.stiffness, 1.0 / self.scales.stiffness)

    @property
    def real_area_star(self):
        return masked_rescale(self.solved, self.real_area, 1.0 / self.nominal_area)

    @property
    def a_l_star(self):
        return masked_rescale(self.solved, self.a_l, 1.0 / self.nominal_area)


def is_solved(status):
    """Whether `a_l` was found: the point is valid, or past interaction breakdown."""
    return (status == Status.OK) | (status == Status.INTERACTION_BREAKDOWN)


def masked_rescale(mask, value, scale=1.0):
    """`value · scale` where `mask`, NaN elsewhere; at masked points every derivative is 0, not NaN.

    The inner `where` matters for gradients: a masked point's value may be NaN, and NaN times
    the zero cotangent it receives would still be NaN.
    """
    xp = namespace(mask, value, scale)
    return xp.where(mask, xp.where(mask, value, 0.0) * scale, xp.nan)


# How many bad points an eager `solve(..., throw=True)` names.
_NAMED = 5


def thrown(solution: Solution) -> Solution:
    """`solution`, or an error where a point's status is not OK: a `StatusError` naming the points
    and their statuses for concrete results; under a trace, a runtime error with the first bad
    point's status message (`equinox.branched_error_if`)."""
    status = solution.status
    if isinstance(status, jax.core.Tracer) or isinstance(solution.load, jax.core.Tracer):
        flat = jnp.ravel(status)
        messages = [f"solve: a point has status {code.name}: {code.message}" for code in Status]
        return eqx.branched_error_if(
            solution, jnp.any(flat != Status.OK), flat[jnp.argmax(flat != Status.OK)], messages
        )
    codes = np.asarray(status)
    bad = np.argwhere(codes != Status.OK)
    if bad.size == 0:
        return solution
    loads = np.asarray(solution.load)
    named = [
        f"loads[{', '.join(map(str, index))}] = {loads[tuple(index)]:.6g} N: {Status(int(codes[tuple(index)])).name}"
        for index in bad[:_NAMED]
    ]
    more = f" and {len(bad) - _NAMED} more" if len(bad) > _NAMED else ""
    meanings = "; ".join(f"{code.name}: {code.message}" for code in sorted({Status(int(c)) for c in codes[codes != 0]}))
    raise StatusError(f"{len(bad)} of {codes.size} points have no valid result ({'; '.join(named)}{more}). {meanings}")
