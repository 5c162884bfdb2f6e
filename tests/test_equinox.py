"""The standard equinox calls on a `Scene`: its floats are array leaves, as in equinox and diffrax."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import GETTERS, PARAMS, TABLE1, make_scene

import jaxcontact as jc

LOADS = jnp.asarray(np.array([1e-6, 1e-4]) * TABLE1["E"] * TABLE1["area"])


def total_log_stiffness(scene):
    return jnp.sum(jnp.log(jc.solve(scene, LOADS).stiffness))


@pytest.fixture(scope="module")
def filter_grads():
    # With the series interaction: what is checked is equinox's filtering of the scene's leaves (the
    # paper interaction's derivatives are test_gradients.py's), and its programs compile in a third
    # of the time. (Without interaction ln K does not depend on A_a at all.)
    scene = make_scene(**TABLE1, interaction="series")
    return scene, eqx.filter_grad(total_log_stiffness)(scene)


def test_every_float_field_is_an_inexact_array_leaf():
    leaves = jax.tree.leaves(make_scene(**TABLE1))
    assert len(leaves) == len(PARAMS)
    assert all(eqx.is_inexact_array(x) for x in leaves)


@pytest.mark.parametrize("name", PARAMS)
def test_filter_grad_differentiates_every_parameter(filter_grads, name):
    """`eqx.filter_grad` of a loss of the scene, each parameter against central differences."""
    scene, grads = filter_grads
    value = TABLE1[name]
    h = 1e-6 * value
    up = float(total_log_stiffness(eqx.tree_at(GETTERS[name], scene, value + h)))
    down = float(total_log_stiffness(eqx.tree_at(GETTERS[name], scene, value - h)))
    np.testing.assert_allclose(float(GETTERS[name](grads)), (up - down) / (2 * h), rtol=1e-6)


def test_filter_jit_does_not_recompile_for_new_parameter_values():
    traces = []

    @eqx.filter_jit
    def K(scene):
        traces.append(None)
        return jc.solve(scene, LOADS).stiffness

    first = K(make_scene(**TABLE1))
    second = K(make_scene(**{**TABLE1, "D": 1.5, "G": 1e-10}))
    assert len(traces) == 1
    assert not np.allclose(np.asarray(first), np.asarray(second))


def test_filter_vmap_over_stacked_scenes_equals_a_loop():
    scenes = [make_scene(**{**TABLE1, "D": D}) for D in (1.3, 1.5)]
    batched = eqx.filter_vmap(lambda s: jc.solve(s, LOADS).stiffness)(jc.stack_scenes(scenes))
    looped = [jc.solve(s, LOADS).stiffness for s in scenes]
    np.testing.assert_allclose(np.asarray(batched), np.asarray(looped), rtol=1e-12)


def test_tree_map_over_two_scenes_gives_a_scene_between_them():
    """`jax.tree.map` rebuilds a Scene from new leaves (its checks pass, its model is kept)."""
    low, high = make_scene(**{**TABLE1, "D": 1.3}), make_scene(**{**TABLE1, "D": 1.5})
    middle = jax.tree.map(lambda a, b: (a + b) / 2, low, high)
    assert float(middle.surface.D) == pytest.approx(1.4, rel=1e-15)


def test_tree_map_over_two_scenes_keeps_their_model():
    low, high = make_scene(**{**TABLE1, "D": 1.3}), make_scene(**{**TABLE1, "D": 1.5})
    assert jax.tree.map(lambda a, b: (a + b) / 2, low, high).model == low.model
