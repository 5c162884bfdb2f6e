"""The JAX boundary-element solve never returns a wrong number with status OK: traced bad arguments
(under `jit` and `vmap`) are flagged per map, a loose tolerance is refused, and a load past full
contact or beyond the cap leaves the other loads' gradients finite."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import refused_type
from hypothesis import given, settings
from hypothesis import strategies as st

import jaxcontact as jc
from jaxcontact import bem

pytest.importorskip("SurfaceTopography")

N, L, E, H = 16, 1e-4, 2e11, 3e9
UNIT = E * L * L
LOADS = jnp.array([1e-3, 3e-3]) * UNIT  # 10-30 % contact
INVALID = jc.Status.INVALID_PARAMETERS


HEIGHTS = np.random.default_rng(0).normal(size=(N, N)) * 1e-7


@functools.cache
def _batch():
    """A vmapped, jitted capped solve over (heights' scale, size, modulus, hardness) per map, with the
    gradient of each map's masked Σ offset: the program every case below runs."""

    def one(scale, size, modulus, hardness):
        def masked(scale):
            sol = bem.solve(scale * HEIGHTS, size, modulus, LOADS, hardness=hardness)
            return jnp.sum(jnp.where(sol.status == 0, sol.offset, 0.0)), sol

        (_, sol), gradient = jax.value_and_grad(masked, has_aux=True)(scale)
        return sol, gradient

    return jax.jit(jax.vmap(one))


def _solve(scale, size, modulus, hardness):
    """Map 0 the good one, map 1 the case: each field's value per map."""
    cases = zip((1.0, L, E, H), (scale, size, modulus, hardness))
    columns = [jnp.array([good, bad], jnp.float64) for good, bad in cases]
    return _batch()(*columns)


CASES = {
    "NaN height scale": (np.nan, L, E, H),
    "infinite heights": (np.inf, L, E, H),
    "heights x 1e300": (1e300, L, E, H),
    "NaN size": (1.0, np.nan, E, H),
    "negative modulus": (1.0, L, -1e11, H),
    "NaN modulus": (1.0, L, np.nan, H),
    "NaN hardness": (1.0, L, E, np.nan),
    "zero hardness": (1.0, L, E, 0.0),
}


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_a_traced_bad_argument_flags_its_map_as_invalid(case):
    sol, _ = _solve(*case)
    np.testing.assert_array_equal(sol.status[1], [INVALID, INVALID])


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_the_bad_maps_stiffness_is_nan(case):
    sol, _ = _solve(*case)
    assert np.all(np.isnan(np.asarray(sol.stiffness[1])))


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_the_good_map_beside_a_bad_one_is_solved_as_alone(case):
    sol, _ = _solve(*case)
    alone, _ = _solve(1.0, L, E, H)
    np.testing.assert_array_equal(sol.stiffness[0], alone.stiffness[0])


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_every_gradient_of_a_batch_with_a_bad_map_is_finite(case):
    _, gradient = _solve(*case)
    assert np.all(np.isfinite(np.asarray(gradient)))


@settings(max_examples=40, deadline=None)
@given(
    scale=st.sampled_from([1.0, -1.0, 0.0, 1e-30, 1e30, 1e300, np.inf, -np.inf, np.nan]),
    size=st.sampled_from([L, 0.0, -L, 1e300, np.inf, np.nan]),
    modulus=st.sampled_from([E, 0.0, -E, 1e-300, 1e300, np.inf, np.nan]),
    hardness=st.sampled_from([H, 1e-300, 0.0, -H, 1e300, np.inf, np.nan]),
)
def test_no_status_ok_with_a_non_finite_or_non_positive_stiffness(scale, size, modulus, hardness):
    """Whatever the traced arguments: an OK point has a finite positive K, and gradients stay finite."""
    sol, gradient = _solve(scale, size, modulus, hardness)
    ok = np.asarray(sol.status) == 0
    stiffness = np.asarray(sol.stiffness)
    assert np.all(np.isfinite(stiffness[ok]) & (stiffness[ok] > 0))
    assert np.all(np.isfinite(np.asarray(gradient)))


@pytest.mark.parametrize("tolerance", [1.0, 0.1, 1e-4, 0.0, -1e-9])
def test_a_tolerance_outside_its_range_is_refused(tolerance):
    with pytest.raises(ValueError, match=r"tolerance .* = .* is outside its valid range \(0, 1e-05\]"):
        bem.solve(HEIGHTS, L, E, LOADS, tolerance=tolerance)


@pytest.mark.parametrize("max_iterations", [0, -3])
def test_max_iterations_below_one_is_refused(max_iterations):
    with pytest.raises(ValueError, match=r"max_iterations = .* must be an integer >= 1"):
        bem.solve(HEIGHTS, L, E, LOADS, max_iterations=max_iterations)


def test_a_map_that_is_not_square_is_refused():
    with refused_type("heights", "must be a square map|takes a square map"):
        bem.solve(jnp.zeros((16, 8)), L, E, LOADS)


def test_a_fractional_iteration_count_is_refused():
    with refused_type("max_iterations", r"max_iterations = 2.5 must be an integer >= 1"):
        bem.solve(HEIGHTS, L, E, LOADS, max_iterations=2.5)


def test_the_bem_model_refuses_a_loose_tolerance():
    with pytest.raises(ValueError, match=r"tolerance .* is outside its valid range"):
        jc.BEM(tolerance=1.0)


def test_a_concrete_map_beyond_the_precisions_range_is_refused():
    with pytest.raises(ValueError, match="beyond the working precision's range"):
        bem.solve(HEIGHTS * 1e300, L, E, LOADS)


@functools.cache
def _past_full_contact(capped: bool):
    """Loads 1e-3, 1e6 (past full contact, and past H·A when capped) and 3e-3 in units of E L²: each
    point's status and the gradient of the masked Σ secant with respect to (heights' scale, E, H)."""
    loads = jnp.array([1e-3, 1e6, 3e-3]) * UNIT

    def masked(theta):
        scale, modulus, hardness = theta
        sol = bem.solve(scale * HEIGHTS, L, modulus, loads, hardness=hardness if capped else None, secant=0.02)
        return jnp.sum(jnp.where(sol.status == 0, sol.secant_stiffness / UNIT, 0.0)), sol.status

    theta = jnp.array([1.0, E, H])
    return jax.grad(masked, has_aux=True)(theta)


@pytest.mark.parametrize("capped", [False, True], ids=["elastic", "capped"])
def test_a_load_past_full_contact_is_flagged(capped):
    _, status = _past_full_contact(capped)
    np.testing.assert_array_equal(status, [0, jc.Status.LOAD_OUT_OF_RANGE, 0])


@pytest.mark.parametrize("capped", [False, True], ids=["elastic", "capped"])
def test_a_load_past_full_contact_leaves_the_gradient_finite(capped):
    gradient, _ = _past_full_contact(capped)
    assert np.all(np.isfinite(np.asarray(gradient)))


def test_the_contact_fractions_are_in_the_working_dtype():
    # A mean of a bool grid is float32 in JAX whatever x64 says; a fraction counted in float32 carries
    # ~1e-7 of round-off (and past 2^24 points cannot count a point), below the solve's own accuracy.
    sol = bem.solve(HEIGHTS, L, E, LOADS, hardness=H)
    assert sol.contact_fraction.dtype == sol.plastic_fraction.dtype == jnp.float64
