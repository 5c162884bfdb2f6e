"""The interaction part of the joint stiffness: `∫ k₀ n (1/(1 ± r) - 1) da` over each regime.

With `ω = ξ ± σ` the asperity stiffness is `k₀/(1 ± r)`, `k₀ = f'/ξ'` and `r = σ'/ξ'` a power law
in each regime (docs/model.md §3). The closed form `∫ k₀ n da` is the stiffness without interaction;
these are the corrections to it, the only integrals of the model done by quadrature (in log-area),
so that the quadrature error only touches the (usually small) interaction part.

- "series" (`-r/(1+r)`, bounded, no real pole): any row quadrature in `t = ln a`.
- "paper" (`r/(1-r)`, a pole where r = 1, i.e. at breakdown): near breakdown the pole sits at the
  end of the interval and no quadrature in `t` converges. So `r/(1-r) = Σ_{j=1..k} r^j +
  r^(k+1)/(1-r)`: the powers of r are power laws (closed forms), and with `u = r(a)` the remainder
  is `C ∫ u^p/(1-u) du`, `p = δ/e + k ≥ 2` in every regime for k = 4: the quadrature's
  `pole_integrals` (`PowerSeries` sums its antiderivative to round-off; a row quadrature
  integrates it in `w = -ln(1-u)`).
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, Float

from ._powerlaw import PowerLaw, exponential_integral
from ._quadrature import AbstractQuadrature, AbstractRowQuadrature

GEOMETRIC_TERMS = 4  # powers of r taken in closed form before the remainder


def series_correction(
    density: PowerLaw, ratio: PowerLaw, lower, upper, quadrature: AbstractRowQuadrature
) -> Float[Array, "rows"]:
    """`∫ k₀ n (-r/(1+r)) da` over each row (interaction "series"); `density` is `k₀ n a` in `t = ln a`."""

    def integrand(t, d_log, d_rate, r_log, r_rate):
        r = jnp.exp(r_log + r_rate * t)
        return jnp.exp(d_log + d_rate * t) * (-r / (1.0 + r))

    # An empty row (a regime no spot reaches) is exactly 0. Its coefficients can be far out of
    # range (a_c ∝ φ^(2/(1-D)) as D → 1), and inf · 0 is NaN: they are replaced by harmless ones.
    nonempty = upper > lower
    safe = (
        jnp.where(nonempty, density.log_coeff, 0.0),
        density.exponent,
        jnp.where(nonempty, ratio.log_coeff, 0.0),
        ratio.exponent,
    )
    value = quadrature.integrate_rows(integrand, safe, lower, upper)
    return jnp.where(nonempty, value, 0.0)


def paper_correction(
    density: PowerLaw, ratio: PowerLaw, lower, upper, quadrature: AbstractQuadrature
) -> list[Float[Array, ""]]:
    """`∫ k₀ n r/(1-r) da` over each regime with stiffness (interaction "paper").

    `density` and `ratio` are `k₀ n a` and `r` as laws in `t = ln a`, one row per regime. With
    `u = r(a)`, `r/(1-r) = Σ_{j=1..k} u^j + u^(k+1)/(1-u)`: the powers are closed forms, and the
    remainder is `C ∫ u^p/(1-u) du` with `C = e^(d - δr/q) / q` and `p = δ/q + k` (`d, δ`: the
    density's log-coefficient and rate; `r, q`: the ratio's), the quadrature's `pole_integrals`.

    **Returns:** one correction per regime, as a list: the regimes' closed forms computed as one
    array or each as its own chain of scalar operations, as `quadrature.regimes_together` says
    (`PowerSeries`: the same numbers, a shorter compile or a faster run on many loads).
    """
    d, r = density, ratio
    remainders = quadrature.pole_integrals(
        d.exponent / r.exponent + GEOMETRIC_TERMS,
        d.log_coeff - d.exponent * r.log_coeff / r.exponent,
        r.log_coeff + r.exponent * lower,
        r.log_coeff + r.exponent * upper,
    )
    # The closed-form powers Σ_j ∫ k₀ n u^j da of each regime, summed over j in the same order either way.
    if quadrature.regimes_together:
        j = jnp.arange(1, GEOMETRIC_TERMS + 1, dtype=lower.dtype)[:, None]
        terms = exponential_integral(d.log_coeff + j * r.log_coeff, d.exponent + j * r.exponent, lower, upper)
        powers = sum((terms[k] for k in range(1, GEOMETRIC_TERMS)), terms[0])
    else:
        powers = [
            sum(
                exponential_integral(
                    d.log_coeff[i] + j * r.log_coeff[i], d.exponent[i] + j * r.exponent[i], lower[i], upper[i]
                )
                for j in range(1, GEOMETRIC_TERMS + 1)
            )
            for i in range(len(remainders))
        ]
    corrections = []
    for i, remainder in enumerate(remainders):
        lo, hi = lower[i], upper[i]
        # The integrand is positive: a difference below 0 is round-off between two nearly equal
        # ends, and an empty interval is exactly 0 (its ends may even lie past the pole, where
        # a_min itself is beyond breakdown). Dividing by q last (not `- ln q` in the exponent)
        # ends the sum in a division, which XLA computes once and shares instead of copying the
        # polynomial work into every output that uses the stiffness (1.3x for a whole Solution).
        corrections.append(powers[i] + jnp.where(hi > lo, jnp.maximum(remainder, 0.0), 0.0) / r.exponent[i])
    return corrections
