"""The contract every contact model passes: jit, vmap over loads and over parameters, gradients
against finite differences, float32, and per-point status masking. A model gets all of it by
being in the registry; the toy model of `toy_model.py` is registered here to show that a new
model is one file plus one registry line.
"""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, log_stiffness_and_gradient, make_scene
from scipy import integrate, optimize
from toy_model import AllElastic

import jaxcontact as jc
from jaxcontact.numerics import x64

jc.register_model(AllElastic)

# The boundary-element model needs a surface its grid resolves (l_min of a few grid spacings, not the
# Table 1 surface's 1 nm on 1 cm): it passes the same contract on such a scene in test_bem_model.py.
MODEL_NAMES = tuple(name for name in jc.MODELS if name != "bem")
F_STAR = np.array([1e-7, 1e-5, 1e-4])
LOAD_UNIT = TABLE1["E"] * TABLE1["area"]
LOADS = F_STAR * LOAD_UNIT
OUT_OF_RANGE = 10.0 * LOAD_UNIT  # F* = 10: more than full contact could carry


def scene_of(name):
    return make_scene(**TABLE1, model=name)


def with_D_and_G(scene, D, G):
    return eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, (D, G))


@eqx.filter_jit
def stiffness(scene, loads):
    return jc.solve(scene, loads).stiffness


def _value_and_grad(theta, scene, loads, weights):
    """Σ w ln K over the valid points at (D, ln G) = theta (flagged points contribute 0), and its
    gradient in theta, from the whole-scene gradient the tests of several files share."""
    G = jnp.exp(theta[1])
    (total, _), grad = log_stiffness_and_gradient(with_D_and_G(scene, theta[0], G), loads, weights)
    return total, jnp.stack([grad.surface.D, grad.surface.G * G])


# The contract loads and two bad points, an out-of-range load and a NaN: every gradient test
# uses one length of load array, so that each model's gradient is compiled once.
MIXED = jnp.asarray(np.concatenate([LOADS, [OUT_OF_RANGE, np.nan]]))
EVERY_POINT = jnp.ones(MIXED.shape)


