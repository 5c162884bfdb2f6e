"""The outputs of `solve`."""

from __future__ import annotations

import equinox as eqx
from jaxtyping import Array, Float, Int

from .asperity import REGIMES


class Solution(eqx.Module):
    """Result of `jaxcontact.solve`, one entry per load (leading axes = the loads' shape).

    **Fields:**

    - `load`: normal load F, N.
    - `a_l`: area of the largest contact spot, m² (NaN where the load is out of range).
    - `stiffness`: normal contact stiffness K_t, N/m (NaN unless `status == 0`).
    - `real_area`: real contact area A_r, m².
    - `status`: int32 per point, see `jaxcontact.Status` (0 = ok).
    - `load_share`, `stiffness_share`: fraction of F and of K carried by each regime, last axis
      ordered as `REGIMES` = (e, ep1, ep2, p). For "jzz2010" the slots are (elastic, 0, 0, plastic).
      None when the scene does not ask for them (`Scene.regime_shares=False`).
    - `load_star`, `stiffness_star`, `real_area_star`, `a_l_star`: the paper's dimensionless
      F* = F/(E A_a), K* = K/(E sqrt(A_a)), A_r* = A_r/A_a, a_l* = a_l/A_a.
    """

    load: Float[Array, "*loads"]
    a_l: Float[Array, "*loads"]
    stiffness: Float[Array, "*loads"]
    real_area: Float[Array, "*loads"]
    status: Int[Array, "*loads"]
    load_share: Float[Array, "*loads 4"] | None
    stiffness_share: Float[Array, "*loads 4"] | None
    load_star: Float[Array, "*loads"]
    stiffness_star: Float[Array, "*loads"]
    real_area_star: Float[Array, "*loads"]
    a_l_star: Float[Array, "*loads"]

    regimes = REGIMES

    @property
    def ok(self):
        """Boolean mask of the valid points."""
        return self.status == 0
