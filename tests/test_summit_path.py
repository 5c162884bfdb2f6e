"""Measured elastic–plastic summits along a load path (`jc.solve_path` with `KogutEtsionSummits`):
each summit unloads and reloads below its deepest interference along Hertz's law about its residual
interference, against scipy's quadrature of that law over the summits (written out here from the
Kogut–Etsion fits), brentq, central differences and the dynamic stiffness's closed form."""

import math

import jax
import numpy as np
import pytest
from scipy import integrate, optimize
from test_measured_asperities import AREA, ETA, GAUSSIAN, HEIGHTS, E, R, ScipyGW
from test_summit_laws import HARDNESS, breaks, kogut_etsion, plastic_scene

import jaxcontact as jc
from jaxcontact.numerics import x64

# N: load, load further, unload twice, reload to the old maximum, beyond it, unload again.
PATH = np.array([3.0, 30.0, 10.0, 1.0, 30.0, 60.0, 5.0])


def unloaded_load(reference: ScipyGW, d_m, delta):
    """Σ over the summits of `P_m (1 − Δ/g)^(3/2)`, `g = 3 P_m/(4E a_m)`, with ω_m = z − d_m."""

    def summit(w_m):
        P, A = kogut_etsion(w_m)
        left = 1 - delta / (3 * P / (4 * E * math.sqrt(A / math.pi)))
        return P * left**1.5 if left > 0 else 0.0

    z = reference.z
    start = max(d_m, z[0])
    points = sorted(x for x in np.concatenate([z, d_m + np.asarray(breaks())]) if start < x < z[-1])
    integrand = lambda x: summit(x - d_m) * np.interp(x, z, reference.pdf)  # noqa: E731
    quad = integrate.quad(integrand, start, z[-1], points=points, limit=2000, epsabs=0.0, epsrel=1e-12)[0]
    return reference.count * quad


def rise(reference, d_m, F):
    """How far the flat rises from `d_m` to carry `F` on unloading (brentq)."""
    return optimize.brentq(lambda x: unloaded_load(reference, d_m, x) - F, 0.0, 3e-6, xtol=1e-20, rtol=1e-14)


@pytest.fixture(scope="module")
def reference():
    return ScipyGW(HEIGHTS, GAUSSIAN, R, ETA, E, AREA, summit=kogut_etsion, breaks=breaks())


@pytest.fixture(scope="module")
def path():
    return jc.solve_path(plastic_scene(), PATH)


def test_the_path_is_loading_unloading_and_reloading(path):
    assert list(np.asarray(path.branch)) == [0, 0, 1, 1, 2, 0, 1]


def test_every_point_is_ok(path):
    assert np.all(np.asarray(path.status) == jc.Status.OK)


def test_the_unloading_approach_is_scipys(path, reference):
    d_0, d_m = reference.separation(PATH[0]), reference.separation(PATH[1])
    expected = [d_0 - d_m - rise(reference, d_m, F) for F in PATH[2:4]]
    np.testing.assert_allclose(path.approach[2:4], expected, rtol=1e-9)


def test_the_unloading_tangent_is_central_differences_of_scipys_load(path, reference):
    d_m = reference.separation(PATH[1])
    delta = rise(reference, d_m, PATH[2])
    h = 1e-4 * delta
    expected = -(unloaded_load(reference, d_m, delta + h) - unloaded_load(reference, d_m, delta - h)) / (2 * h)
    np.testing.assert_allclose(path.stiffness[2], expected, rtol=1e-6)


def test_reloading_to_the_old_maximum_returns_to_its_approach(path):
    np.testing.assert_allclose(path.approach[4], path.approach[1], rtol=1e-12)


def test_the_reloading_tangent_at_the_old_maximum_is_the_unloading_tangent_at_the_top(path):
    np.testing.assert_allclose(path.stiffness[4], path.unloading_stiffness[1], rtol=1e-12)


def test_beyond_the_old_maximum_the_path_is_the_loading_curve(path, reference):
    np.testing.assert_allclose(
        path.approach[5], reference.separation(PATH[0]) - reference.separation(PATH[5]), rtol=1e-9
    )


def test_the_initial_unloading_tangent_is_the_dynamic_stiffness(path):
    """At the top the law unloads with Sneddon's 2E a_m per summit, the dynamic stiffness's closed form."""
    dynamic = jc.dynamic_stiffness(plastic_scene(), PATH[[1, 5]]).stiffness
    np.testing.assert_allclose(np.asarray(path.unloading_stiffness)[[1, 5]], dynamic, rtol=1e-9)


def test_the_residual_approach_is_the_top_summits_residual_interference(path, reference):
    w_m = HEIGHTS[-1] - reference.separation(PATH.max())
    P, A = kogut_etsion(w_m)
    expected = w_m - 3 * P / (4 * E * math.sqrt(A / math.pi))
    np.testing.assert_allclose(path.residual_approach, expected, rtol=1e-9)


def unloading_approach(hardness, loads):
    return jc.solve_path(plastic_scene(H=hardness), loads).approach[3]


@pytest.fixture(scope="module")
def gradient():
    return jax.grad(unloading_approach, argnums=(0, 1))(HARDNESS, PATH)


def test_the_approachs_derivative_with_respect_to_an_unloading_load_is_the_inverse_tangent(path, gradient):
    np.testing.assert_allclose(gradient[1][3], 1 / path.stiffness[3], rtol=1e-8)


def test_the_approachs_derivative_with_respect_to_the_hardness_is_central_differences(gradient):
    h = 1e-5 * HARDNESS
    expected = (unloading_approach(HARDNESS + h, PATH) - unloading_approach(HARDNESS - h, PATH)) / (2 * h)
    np.testing.assert_allclose(gradient[0], expected, rtol=1e-5)


def test_the_real_area_on_unloading_is_scipys(path, reference):
    d_m = reference.separation(PATH[1])
    delta = rise(reference, d_m, PATH[2])

    def summit(w_m):
        P, A = kogut_etsion(w_m)
        return A * max(1 - delta / (3 * P / (4 * E * math.sqrt(A / math.pi))), 0.0)

    np.testing.assert_allclose(path.real_area[2], reference.summed(summit, d_m), rtol=1e-8)


def test_float32_follows_float64(path):
    with x64(False):
        single = jc.solve_path(plastic_scene(), PATH.astype(np.float32))
    np.testing.assert_allclose(single.approach[1:], path.approach[1:], rtol=1e-3)
