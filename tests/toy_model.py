"""A toy contact model, to show that a new model is one file plus one registry line.

Every contact spot is elastic: it carries the load of Eq. (5) and has the Hertz stiffness
`k = 2 E sqrt(a/π)`, over the Majumdar–Bhushan distribution cut at `a_min` (no plastic regime,
no interaction). Every total is a closed form. `tests/test_contract.py` registers it with
`jaxcontact.register_model(AllElastic)` and puts it through the contract every model passes.
"""

from __future__ import annotations

from typing import ClassVar

import jax.numpy as jnp
from jaxtyping import Array, Float

from jaxcontact import (
    AbstractJoint,
    AbstractLargestSpotModel,
    GenericLoadPieces,
    JointResponse,
    NewtonBisection,
    PowerLaw,
    SpotFamilies,
    hertz_stiffness,
    kogut_etsion_laws,
    size_distribution,
)


class AllElastic(AbstractLargestSpotModel):
    """Every spot elastic (Eq. 5 load, Hertz stiffness); one regime, "e"."""

    name: ClassVar[str] = "toy-all-elastic"
    regimes: ClassVar[tuple[str, ...]] = ("e",)
    root_finder: NewtonBisection = NewtonBisection()

    def joint(self, s):
        laws, _ = kogut_etsion_laws(s.D, s.log_G, s.log_hardness, s.nu)
        return AllElasticJoint(D=s.D, log_a_min=s.log_a_min, load_law=laws[0])


class AllElasticJoint(AbstractJoint):
    D: Float[Array, ""]
    log_a_min: Float[Array, ""]
    load_law: PowerLaw

    def kinks(self):
        return jnp.zeros((0,), self.log_a_min.dtype)

    def load_pieces(self):
        return GenericLoadPieces.of(self)

    def regime_load(self, log_a_l):
        n = size_distribution(self.D, log_a_l, 0.0)
        return (self.load_law * n).integral(self.log_a_min, log_a_l)[None]

    def response(self, log_a_l, log_load):
        n = size_distribution(self.D, log_a_l, 0.0)
        stiffness = (hertz_stiffness(self.D) * n).integral(self.log_a_min, log_a_l)[None]
        area = (PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D)) * n).integral(self.log_a_min, log_a_l)
        return JointResponse(self.regime_load(log_a_l), stiffness, area, jnp.array(False))

    def unloading_stiffness(self, log_a_l, log_load):
        return self.response(log_a_l, log_load).regime_stiffness, jnp.array(False)  # elastic spots

    def spots(self, log_a_l, log_load):
        count = size_distribution(self.D, log_a_l, 0.0) * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        one = lambda law: PowerLaw(law.log_coeff[None], law.exponent[None])  # noqa: E731
        return SpotFamilies.without_interaction(
            one(count), one(self.load_law), one(hertz_stiffness(self.D)), self.log_a_min[None], log_a_l[None]
        )
