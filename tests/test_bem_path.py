"""`bem.solve_path`, the capped boundary-element contact along a load path: a Hertz sphere flattened
past the cap and unloaded against Sneddon's 2E*a, reloading against unloading, a rough surface's
unloading against a numpy flattening then an elastic `bem.solve`, derivatives against central
differences, float32, bad loads."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING, refused_type

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.numerics import x64

E, H = BEM_SETTING["E"], 3e8
TOP = 1e-4 * E * L * L  # 9.5 % contact on the rough map below, half of it at the cap
B = jc.Branch


def centred_grid(n):
    x = (np.arange(n) + 0.5) / n - 0.5
    return x[:, None], x[None, :]


# A paraboloid (R = 1, E* = 1) on a free half-space (64²), loaded to the elastic Hertz load of
# a = 0.2 (13 grid spacings) with the pressure capped at half Hertz's peak, 0.06: the contact flattens.
SPHERE_LOAD = 4 * 0.2**3 / 3
SPHERE_PATH = np.array([0.25, 0.5, 1.0, 0.5, 0.25, 0.5, 1.0, 1.2]) * SPHERE_LOAD


@pytest.fixture(scope="module")
def sphere():
    x, y = centred_grid(64)
    heights = jnp.asarray(-(x * x + y * y) / 2)
    path = bem.solve_path(heights, 1.0, 1.0, jnp.asarray(SPHERE_PATH), hardness=0.06, substrate=bem.Free())
    return heights, path


def test_each_point_is_on_the_branch_its_load_reaches(sphere):
    _, path = sphere
    assert np.asarray(path.branch).tolist() == [B.LOADING] * 3 + [B.UNLOADING] * 2 + [B.RELOADING] * 2 + [B.LOADING]


def test_the_sphere_flows_on_loading(sphere):
    _, path = sphere
    assert float(path.plastic_fraction[2]) > 0.5 * float(path.contact_fraction[2])


def test_the_initial_unloading_stiffness_is_2Ea_of_the_flattened_contact(sphere):
    _, path = sphere
    a = math.sqrt(float(path.contact_fraction[2]) / math.pi)
    np.testing.assert_allclose(float(path.unloading_stiffness[2]), 2 * a, rtol=1e-2)


def test_unloading_is_stiffer_than_loading_at_the_same_load(sphere):
    _, path = sphere
    assert float(path.stiffness[3]) > 1.5 * float(path.stiffness[1])


def test_a_full_unload_leaves_a_residual_approach(sphere):
    _, path = sphere
    assert float(path.residual_approach) > 0.1 * float(path.approach[2])


def test_reloading_below_the_old_maximum_retraces_unloading(sphere):
    _, path = sphere
    np.testing.assert_allclose(float(path.approach[5]), float(path.approach[3]), rtol=1e-7)


def test_reloading_below_the_old_maximum_is_elastic(sphere):
    _, path = sphere
    assert float(path.plastic_fraction[5]) == 0.0


def test_reloading_to_the_old_maximum_returns_to_its_approach(sphere):
    _, path = sphere
    np.testing.assert_allclose(float(path.approach[6]), float(path.approach[2]), rtol=1e-7)


ROUGH_PATH = np.array([1.0, 0.6, 0.3]) * TOP


@pytest.fixture(scope="module")
def rough():
    return jnp.asarray(bem.realisation(1.5, 1e-12, L / 16, L, 64, 1).heights())


def _numpy_flattened(heights, pressure, offset, hardness):
    """The heights lowered by the interpenetration of the points at the cap: the displacement of
    the periodic half-space `2 p̂(q) / (E* |q|)` by numpy's FFT, the gap `u − h − δ`."""
    n = heights.shape[0]
    q = 2 * np.pi * np.hypot(*np.meshgrid(np.fft.fftfreq(n, L / n), np.fft.rfftfreq(n, L / n), indexing="ij"))
    kernel = np.divide(2.0, E * q, out=np.zeros_like(q), where=q > 0)
    displacement = np.fft.irfft2(np.fft.rfft2(pressure) * kernel, s=(n, n))
    gap = displacement - heights - offset
    return heights + np.where(pressure >= hardness * (1 - 1e-9), np.minimum(gap, 0.0), 0.0)


@pytest.fixture(scope="module")
def rough_unloading(rough):
    """The path, and its oracle: the capped solve at the top, the map flattened by numpy, the
    elastic solve of the flattened map at the unloading loads."""
    path = bem.solve_path(rough, L, E, jnp.asarray(ROUGH_PATH), hardness=H)
    top = bem.solve(rough, L, E, jnp.asarray(ROUGH_PATH[:1]), hardness=H, pressure=True)
    flattened = _numpy_flattened(np.asarray(rough), np.asarray(top.pressure[0]), float(top.offset[0]), H)
    elastic = bem.solve(jnp.asarray(flattened), L, E, jnp.asarray(ROUGH_PATH[1:]))
    return path, top, flattened, elastic


