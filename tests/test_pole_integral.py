"""The pole term `J_p(u) = ∫_0^u s^p/(1-s) ds` against mpmath's Lerch transcendent, with its derivatives."""

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest

from jaxcontact.numerics import x64
from jaxcontact.numerics._pole_integral import PoleIntegral

# p = δ/q + 4 spans [2, 6] over D in (1, 2): 2 in the elastic regime, 4.2–5.9 in the others.
POWERS = (2.0, 2.37, 4.4, 5.9)
U = (1e-200, 1e-8, 0.3, 0.49999, 0.5, 0.50001, 0.7, 0.9, 0.999, 1 - 1e-6, 1 - 1e-12)


def exact(p, u):
    """The Lerch series where it converges fast, else quadrature in w = -ln(1-s), where the integrand is smooth."""
    with mp.workdps(40):
        u = mp.mpf(u)
        if u <= 0.5:
            return u ** (p + 1) * mp.nsum(lambda n: u**n / (n + p + 1), [0, mp.inf])
        w = -mp.log1p(-u)
        return mp.quad(lambda t: (-mp.expm1(-t)) ** p, mp.linspace(0, w, 8))


@pytest.mark.parametrize("p", POWERS)
def test_matches_the_lerch_series_on_both_sides_of_the_switch(p):
    pole = PoleIntegral.build(jnp.asarray(p))
    for u in U:
        got = float(pole(jnp.asarray(float(mp.log(u))), jnp.asarray(0.0)))
        # 1.3e-13 just above u = 1/2 for p = 5.9, where -ln(1-u) - H_p cancels to J_p ≈ 1e-3.
        np.testing.assert_allclose(got, float(exact(p, u)), rtol=2e-13, err_msg=f"p={p} u={u}")


def test_the_coefficient_is_carried_in_the_exponent():
    """A coefficient of e^600 with u^(p+1) ≈ e^-700: neither overflows on its own."""
    p, log_u = 4.4, -700.0 / 5.4
    got = PoleIntegral.build(jnp.asarray(p))(jnp.asarray(log_u), jnp.asarray(600.0))
    with mp.workdps(40):
        expected = mp.e**600 * exact(p, mp.e ** mp.mpf(log_u))
    np.testing.assert_allclose(float(got), float(expected), rtol=1e-13)


@pytest.mark.parametrize("p", POWERS)
def test_derivatives_in_u_and_p(p):
    pole = PoleIntegral.build(jnp.asarray(p))
    for u in (1e-3, 0.4, 0.6, 0.99, 1 - 1e-9):
        log_u = float(np.log(u))
        # d/d ln u of J_p(u) is u · u^p/(1-u), in closed form.
        slope = jax.grad(lambda lu: pole(lu, 0.0))(jnp.asarray(log_u))
        np.testing.assert_allclose(float(slope), u ** (p + 1) / (1 - u), rtol=1e-12, err_msg=f"u={u}")
        # d/dp through the coefficients (binomials, digamma), against mpmath's derivative.
        by_p = jax.grad(lambda q: PoleIntegral.build(q)(jnp.asarray(log_u), 0.0))(jnp.asarray(p))
        with mp.workdps(40):  # ∂J_p/∂p = ∫ s^p ln(s) dw over w = -ln(1-s) ∈ [0, -ln(1-u)]
            w = -mp.log1p(-mp.mpf(u))
            expected = mp.quad(lambda t: (-mp.expm1(-t)) ** p * mp.log(-mp.expm1(-t)), mp.linspace(0, w, 8))
        np.testing.assert_allclose(float(by_p), float(expected), rtol=1e-10, err_msg=f"u={u}")


def test_float32():
    with x64(False):
        pole = PoleIntegral.build(jnp.asarray(4.4, jnp.float32))
        log_u = jnp.log(jnp.asarray([1e-6, 0.3, 0.7, 0.999], jnp.float32))
        got = np.asarray(pole(log_u, jnp.zeros(4, jnp.float32)))
    assert got.dtype == np.float32
    np.testing.assert_allclose(got, [float(exact(4.4, float(u))) for u in np.exp(np.asarray(log_u, float))], rtol=2e-5)
