"""What `solve` returns: an option of the call, as diffrax takes `saveat=` on `diffeqsolve`, never a
field of the `Scene` (the joint and its model, which holds its own root finder)."""

from __future__ import annotations

import equinox as eqx

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