def test_the_rough_map_flows_at_the_top(rough_unloading):
    path, *_ = rough_unloading
    assert float(path.plastic_fraction[0]) > 0.3 * float(path.contact_fraction[0])


def test_the_flattened_map_is_numpys(rough_unloading, rough):
    path, _, flattened, _ = rough_unloading
    np.testing.assert_allclose(np.asarray(path.heights), flattened, rtol=0, atol=1e-7 * float(jnp.std(rough)))


def test_a_rough_unloading_has_the_flattened_maps_approach(rough_unloading, rough):
    path, top, _, elastic = rough_unloading
    expected = np.asarray(elastic.offset) - float(top.offset[0])
    np.testing.assert_allclose(np.asarray(path.approach[1:]), expected, rtol=0, atol=1e-6 * float(jnp.std(rough)))


def test_a_rough_unloading_has_the_flattened_maps_stiffness(rough_unloading):
    path, _, _, elastic = rough_unloading
    np.testing.assert_allclose(np.asarray(path.stiffness[1:]), np.asarray(elastic.stiffness), rtol=1e-6)


def test_loading_past_the_old_maximum_is_the_monotone_capped_solve(rough, rough_unloading):
    _, top, _, _ = rough_unloading
    path = bem.solve_path(rough, L, E, jnp.asarray(ROUGH_PATH[::-1]), hardness=H)  # 0.3, 0.6 and 1 TOP
    np.testing.assert_allclose(float(path.stiffness[-1]), float(top.stiffness[0]), rtol=1e-6)


def test_an_elastic_path_retraces_the_loading_solve(rough, rough_unloading):
    *_, elastic = rough_unloading
    path = bem.solve_path(rough, L, E, jnp.asarray(ROUGH_PATH))
    loading = bem.solve(rough, L, E, jnp.asarray(ROUGH_PATH[1:]))
    np.testing.assert_allclose(np.asarray(path.stiffness[1:]), np.asarray(loading.stiffness), rtol=1e-7)


def test_the_derivatives_match_central_differences(rough):
    """Of the residual approach and the approach after unloading, with respect to a scale factor of
    the heights, ln E*, ln H and ln F: through the flattening of the earlier points."""
    shape = jnp.asarray([1.0, 0.4, 0.7])  # unloading, then reloading

    @jax.jit
    def outputs(theta):
        s, log_E, log_H, log_F = theta
        path = bem.solve_path(s * rough, L, jnp.exp(log_E), TOP * jnp.exp(log_F) * shape, hardness=jnp.exp(log_H))
        return jnp.stack([path.residual_approach, path.approach[-1]]) / 1e-7

    theta = jnp.array([1.0, math.log(E), math.log(H), 0.0])
    jacobian = jax.jacrev(outputs)(theta)
    step = 1e-6
    differences = jnp.stack(
        [(outputs(theta.at[i].add(step)) - outputs(theta.at[i].add(-step))) / (2 * step) for i in range(4)], axis=1
    )
    np.testing.assert_allclose(jacobian, differences, rtol=1e-4, atol=1e-6 * float(jnp.max(jnp.abs(differences))))


@pytest.fixture(scope="module")
def single(rough):
    """The rough path in float32 under `jax.jit`: one program for float32 and for traced bad loads."""
    with x64(False):
        solve = jax.jit(
            lambda loads: bem.solve_path(
                jnp.asarray(rough, jnp.float32), np.float32(L), np.float32(E), loads, hardness=np.float32(H)
            )
        )
        return {
            "path": solve(jnp.asarray(ROUGH_PATH, jnp.float32)),
            "bad": solve(jnp.array([TOP, jnp.nan, 0.3 * TOP], jnp.float32)),
            "good": solve(jnp.array([TOP, TOP, 0.3 * TOP], jnp.float32)),
        }


def test_float32_gives_the_float64_path_within_1e_3(rough_unloading, single):
    path, *_ = rough_unloading
    assert single["path"].stiffness.dtype == jnp.float32
    np.testing.assert_allclose(np.asarray(single["path"].stiffness), np.asarray(path.stiffness), rtol=1e-3)


def test_a_traced_bad_load_is_flagged(single):
    assert int(single["bad"].status[1]) == jc.Status.INVALID_LOAD


def test_a_traced_bad_load_leaves_the_surface_as_it_was(single):
    np.testing.assert_allclose(float(single["bad"].stiffness[2]), float(single["good"].stiffness[2]), rtol=1e-4)


@pytest.mark.parametrize("path, message", [([1.0, -1.0], r"path .* \(0, inf\)"), ([], r"path .* non-empty")])
def test_bad_paths_are_refused_naming_the_path(rough, path, message):
    with pytest.raises(ValueError, match=message):
        bem.solve_path(rough, L, E, np.asarray(path, float), hardness=H)


def test_a_path_of_more_than_one_axis_is_refused(rough):
    with refused_type("path", r"path .* 1-D"):
        bem.solve_path(rough, L, E, np.ones((2, 2)), hardness=H)
