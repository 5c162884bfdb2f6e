"""The public API's transformation contract: jit, vmap over loads and scenes, grad, jvp, x64."""

import subprocess
import sys

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import GETTERS, PARAMS, TABLE1, log_stiffness_and_gradient, make_scene

import jaxcontact as jc

LOADS = jnp.array([2.2, 22.0, 220.0])


def test_scalar_and_shaped_loads(table1_scene):
    vector = jc.solve(table1_scene, LOADS)
    scalar = jc.solve(table1_scene, 22.0)
    assert scalar.stiffness.shape == ()
    assert scalar.load_share.shape == (4,)
    np.testing.assert_allclose(scalar.stiffness, vector.stiffness[1], rtol=1e-14)
    grid = jc.solve(table1_scene, jnp.stack([LOADS, LOADS]))
    assert grid.stiffness.shape == (2, 3)
    assert grid.load_share.shape == (2, 3, 4)
    np.testing.assert_allclose(grid.stiffness[1], vector.stiffness, rtol=1e-14)


def test_jit_and_vmap_over_loads(table1_scene):
    ref = jc.solve(table1_scene, LOADS).stiffness
    np.testing.assert_allclose(jax.jit(jc.solve)(table1_scene, LOADS).stiffness, ref, rtol=1e-14)
    per_point = jax.vmap(lambda F: jc.solve(table1_scene, F).stiffness)(LOADS)
    np.testing.assert_allclose(per_point, ref, rtol=1e-13)


def test_vmap_over_batched_scenes():
    Ds = [1.3, 1.4058, 1.6]
    expected = [jc.solve(make_scene(**(TABLE1 | {"D": D})), LOADS).stiffness for D in Ds]
    # equinox idiom: in_axes as a tree like the scene's, mapping only D.
    scene = make_scene(**TABLE1)
    batched = eqx.tree_at(lambda s: s.surface.D, scene, jnp.array(Ds))
    in_axes = eqx.tree_at(lambda s: s.surface.D, jax.tree.map(lambda _: None, scene), 0, is_leaf=lambda x: x is None)
    out = eqx.filter_vmap(lambda s: jc.solve(s, LOADS).stiffness, in_axes=(in_axes,))(batched)
    np.testing.assert_allclose(out, jnp.stack(expected), rtol=1e-12)
    # plain jax.vmap over a fully stacked scene.
    stacked = jc.stack_scenes([make_scene(**(TABLE1 | {"D": D})) for D in Ds])
    out = jax.vmap(jc.solve, in_axes=(0, None))(stacked, LOADS).stiffness
    np.testing.assert_allclose(out, jnp.stack(expected), rtol=1e-12)
    # The dimensionless properties of a batch of scenes with different E and A_a: each row
    # divided by its own scene's scales (they are stored to broadcast against the loads).
    scales = [(1e11, 1e-4), (2e11, 4e-4), (3e11, 1e-3)]
    scenes = [make_scene(**(TABLE1 | {"E": E, "area": A})) for E, A in scales]
    batch = jax.vmap(jc.solve, in_axes=(0, None))(jc.stack_scenes(scenes), LOADS)
    for row, (E, A) in enumerate(scales):
        np.testing.assert_allclose(batch.load_star[row], LOADS / (E * A), rtol=1e-15)
        np.testing.assert_allclose(
            batch.stiffness_star[row], jc.solve(scenes[row], LOADS).stiffness / (E * np.sqrt(A)), rtol=1e-12
        )


@pytest.fixture(scope="module")
def whole_scene_gradient(table1_scene):
    """dK/d(every leaf) at 22 N: K times the gradient of ln K, from the program other files share."""
    (log_K, _), grad = log_stiffness_and_gradient(table1_scene, [22.0])
    return jax.tree.map(lambda g: jnp.exp(log_K) * g, grad)


