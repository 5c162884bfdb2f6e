"""The comparator models (GW, Persson, the Sneddon option) across the valid domain, as the seed
model's property tests do (hypothesis): finite or flagged, float32 agreeing with float64, finite
gradients beside bad loads, gradients against central differences."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from test_properties import SETTINGS, scene_of, valid

import jaxcontact as jc
from jaxcontact.numerics import x64

# The valid domain reaches hardnesses that look like unit mistakes (H > 1e11 Pa): expected here.
pytestmark = pytest.mark.filterwarnings("ignore::jaxcontact.PlausibilityWarning")


MODELS = {
    "gw": dict(model="gw"),
    "persson": dict(model="persson"),
    "sneddon": dict(model="xia2024", interaction="none", spot_stiffness="sneddon"),
}
AREA = 1e-4
# Loads that no model can evaluate, each beside good ones: NaN, negative, zero, far past full contact.
BAD_LOADS = (np.nan, -1.0, 0.0, 1e30)


def stiffness_and_status(scene, loads):
    sol = jc.solve(scene, loads)
    return np.asarray(sol.stiffness, dtype=float), np.asarray(sol.status)


@SETTINGS
@given(**valid, model=st.sampled_from(sorted(MODELS)))
def test_outputs_are_finite_or_flagged_and_float32_agrees(
    D, log10_G_star, E, nu, H_over_E, log10_l_min, log10_F_star, model
):
    point = (D, log10_G_star, E, nu, H_over_E, log10_l_min)
    loads = 10**log10_F_star * E * AREA * np.array([1.0, 0.1, 10.0])
    K64, status64 = stiffness_and_status(scene_of(*point, **MODELS[model]), jnp.asarray(loads))
    with x64(False):
        K32, status32 = stiffness_and_status(scene_of(*point, **MODELS[model]), loads.astype(np.float32))
    for K, status in ((K64, status64), (K32, status32)):
        assert np.all(np.isfinite(K[status == 0]) & (K[status == 0] >= 0)), (K, status)
        assert np.all(np.isnan(K[status != 0])), (K, status)
    both = (status64 == 0) & (status32 == 0) & (K64 > 0)
    np.testing.assert_allclose(K32[both], K64[both], rtol=1e-3)


def _with_theta(scene, theta):
    """D, ln G, ln E, ln H of `scene` set from `theta`."""
    getters = lambda s: (s.surface.D, s.surface.G, s.material.E, s.material.H)  # noqa: E731
    return eqx.tree_at(getters, scene, (theta[0], jnp.exp(theta[1]), jnp.exp(theta[2]), jnp.exp(theta[3])))


@jax.jit
def masked_log_stiffness(theta, scene, loads):
    """Σ ln K over the valid points with K > 0 (flagged ones add exactly 0), and how many there are."""
    sol = jc.solve(_with_theta(scene, theta), loads)
    used = sol.ok & (sol.stiffness > 0)
    return jnp.sum(jnp.where(used, jnp.log(jnp.where(used, sol.stiffness, 1.0)), 0.0)), jnp.sum(used)


gradient = jax.jit(jax.jacfwd(lambda theta, scene, loads: masked_log_stiffness(theta, scene, loads)[0]))


@SETTINGS
@given(**valid, model=st.sampled_from(sorted(MODELS)))
def test_gradients_are_finite_beside_bad_loads_and_match_central_differences(
    D, log10_G_star, E, nu, H_over_E, log10_l_min, log10_F_star, model
):
    scene = scene_of(D, log10_G_star, E, nu, H_over_E, log10_l_min, **MODELS[model])
    good = 10**log10_F_star * E * AREA * np.array([1.0, 0.3])
    loads = jnp.asarray(np.concatenate([good, np.array(BAD_LOADS) * E * AREA]))
    theta = jnp.array([D, np.log(float(scene.surface.G)), np.log(E), np.log(float(scene.material.H))])
    g = np.asarray(gradient(theta, scene, loads))
    assert np.all(np.isfinite(g)), g
    value, used = masked_log_stiffness(theta, scene, loads)
    assume(int(used) == 2)
    for i in range(4):
        step = 1e-6 * max(1.0, abs(float(theta[i])))
        # Smooth here: central differences of two steps agree (no regime boundary or flag within them).
        sides = [
            masked_log_stiffness(theta.at[i].add(sign * h), scene, loads) for h in (step, 2 * step) for sign in (1, -1)
        ]
        if any(int(n) != 2 for _, n in sides):
            continue
        fd1, fd2 = ((float(sides[k][0]) - float(sides[k + 1][0])) / (2 * h) for k, h in ((0, step), (2, 2 * step)))
        if abs(fd1 - fd2) > 1e-5 * max(abs(fd1), 1.0):
            continue
        assert abs(g[i] - fd1) <= 1e-5 * max(abs(fd1), 1.0), (model, i, g[i], fd1)
