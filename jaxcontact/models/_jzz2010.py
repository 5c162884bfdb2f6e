"""The classical comparator: Jiang, Zheng & Zhu (J. Tribology 132, 011401, 2010), docs/model.md §5.

Majumdar–Bhushan ordering: spots larger than `a_c` are elastic (Eq. 5, Hertz stiffness
`k = 2E sqrt(a/π)`), smaller ones fully plastic (`H a`, no stiffness). No lower cutoff: the
plastic integrand `a^(-D/2)` is integrable at 0. Every total is a closed form.
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ..numerics import NewtonBisection, PowerLaw, check_instance
from ..physics import AbstractDistribution, MajumdarBhushan, hertz_stiffness, kogut_etsion_laws, size_distribution
from ..quantities import DimensionlessScene
from ._base import JointResponse
from ._largest_spot import AbstractJoint, AbstractLargestSpotModel
from ._load_pieces import GenericLoadPieces
from ._spots import SpotFamilies


class JZZ2010(AbstractLargestSpotModel):
    """Jiang, Zheng & Zhu (2010), the comparator of the paper's Figs. 7–8 (docs/model.md §5): spots
    larger than `a_c` elastic with Hertz stiffness, smaller ones fully plastic. Regimes (e, p).

    **Arguments:** `distribution`, `MajumdarBhushan()` (the default) or `WangKomvopoulos()`;
    `root_finder`, the a_l solve of each load (`NewtonBisection()`).
    """

    name: ClassVar[str] = "jzz2010"
    regimes: ClassVar[tuple[str, ...]] = ("e", "p")
    distribution: AbstractDistribution = MajumdarBhushan()
    # Keyword-only: the base class declares it first, and the choices keep their positions.
    root_finder: NewtonBisection = eqx.field(default=NewtonBisection(), kw_only=True)

    def __check_init__(self):
        check_instance("distribution", self.distribution, AbstractDistribution)
        check_instance("root_finder", self.root_finder, NewtonBisection)

    def joint(self, s: DimensionlessScene) -> JZZ2010Joint:
        laws, log_a_c = kogut_etsion_laws(s.D, s.log_G, s.log_hardness, s.nu)
        return JZZ2010Joint(
            D=s.D,
            log_a_min=s.log_a_min,
            log_a_c=log_a_c,
            log_hardness=s.log_hardness,
            log_density=self.distribution.log_scale(s.D),
            elastic_law=PowerLaw(laws.log_coeff[0], laws.exponent[0]),
        )


class JZZ2010Joint(AbstractJoint):
    """The JZZ joint as a function of `ln a_l*`; regime slots (elastic, plastic)."""

    D: Float[Array, ""]
    log_a_min: Float[Array, ""]
    log_a_c: Float[Array, ""]
    log_hardness: Float[Array, ""]
    log_density: Float[Array, ""]
    elastic_law: PowerLaw

    def _log_plastic_prefactor(self, log_a_l):
        # ∫_0^x H a n(a) da = H ψ D/(2-D) a_l^(D/2) x^((2-D)/2)
        return self.log_density + jnp.log(self.D / (2.0 - self.D)) + self.D / 2.0 * log_a_l

    def _elastic_range(self, log_a_l):
        return self.log_a_c, jnp.maximum(log_a_l, self.log_a_c)

    def kinks(self):
        return self.log_a_c[None]

    def load_pieces(self):
        return GenericLoadPieces.of(self)

    def regime_load(self, log_a_l):
        n = size_distribution(self.D, log_a_l, self.log_density)
        elastic = (self.elastic_law * n).integral(*self._elastic_range(log_a_l))
        plastic = jnp.exp(
            self.log_hardness
            + self._log_plastic_prefactor(log_a_l)
            + (2.0 - self.D) / 2.0 * jnp.minimum(self.log_a_c, log_a_l)
        )
        return jnp.stack([elastic, plastic])

    def response(self, log_a_l, log_load):
        del log_load  # no interaction in this model
        n = size_distribution(self.D, log_a_l, self.log_density)
        elastic = (hertz_stiffness(self.D) * n).integral(*self._elastic_range(log_a_l))
        stiffness = jnp.stack([elastic, jnp.zeros_like(elastic)])
        real_area = jnp.exp(self._log_plastic_prefactor(log_a_l) + (2.0 - self.D) / 2.0 * log_a_l)
        return JointResponse(self.regime_load(log_a_l), stiffness, real_area, jnp.array(False))

    def unloading_stiffness(self, log_a_l, log_load):
        """Elastic spots unload along Hertz's stiffness, as they load; the plastic ones (below `a_c`)
        with Sneddon's `2E√(a/π)` of their contact area (docs/model.md §12): the same law over every spot."""
        del log_load
        n = size_distribution(self.D, log_a_l, self.log_density)
        law = hertz_stiffness(self.D) * n
        elastic = law.integral(*self._elastic_range(log_a_l))
        plastic = law.integral(self.log_a_min, jnp.minimum(self.log_a_c, log_a_l))
        return jnp.stack([elastic, plastic]), jnp.array(False)

    def spots(self, log_a_l, log_load) -> SpotFamilies:
        """The elastic spots (Eq. 5 load) above `a_c` and the plastic ones (`H a`) from `a_min` to
        `a_c`, every one with Sneddon's unloading stiffness, as `unloading_stiffness` sums them."""
        del log_load
        n = size_distribution(self.D, log_a_l, self.log_density)
        count = n * PowerLaw(jnp.zeros_like(self.D), jnp.ones_like(self.D))
        elastic_lower, elastic_upper = self._elastic_range(log_a_l)
        lower = jnp.stack([elastic_lower, self.log_a_min])
        upper = jnp.stack([elastic_upper, jnp.maximum(jnp.minimum(self.log_a_c, log_a_l), self.log_a_min)])
        rows = lambda a, b: PowerLaw(jnp.stack([a.log_coeff, b.log_coeff]), jnp.stack([a.exponent, b.exponent]))  # noqa: E731
        plastic = PowerLaw(self.log_hardness, jnp.ones_like(self.D))
        return SpotFamilies.without_interaction(
            rows(count, count), rows(self.elastic_law, plastic), rows(*(hertz_stiffness(self.D),) * 2), lower, upper
        )
