"""Gradients (implicit-function-theorem a_l solve) against central finite differences.

The loads are chosen so that a_l sits inside each regime and 0.1 % either side of each regime
boundary (a_c, 7.12 a_c, 205.4 a_c), where the per-asperity load law is discontinuous.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import GETTERS, PARAMS, TABLE1, make_joint, make_scene, total_loads, with_params

import jaxcontact as jc
from jaxcontact.physics._asperity import EP1_END, EP2_END


@eqx.filter_jit
def _stiffness_slopes(joint, log_a_l, log_load):
    """d ln K / d ln a_l at fixed load, per point."""

    def log_K(la, lf):
        return jnp.log(jnp.sum(joint.response(la, lf).regime_stiffness))

    return jax.vmap(jax.grad(log_K))(log_a_l, log_load)


def loads_for_spots(scene, spots_over_a_c):
    """Loads (N) at which the largest spot is a_l = factor · a_c, via the closed-form F_t."""
    joint = make_joint(scene)
    area, E = scene.area, scene.material.E
    log_a_c = float(joint.edges[1]) if hasattr(joint, "edges") else float(joint.log_a_c)
    log_a_l = jnp.log(jnp.asarray(spots_over_a_c)) + log_a_c
    return total_loads(joint, log_a_l) * E * area, jnp.exp(log_a_l) * area


def check_gradients(scene, factors, rtol=1e-5):
    loads, a_l = loads_for_spots(scene, factors)
    # θ: the scene's float fields, then s, the log of a common factor on every load: K_i depends
    # on F_i only, so dK_i/ds = F_i dK_i/dF_i, the load elasticity times K.
    theta0 = jnp.array([float(GETTERS[p](scene)) for p in PARAMS] + [0.0])
    names = (*PARAMS, "F")

    def stiffness(theta):
        return jc.solve(with_params(scene, theta[:-1]), loads * jnp.exp(theta[-1])).stiffness

    # One compiled program gives K and its Jacobian, for the exact derivatives and for the
    # finite differences alike (a separate forward program would be a second compilation).
    stiffness_and_jacobian = jax.jit(lambda theta: (stiffness(theta), jax.jacfwd(stiffness)(theta)))
    base, jac = stiffness_and_jacobian(theta0)
    assert np.all(np.isfinite(base))
    np.testing.assert_allclose(jc.solve(scene, loads).a_l, a_l, rtol=1e-9)  # the loads do hit the targets
    round_off = difference_round_off(scene, loads, a_l)
    for j, name in enumerate(names):
        h = 1e-6 * theta0[j] if name != "F" else 1e-6
        e = jnp.zeros_like(theta0).at[j].set(h)
        fd = (stiffness_and_jacobian(theta0 + e)[0] - stiffness_and_jacobian(theta0 - e)[0]) / (2 * h)
        scale = theta0[j] if name != "F" else 1.0  # s is a log already: dK/ds is θ dK/dθ
        assert_elasticity_close(jac[:, j], fd, scale, base, rtol, round_off, f"dK/d{name}")


def difference_round_off(scene, loads, a_l):
    """What round-off alone puts into a central-difference elasticity (step 1e-6 θ).

    The solve finds ln a_l to a few ulps, and K moves by |∂ln K/∂ln a_l| times that. Just above
    a_c, where K ∝ ln(a_l/a_c) + ..., that factor is ~1/0.001, so an ulp of ln a_l is a 4e-12
    change in K: central differences cannot see elasticities below ~1e-5 there.
    """
    joint = make_joint(scene)
    log_a_l = jnp.log(a_l / scene.area)
    log_load = jnp.log(loads / (scene.material.E * scene.area))
    slope = np.asarray(_stiffness_slopes(joint, log_a_l, log_load))
    slope = np.where(np.isfinite(slope), np.abs(slope), 0.0)
    return 4 * np.finfo(float).eps * np.abs(np.asarray(log_a_l)) * slope / 2e-6


def assert_elasticity_close(grad, fd, theta, value, rtol, round_off, what):
    """Compare the elasticities θ/K dK/dθ: to `rtol` relatively, or absolutely to 1e-8 plus the
    round-off floor of the difference where K hardly depends on θ (at fixed load K is nearly
    independent of the nominal area: there a central difference measures nothing but round-off)."""
    scale = np.where(np.asarray(value) != 0, value, 1.0)  # K = 0 exactly: all spots plastic (JZZ)
    exact, approx = np.asarray(grad * theta / scale), np.asarray(fd * theta / scale)
    tolerance = 1e-8 + round_off + rtol * np.abs(approx)
    bad = ~(np.abs(exact - approx) <= tolerance)
    assert not bad.any(), f"{what}: exact {exact[bad]}, differences {approx[bad]}, tolerance {tolerance[bad]}"


BOUNDARY_FACTORS = [
    0.05,
    0.999,
    1.001,
    3.0,
    EP1_END * 0.999,
    EP1_END * 1.001,
    40.0,
    EP2_END * 0.999,
    EP2_END * 1.001,
    1e4,
]


@pytest.mark.parametrize("interaction", ["paper", "series", "none"])
def test_xia2024_gradients_in_every_regime_and_across_boundaries(interaction):
    check_gradients(make_scene(**TABLE1, interaction=interaction), BOUNDARY_FACTORS)


def test_xia2024_wk_gradients():
    # The distribution is what is new here: with the series interaction (the paper one and its
    # pole are checked above), whose program compiles in a third of the time.
    check_gradients(make_scene(**TABLE1, distribution="wk", interaction="series"), [0.05, 1.001, 40.0, 1e4])


def test_jzz2010_gradients_either_side_of_a_c():
    check_gradients(make_scene(**TABLE1, model="jzz2010"), [0.3, 0.999, 1.001, 50.0, 1e4])
