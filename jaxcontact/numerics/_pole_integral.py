"""`J_p(u) = ∫_0^u s^p / (1 - s) ds`: the pole term of the "paper" interaction, without quadrature.

With `ω = ξ - σ` the interaction stiffness has the factor `1/(1 - r)`, whose pole `r = 1` is the
breakdown of the model (`joint.Xia2024Joint.regime_stiffness`). After the first powers of `r` are
taken out in closed form, what is left of each regime is `C ∫ u^p/(1-u) du` over `u = r(a)`, with
`p` fixed by the regime's exponents (2 ≤ p ≤ 6 over D in (1, 2)). Its antiderivative has two
convergent expansions, and each is used where it converges fast:

- near 0: `J_p(u) = u^(p+1) Σ_n u^n / (p + 1 + n)` (the Lerch series), for `u ≤ 1/2`;
- near 1: `J_p(u) = -ln(1 - u) - H_p + Σ_k (-1)^(k+1) C(p, k) v^k / k` with `v = 1 - u` and
  `H_p = ψ(p + 1) + γ`, the harmonic number, for `u > 1/2`. It carries the pole's logarithm
  exactly, however close `u` is to 1.

Both are polynomials (no transcendental function per term; the Gauss–Legendre remainder it
replaces needed a float64 `log` per node, which XLA does not vectorise on CPU), and the result is
exact to round-off right up to breakdown.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from ._caches import cached

# u^48 / (1 - u) at u = 1/2 is 7e-15 of the first term; |C(p, k)| / k falls at least like k^(-4).
NEAR_ZERO_TERMS = 48
NEAR_ONE_TERMS = 32
# Both series are then economised (Chebyshev-truncated) to this degree in y = 4x - 1 over
# x in [0, 1/2]: within 7e-16 of the full series for p in [2, 6], in 21 terms instead of 48.
DEGREE = 20
_LOG_SWITCH = math.log(0.5)


@cached  # built on first use, not at import (~0.1 s)
def _economisation(terms: int) -> np.ndarray:
    """Matrix taking the coefficients of `Σ c_n x^n` (n < terms, x in [0, 1/2]) to those of its
    degree-`DEGREE` Chebyshev truncation, as a polynomial in `y = 4x - 1`."""
    matrix = np.zeros((terms, DEGREE + 1))
    for n in range(terms):
        chebyshev = np.polynomial.chebyshev.poly2cheb(np.polynomial.polynomial.polypow([0.25, 0.25], n))
        monomial = np.polynomial.chebyshev.cheb2poly(chebyshev[: DEGREE + 1])
        matrix[n, : len(monomial)] = monomial
    return matrix


# The coefficients are built from reductions (`sum`, `prod`), not from chains of elementwise
# operations. XLA computes a reduction once and shares its result; a chain of cheap operations
# (and a small matmul, which it rewrites into one) it copies into every fusion that reads it. In
# a gradient the per-scene coefficients are read by many per-load fusions, and such copies make
# the "paper" gradient's program much larger and slower to compile.
def _economise(series, matrix):
    """`series @ matrix`, as a reduction over the series' terms (see above)."""
    return jnp.sum(series[..., :, None] * jnp.asarray(matrix, series.dtype), axis=-2)


def _coefficients(power):
    """The two expansions' coefficients, economised, and `H_p`."""
    n = jnp.arange(NEAR_ZERO_TERMS, dtype=power.dtype)
    k = jnp.arange(1, NEAR_ONE_TERMS + 1, dtype=power.dtype)
    factors = (power[..., None] - k + 1.0) / k
    # C(p, k) = Π_{i<k} factors[i], as one reduction over a masked square.
    below = np.arange(NEAR_ONE_TERMS)[:, None] < np.arange(1, NEAR_ONE_TERMS + 1)[None, :]
    binomial = jnp.prod(jnp.where(below, factors[..., :, None], 1.0), axis=-2)
    signs = np.where(np.arange(NEAR_ONE_TERMS) % 2 == 0, 1.0, -1.0)
    near_one = jnp.concatenate([jnp.zeros_like(power)[..., None], binomial * signs / k], axis=-1)
    near_zero = _economise(1.0 / (power[..., None] + 1.0 + n), _economisation(NEAR_ZERO_TERMS))
    near_one = _economise(near_one, _economisation(NEAR_ONE_TERMS + 1))
    # H_p from the two expansions meeting at u = 1/2 (y = 1: the sums of the coefficients): no
    # digamma, and J_p is continuous across the switch to the last bit.
    harmonic = (
        math.log(2.0)
        + jnp.sum(near_one, axis=-1)
        - jnp.exp(-(power + 1.0) * math.log(2.0)) * jnp.sum(near_zero, axis=-1)
    )
    return near_zero, near_one, harmonic


