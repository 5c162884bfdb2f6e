"""Power laws `c * a**q` and their exact integrals.

Every single-asperity law of the model (load, interference, settlement, stiffness without
interaction) and the size distribution are power laws in the contact area `a`, so every integral
without interaction has a closed form. They are kept in log form, `log c` and `q`, because the
coefficients span hundreds of decades (a_c ∝ φ^(2/(1-D)) with D → 1) and would overflow float32.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float


def log_sinhc(z: Float[ArrayLike, "*shape"]) -> Float[Array, "*shape"]:
    """`log(sinh(z) / z)`, even in z, accurate and smooth (gradient included) through z = 0."""
    z = jnp.asarray(z)
    small = jnp.abs(z) < 1e-2
    # Two-sided `where` so that the unused branch never produces NaN gradients at z = 0.
    z_big = jnp.where(small, 1.0, jnp.abs(z))
    big = z_big + jnp.log(-jnp.expm1(-2.0 * z_big)) - jnp.log(2.0 * z_big)
    z2 = z * z
    series = z2 / 6.0 - z2 * z2 / 180.0
    return jnp.where(small, series, big)


def exponential_integral(log_coeff, rate, lower, upper):
    """`∫_lower^upper exp(log_coeff + rate * t) dt`, exactly.

    With `t = ln a` this is `∫ c a^q da` over `[e^lower, e^upper]` for `rate = q + 1`. Written
    about the interval's midpoint, `(e^(rate·v) - e^(rate·u))/rate = e^(rate·(u+v)/2) · L ·
    sinh(rate·L/2)/(rate·L/2)`, it needs no division by `rate`: values and gradients stay exact
    at and near `rate = 0` (the elastic load at D = 1.5, where the integral becomes `c·ln(hi/lo)`).
    An empty interval (`upper == lower`) gives exactly 0, whatever the size of the coefficient.
    """
    length = upper - lower
    exponent = log_coeff + rate * 0.5 * (upper + lower) + log_sinhc(0.5 * rate * length)
    nonempty = length > 0
    exponent = jnp.where(nonempty, exponent, 0.0)
    return jnp.where(nonempty, jnp.exp(exponent) * length, 0.0)


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
