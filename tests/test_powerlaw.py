"""The closed-form power-law integral, including its log limit at zero rate."""

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest

from jaxcontact.numerics._powerlaw import PowerLaw, exponential_integral, mean_decay


def exact(log_c, rate, u, v):
    mpmath.mp.dps = 40
    log_c, rate, u, v = map(mpmath.mpf, (log_c, rate, u, v))
    if rate == 0:
        return float(mpmath.e**log_c * (v - u))
    return float(mpmath.e**log_c * (mpmath.e ** (rate * v) - mpmath.e ** (rate * u)) / rate)


@pytest.mark.parametrize("rate", [-2.3, -0.7, -1e-3, -1e-9, 0.0, 1e-12, 1e-6, 5e-3, 0.4, 1.9])
def test_matches_high_precision(rate):
    for log_c, u, v in [(0.0, -32.0, -10.0), (3.0, -20.0, -19.5), (-5.0, -1.0, 0.0)]:
        got = float(exponential_integral(log_c, rate, u, v))
        np.testing.assert_allclose(got, exact(log_c, rate, u, v), rtol=2e-14)


def test_gradient_through_zero_rate_is_finite_and_exact():
    u, v = -25.0, -3.0
    grad = jax.grad(exponential_integral, argnums=(1, 2, 3))
    g0 = grad(0.0, 0.0, u, v)
    # d/dr ∫ e^{rt} dt at r = 0 is ∫ t dt; d/du = -e^{ru} = -1; d/dv = 1.
    np.testing.assert_allclose(g0, ((v * v - u * u) / 2, -1.0, 1.0), rtol=1e-13)
    for r in (1e-9, -1e-9, 1e-3):
        g = grad(0.0, r, u, v)[0]
        h = 1e-6
        fd = (exponential_integral(0.0, r + h, u, v) - exponential_integral(0.0, r - h, u, v)) / (2 * h)
        np.testing.assert_allclose(g, fd, rtol=1e-7)


def test_empty_interval_is_zero_even_with_huge_coefficient():
    assert float(exponential_integral(900.0, 1.3, -4.0, -4.0)) == 0.0
    g = jax.grad(exponential_integral, argnums=(0, 3))(900.0, 1.3, -4.0, -4.0)
    assert all(np.isfinite(g))


def test_mean_decay_and_its_derivative_match_high_precision():
    # Both sides of the derivative's switch to its series (x = 0.1), and the floor at x = 0.
    x = np.array([0.0, 1e-12, 1e-5, 0.0999, 0.1, 0.1001, 0.7, 30.0])
    mpmath.mp.dps = 40

    def value(v):
        return mpmath.mpf(1) if v == 0 else -mpmath.expm1(-v) / v

    want = [float(value(mpmath.mpf(v))) for v in x]
    want_slope = [float(mpmath.diff(value, mpmath.mpf(v))) if v > 0 else -0.5 for v in x]
    np.testing.assert_allclose(mean_decay(jnp.asarray(x)), want, rtol=1e-15)
    np.testing.assert_allclose(jax.vmap(jax.grad(mean_decay))(jnp.asarray(x)), want_slope, rtol=1e-12)


def test_power_law_algebra():
    f = PowerLaw(jnp.log(3.0), jnp.asarray(1.5))
    t = jnp.log(2.0)
    np.testing.assert_allclose(f(t), 3 * 2**1.5, rtol=1e-14)
    np.testing.assert_allclose(f.derivative()(t), 4.5 * 2**0.5, rtol=1e-14)
    np.testing.assert_allclose(f.sqrt()(t), (3 * 2**1.5) ** 0.5, rtol=1e-14)
    np.testing.assert_allclose(f.integral(jnp.log(1.0), jnp.log(2.0)), 3 * (2**2.5 - 1) / 2.5, rtol=1e-14)
