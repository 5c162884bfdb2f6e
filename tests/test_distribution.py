"""The Wang–Komvopoulos factor ψ(D) against a 30-digit mpmath root and its closed-form ends."""

import math

import jax
import jax.numpy as jnp
import mpmath
import numpy as np
import pytest

from jaxcontact.physics import wang_komvopoulos_psi

mpmath.mp.dps = 30


def psi_reference(D):
    D = mpmath.mpf(D)
    x = (2 - D) / D
    return mpmath.findroot(lambda p: (p ** ((2 - D) / 2) - (1 + p ** (-D / 2)) ** (-x)) / x - 1, 2)


# Dense in the middle, geometric towards both ends (D → 1 and D → 2 are where ψ's equation is
# hardest: a quadratic in √ψ, and a 0/0).
D_GRID = np.concatenate([1 + np.geomspace(1e-9, 1e-2, 8), np.linspace(1.01, 1.99, 99), 2 - np.geomspace(1e-2, 1e-9, 8)])


@pytest.fixture(scope="module")
def psi_grid():
    return np.asarray(jax.jit(jax.vmap(wang_komvopoulos_psi))(jnp.asarray(D_GRID)))


def test_psi_matches_mpmath_on_the_whole_range(psi_grid):
    reference = np.array([float(psi_reference(D)) for D in D_GRID])
    np.testing.assert_allclose(psi_grid, reference, rtol=5e-15, atol=0)


def test_psi_tends_to_the_closed_forms_at_the_ends(psi_grid):
    golden_squared = ((1 + math.sqrt(5)) / 2) ** 2
    # ψ is smooth in D with |dψ/dD| < 2, so 1e-9 from an end it is within 2e-9 of the end's root.
    assert abs(psi_grid[0] - golden_squared) < 2e-9
    assert abs(psi_grid[-1] - (math.e - 1)) < 2e-9


def test_psi_gradient_is_the_implicit_derivative():
    for D in (1.05, 1.4058, 1.5, 1.93, 1.9999):
        exact = float(mpmath.diff(psi_reference, D))
        got = float(jax.grad(wang_komvopoulos_psi)(jnp.asarray(D)))
        assert got == pytest.approx(exact, rel=1e-11), D


def test_psi_in_float32():
    D = jnp.asarray([1.05, 1.4058, 1.93, 1.9999], jnp.float32)
    got = jax.vmap(wang_komvopoulos_psi)(D)
    assert got.dtype == jnp.float32
    reference = [float(psi_reference(float(d))) for d in D]
    np.testing.assert_allclose(np.asarray(got), reference, rtol=2e-6)