def test_jvp_matches_grad(table1_scene, whole_scene_gradient):
    """Forward mode in D against the reverse-mode gradient with respect to the whole scene."""

    def K(D):
        return jc.solve(eqx.tree_at(lambda s: s.surface.D, table1_scene, D), 22.0).stiffness

    _, tangent = jax.jvp(K, (1.4058,), (1.0,))
    np.testing.assert_allclose(tangent, whole_scene_gradient.surface.D, rtol=1e-10)


@pytest.mark.parametrize("name", PARAMS)
def test_gradient_with_respect_to_the_whole_scene(table1_scene, whole_scene_gradient, name):
    """`jax.grad` with respect to the scene itself: each leaf's derivative against central differences."""
    grads = whole_scene_gradient
    value = TABLE1[name]
    h = 1e-6 * value
    up = float(jc.solve(eqx.tree_at(GETTERS[name], table1_scene, value + h), 22.0).stiffness)
    down = float(jc.solve(eqx.tree_at(GETTERS[name], table1_scene, value - h), 22.0).stiffness)
    np.testing.assert_allclose(float(GETTERS[name](grads)), (up - down) / (2 * h), rtol=1e-6)


def test_dimensionless_outputs(table1_scene):
    grid = jnp.stack([LOADS, 10.0 * LOADS])  # two load axes: the scales must broadcast over both
    sol = jc.solve(table1_scene, grid)
    E, A = TABLE1["E"], TABLE1["area"]
    np.testing.assert_allclose(sol.load_star, grid / (E * A), rtol=1e-15)
    np.testing.assert_allclose(sol.stiffness_star, sol.stiffness / (E * np.sqrt(A)), rtol=1e-14)
    np.testing.assert_allclose(sol.real_area_star, sol.real_area / A, rtol=1e-14)
    np.testing.assert_allclose(sol.a_l_star, sol.a_l / A, rtol=1e-14)
    assert sol.stiffness_star.shape == grid.shape
    assert sol.status.dtype == jnp.int32


def test_a_solution_on_the_host_gives_its_dimensionless_outputs_on_the_host(table1_scene):
    """A numpy solution (`solve_sweep`'s): its starred properties stay numpy (no JAX dispatch), equal to round-off."""
    sol = jc.solve(table1_scene, jnp.stack([LOADS, 10.0 * LOADS]))
    host = jax.tree.map(np.asarray, sol)
    for name in ("load_star", "stiffness_star", "real_area_star", "a_l_star"):
        assert type(getattr(host, name)) is np.ndarray, name
        np.testing.assert_allclose(getattr(host, name), np.asarray(getattr(sol, name)), rtol=1e-15, err_msg=name)


def test_import_does_not_enable_x64():
    code = (
        "import jax, jaxcontact as jc; assert not jax.config.jax_enable_x64; "
        "scene = jc.Scene(jc.Surface(1.4, 1e-10), jc.Material(2e11, 0.3, 1e11), 1e-4); "
        # The dtypes are fixed where the solve is traced: its shapes, without compiling it.
        "print(jax.eval_shape(jc.solve, scene, 10.0).stiffness.dtype)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        env={"JAX_PLATFORMS": "cpu", "PATH": ""},
    )
    assert out.stdout.strip() == "float32"


def test_import_leaves_diffrax_optimistix_and_quadax_until_they_are_needed():
    """`import jaxcontact` pays for none of diffrax's import (`jc.approach` brings it in),
    optimistix's (the first traced solve does) and quadax's (an adaptive quadrature's trace)."""
    code = (
        "import sys, jaxcontact as jc; print(*(m in sys.modules for m in ('diffrax', 'optimistix', 'quadax'))); "
        "jc.approach; print('diffrax' in sys.modules); print(sorted(set(jc.__all__) - set(dir(jc))))"
    )
    env = {"JAX_PLATFORMS": "cpu", "PATH": ""}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    at_import, after_approach, missing = out.stdout.split("\n")[:3]
    assert at_import == "False False False"
    assert after_approach == "True"
    assert missing == "[]"


def test_status_names():
    assert jc.status_message(0) == "ok"
    assert jc.status_message(2) == "interaction_breakdown"
    assert jc.status_message(jc.Status.LOAD_OUT_OF_RANGE) == "load_out_of_range"