class PoleIntegral(eqx.Module):
    """`e^c J_p(u)` for a fixed power `p ≥ 0` (one per regime; arrays of powers broadcast).

    **Fields:** `power`, `p`; `coefficients`, the two expansions' economised coefficients (of
    `Σ x^n/(p + 1 + n)` and `Σ (-1)^(k+1) C(p, k) x^k/k`) and `H_p`; `slopes`, their derivatives
    in `p`. Build with `PoleIntegral.build(power)`: the coefficients must be those of `power`,
    because derivatives with respect to `p` are taken through `power` and `slopes` alone.
    """

    power: Float[Array, "*rows"]
    coefficients: tuple[Float[Array, "*rows terms"], Float[Array, "*rows terms"], Float[Array, "*rows"]]
    slopes: tuple[Float[Array, "*rows terms"], Float[Array, "*rows terms"], Float[Array, "*rows"]]

    @classmethod
    def build(cls, power: Float[ArrayLike, "*rows"]) -> "PoleIntegral":
        power = jnp.asarray(power)
        coefficients, slopes = jax.jvp(_coefficients, (power,), (jnp.ones_like(power),))
        return cls(power, coefficients, slopes)

    def __getitem__(self, index) -> "PoleIntegral":
        """The integral(s) of the powers `power[index]`."""
        return jax.tree.map(lambda x: x[index], self)

    def __call__(self, log_u: Float[ArrayLike, "*rows"], log_coeff: Float[ArrayLike, "*rows"]):
        """`e^log_coeff · J_p(u)` for `0 < u < 1`, given `ln u`.

        **Arguments:**

        - `log_u`: `ln u`, with `u < 1` (strictly: `J_p` has its pole at `u = 1`).
        - `log_coeff`: `ln` of the coefficient. It is combined with `u^(p+1)` in the exponent, so
          a huge coefficient times a tiny `u^(p+1)` neither overflows nor underflows.

        **Returns:** the integral, elementwise. Both expansions are evaluated at a `u` clamped
        into their own range, so every lane (and every derivative) is finite; `u ≥ 1` (past the
        pole: the caller flags such points, or has an empty interval there) is taken as just
        below 1.
        """
        log_u, log_coeff = jnp.asarray(log_u), jnp.asarray(log_coeff)
        log_u = jnp.minimum(log_u, -float(jnp.finfo(log_u.dtype).eps))
        return _scaled_pole_integral(self.power, self.coefficients, self.slopes, log_u, log_coeff)


def _series(near_zero, near_one, small, x):
    """One Horner pass for both expansions, each lane with its own coefficients and variable."""
    y = 4.0 * x - 1.0
    series = jnp.where(small, near_zero[..., -1], near_one[..., -1])
    for n in range(DEGREE - 1, -1, -1):
        series = series * y + jnp.where(small, near_zero[..., n], near_one[..., n])
    return series


def _evaluate(power, coefficients, log_u, log_coeff):
    """The value, and what its derivative rule reuses: the lanes' split and variable, the scales."""
    near_zero, near_one, harmonic = coefficients
    small = log_u <= _LOG_SWITCH
    log_u_large = jnp.maximum(log_u, _LOG_SWITCH)
    v = -jnp.expm1(log_u_large)  # 1 - u, without losing digits as u → 1
    x = jnp.where(small, jnp.exp(jnp.minimum(log_u, _LOG_SWITCH)), v)
    # u^-(p+1) on the near-one side, where u ≥ 1/2 keeps it bounded.
    inverse_power = jnp.exp(-(power + 1.0) * log_u_large)
    series = _series(near_zero, near_one, small, x)
    near_one_scaled = (-jnp.log(v) - harmonic + series) * inverse_power
    scale = jnp.exp(log_coeff + (power + 1.0) * log_u)
    value = scale * jnp.where(small, series, near_one_scaled)
    return value, (small, log_u_large, x, inverse_power, near_one_scaled, scale)


# Its own derivative rule. d/d ln u is the integrand, in closed form; d/dp is the same series
# with the coefficients' slopes. Differentiating the unrolled Horner steps instead (and, in reverse
# mode, every coefficient separately) made gradients several times slower to compile and run.
@jax.custom_jvp
def _scaled_pole_integral(power, coefficients, slopes, log_u, log_coeff):
    del slopes
    return _evaluate(power, coefficients, log_u, log_coeff)[0]


@_scaled_pole_integral.defjvp
def _scaled_pole_integral_jvp(primals, tangents):
    power, coefficients, (near_zero_slope, near_one_slope, harmonic_slope), log_u, log_coeff = primals
    # The coefficients' own tangents are ṗ times their slopes: they are taken through `power`.
    power_dot, _, _, log_u_dot, log_coeff_dot = tangents
    value, (small, log_u_large, x, inverse_power, near_one_scaled, scale) = _evaluate(
        power, coefficients, log_u, log_coeff
    )
    # ∂/∂p at fixed ln u: through the coefficients, and through u^(p+1) and u^-(p+1).
    series_slope = _series(near_zero_slope, near_one_slope, small, x)
    scaled_slope = jnp.where(
        small, series_slope, (series_slope - harmonic_slope) * inverse_power - log_u_large * near_one_scaled
    )
    by_power = value * log_u + scale * scaled_slope
    # d/d ln u of e^c J_p(u) is e^c u^(p+1) / (1 - u).
    by_log_u = scale / (-jnp.expm1(log_u))
    return value, value * log_coeff_dot + by_power * power_dot + by_log_u * log_u_dot
