"""Power laws `c * a**q` and their exact integrals.

Every single-asperity law of the model (load, interference, settlement, stiffness without
interaction) and the size distribution are power laws in the contact area `a`, so every integral
without interaction has a closed form. They are kept in log form, `log c` and `q`, because the
coefficients span hundreds of decades (a_c ∝ φ^(2/(1-D)) with D → 1) and would overflow float32.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float


@jax.custom_jvp
def mean_decay(x: Float[ArrayLike, "*shape"]) -> Float[Array, "*shape"]:
    """`(1 - e^(-x)) / x` for `x ≥ 0`, the mean of `e^(-s)` over `s ∈ [0, x]`; 1 at `x = 0`.

    `expm1` keeps it exact for small `x`; a floor far below `eps` makes `x = 0` give exactly 1
    without a branch (a `where` between two formulas stops XLA from vectorising the
    surrounding loop, which made the closed forms several times slower). The derivative,
    which needs a series near 0, has its own rule.
    """
    x = jnp.asarray(x)
    floor = float(jnp.finfo(x.dtype).eps) ** 2
    x = jnp.maximum(x, floor)
    return -jnp.expm1(-x) / x


@mean_decay.defjvp
def _mean_decay_jvp(primals, tangents):
    (x,), (x_dot,) = primals, tangents
    value = mean_decay(x)
    # d/dx = (e^(-x)(1 + x) - 1) / x², which cancels for small x: there, its Taylor series.
    small = x < 0.1
    xs = jnp.where(small, 1.0, x)
    direct = (jnp.exp(-xs) * (1.0 + xs) - 1.0) / (xs * xs)
    series = -0.5 + x * (
        1 / 3
        + x * (-1 / 8 + x * (1 / 30 + x * (-1 / 144 + x * (1 / 840 + x * (-1 / 5760 + x * (1 / 45360 - x / 403200))))))
    )
    return value, jnp.where(small, series, direct) * x_dot


def exponential_integral(log_coeff, rate, lower, upper):
    """`∫_lower^upper exp(log_coeff + rate * t) dt`, exactly.

    With `t = ln a` this is `∫ c a^q da` over `[e^lower, e^upper]` for `rate = q + 1`. Written
    as the integrand at the interval's larger end times `L · mean_decay(|rate| L)`, it needs
    no division by `rate` (values and gradients stay exact at and near `rate = 0`, the elastic
    load at D = 1.5, where the integral becomes `c·ln(hi/lo)`), cannot overflow in the
    subtraction, and costs one `exp` and one `expm1`. An empty interval (`upper == lower`)
    gives exactly 0, whatever the size of the coefficient.
    """
    length = upper - lower
    rising = rate >= 0
    larger_end = jnp.where(rising, upper, lower)
    # Signed so that d|rate|/d rate is +1 at rate = 0, where the larger end is `upper`.
    decay = jnp.where(rising, rate, -rate) * length
    # An empty interval's value *and* derivatives must be exactly 0: with e^0 in their place the
    # ±1 derivatives of its two ends would cancel only to round-off, which is large next to
    # the tiny loads of the regimes that are not empty.
    exponent = jnp.where(length > 0, log_coeff + rate * larger_end, -jnp.inf)
    return jnp.exp(exponent) * length * mean_decay(decay)


class PowerLaw(eqx.Module):
    """`a ↦ exp(log_coeff) * a**exponent`, for `a > 0`; arrays of laws broadcast elementwise.

    Areas are passed as `log_a = ln a` throughout.
    """

    log_coeff: Float[Array, "*shape"]
    exponent: Float[Array, "*shape"]

    def __call__(self, log_a):
        return jnp.exp(self.log_coeff + self.exponent * log_a)

    def __mul__(self, other: "PowerLaw") -> "PowerLaw":
        return PowerLaw(self.log_coeff + other.log_coeff, self.exponent + other.exponent)

    def __truediv__(self, other: "PowerLaw") -> "PowerLaw":
        return PowerLaw(self.log_coeff - other.log_coeff, self.exponent - other.exponent)

    def __getitem__(self, index) -> "PowerLaw":
        return PowerLaw(self.log_coeff[index], self.exponent[index])

    def scaled(self, log_factor) -> "PowerLaw":
        """The law times `exp(log_factor)`."""
        return PowerLaw(self.log_coeff + log_factor, self.exponent)

    def sqrt(self) -> "PowerLaw":
        return PowerLaw(0.5 * self.log_coeff, 0.5 * self.exponent)

    def derivative(self) -> "PowerLaw":
        """d/da, for a positive exponent (every law of the model has one)."""
        return PowerLaw(self.log_coeff + jnp.log(self.exponent), self.exponent - 1.0)

    def integral(self, log_lower, log_upper):
        """`∫ c a^q da` from `e^log_lower` to `e^log_upper` (closed form, see `exponential_integral`)."""
        return exponential_integral(self.log_coeff, self.exponent + 1.0, log_lower, log_upper)

    def expanded(self) -> "PowerLaw":
        """The same laws with a trailing axis, to evaluate each on its own row of points."""
        return PowerLaw(self.log_coeff[..., None], self.exponent[..., None])