def test_a_scene_names_the_registered_toy_model():
    """The one registry line makes the class a name that scenes (and scene files) use."""
    assert type(make_scene(**TABLE1, model="toy-all-elastic").model) is AllElastic


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_solve_is_valid_at_the_contract_loads(name):
    sol = jc.solve(scene_of(name), LOADS)
    np.testing.assert_array_equal(np.asarray(sol.status), 0)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_regime_shares_are_keyed_by_the_model_regimes(name):
    sol = jc.solve(scene_of(name), LOADS)
    assert sol.regimes == jc.MODELS[name].regimes
    assert sol.load_share.shape == (len(LOADS), len(sol.regimes))
    np.testing.assert_allclose(np.asarray(sol.load_share).sum(-1), 1.0, rtol=1e-12)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_jit_of_solve_equals_solve(name):
    scene = scene_of(name)
    jitted = stiffness(scene, jnp.asarray(LOADS))  # shared with the vmap tests below: one compilation
    np.testing.assert_allclose(np.asarray(jitted), np.asarray(jc.solve(scene, LOADS).stiffness), rtol=1e-14)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_vmap_over_loads_equals_the_batch(name):
    scene = scene_of(name)
    one_by_one = jax.vmap(lambda F: jc.solve(scene, F).stiffness)(jnp.asarray(LOADS))
    np.testing.assert_allclose(np.asarray(one_by_one), np.asarray(stiffness(scene, jnp.asarray(LOADS))), rtol=1e-13)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_vmap_over_parameters_equals_a_loop(name):
    scene = scene_of(name)
    Ds = jnp.array([1.3, 1.45, 1.6])
    batched = jax.vmap(lambda D: stiffness(eqx.tree_at(lambda s: s.surface.D, scene, D), jnp.asarray(LOADS)))(Ds)
    # D weakly typed, as a scene's own leaves are: the program `test_jit_of_solve_equals_solve` compiled.
    looped = [
        stiffness(eqx.tree_at(lambda s: s.surface.D, scene, jnp.asarray(float(D))), jnp.asarray(LOADS)) for D in Ds
    ]
    np.testing.assert_allclose(np.asarray(batched), np.asarray(looped), rtol=1e-12)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_gradient_matches_finite_differences(name):
    scene = scene_of(name)
    theta = jnp.array([TABLE1["D"], math.log(TABLE1["G"])])
    _, grad = _value_and_grad(theta, scene, MIXED, EVERY_POINT)
    h = 1e-6
    for i in range(2):
        step = jnp.zeros(2).at[i].set(h)
        up = float(_value_and_grad(theta + step, scene, MIXED, EVERY_POINT)[0])
        down = float(_value_and_grad(theta - step, scene, MIXED, EVERY_POINT)[0])
        np.testing.assert_allclose(float(grad[i]), (up - down) / (2 * h), rtol=1e-6, err_msg=f"d/d theta[{i}]")


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_float32_agrees_with_float64(name):
    scene = scene_of(name)
    reference = np.asarray(jc.solve(scene, LOADS).stiffness)
    with x64(False):
        single = jc.solve(scene, LOADS.astype(np.float32)).stiffness
        assert single.dtype == jnp.float32
        np.testing.assert_allclose(np.asarray(single), reference, rtol=1e-4)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_a_bad_point_is_flagged_and_leaves_the_others_alone(name):
    scene = scene_of(name)
    mixed = jnp.asarray(np.append(LOADS, OUT_OF_RANGE))
    sol = jc.solve(scene, mixed)
    assert int(sol.status[-1]) == jc.Status.LOAD_OUT_OF_RANGE
    assert np.isnan(float(sol.stiffness[-1]))
    np.testing.assert_allclose(np.asarray(sol.stiffness[:-1]), np.asarray(jc.solve(scene, LOADS).stiffness), rtol=1e-14)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_bad_points_leave_the_gradient_of_the_others_alone(name):
    """An out-of-range load and a NaN load in the batch add exactly nothing to the loss and its
    gradient: as much as two good loads of weight zero in their place."""
    scene = scene_of(name)
    theta = jnp.array([TABLE1["D"], math.log(TABLE1["G"])])
    value_mixed, grad_mixed = _value_and_grad(theta, scene, MIXED, EVERY_POINT)
    good_in_their_place = MIXED.at[len(LOADS) :].set(LOADS[0])
    only_the_good = EVERY_POINT.at[len(LOADS) :].set(0.0)
    value_alone, grad_alone = _value_and_grad(theta, scene, good_in_their_place, only_the_good)
    np.testing.assert_allclose(float(value_mixed), float(value_alone), rtol=1e-13)
    np.testing.assert_allclose(np.asarray(grad_mixed), np.asarray(grad_alone), rtol=1e-12)


def test_the_toy_model_matches_a_scipy_quadrature():
    """The registered toy model by name, against its integrals done by scipy (independent oracle)."""
    v = TABLE1
    D, G, E, area, a_min = v["D"], v["G"], v["E"], v["area"], v["l_min"] ** 2
    F = LOADS[1]
    elastic = 4 * math.sqrt(math.pi) / 3 * E * G ** (D - 1)

    def n(a, a_l):
        return D / 2 * a_l ** (D / 2) * a ** (-(D + 2) / 2)

    def in_log_area(integrand, a_l):
        """`∫ integrand(a) da` over (a_min, a_l], as `∫ integrand(e^t) e^t dt` (many decades of a)."""
        return integrate.quad(
            lambda t: integrand(math.exp(t)) * math.exp(t),
            math.log(a_min),
            math.log(a_l),
            epsabs=0.0,
            epsrel=1e-12,
            limit=200,
        )[0]

    def load(a_l):
        return in_log_area(lambda a: elastic * a ** ((3 - D) / 2) * n(a, a_l), a_l)

    a_l = math.exp(
        optimize.brentq(
            lambda t: math.log(load(math.exp(t)) / F), math.log(a_min) + 1e-9, math.log(area), xtol=1e-14, rtol=1e-14
        )
    )
    K = in_log_area(lambda a: 2 * E * math.sqrt(a / math.pi) * n(a, a_l), a_l)
    sol = jc.solve(make_scene(**TABLE1, model="toy-all-elastic"), F)
    np.testing.assert_allclose(float(sol.a_l), a_l, rtol=1e-8)
    np.testing.assert_allclose(float(sol.stiffness), K, rtol=1e-8)
