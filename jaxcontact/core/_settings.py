"""What `solve` returns: an option of the call, as diffrax takes `saveat=` on `diffeqsolve`, never a
field of the `Scene` (the joint and its model, which holds its own root finder)."""

from __future__ import annotations

import equinox as eqx

from ..numerics import InputError
from ..numerics._validate import check_strategy
from ..physics import AbstractStiffness, Loading, TangentialStick, Unloading

# The stiffnesses by name, as the command line gives them.
STIFFNESSES = {kind.name: kind for kind in (Loading, Unloading, TangentialStick)}


class Outputs(eqx.Module):
    """What `solve` returns beside the largest spot and the real area.

    **Arguments:**

    - `regime_shares`: whether to split load and stiffness by the model's regimes
      (`Solution.load_share`, `stiffness_share`); with False those fields are None and nothing is
      spent on them.
    - `stiffness`: which stiffness `Solution.stiffness` is (docs/in-service.md): `Loading()` (the
      default, the loading tangent dF/dδ of the paper), `Unloading()` (the initial unloading
      tangent from the state the load reaches on loading: what a small vibration about a preload
      feels) or `TangentialStick()` (Mindlin's tangential stiffness in full stick at that state).

    Static: changing either compiles a different program.
    """

    regime_shares: bool = eqx.field(static=True, default=True)
    stiffness: AbstractStiffness = Loading()

    def __check_init__(self):
        if not isinstance(self.regime_shares, bool):
            raise InputError(f"regime_shares = {self.regime_shares!r} must be true or false")
        check_strategy("stiffness", self.stiffness, AbstractStiffness, STIFFNESSES, "jaxcontact")
