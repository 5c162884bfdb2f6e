"""The paper's qualitative findings (Figs. 3–6), with the material of Sec. 5.1, F* from 1e-7 to 1e-4."""

import jax.numpy as jnp
import numpy as np
import pytest
from helpers import SEC51, TABLE1, make_scene

import jaxcontact as jc

F_STAR = jnp.logspace(-7, -4, 7)
LOADS = F_STAR * SEC51["E"] * SEC51["area"]
SQRT_AREA = np.sqrt(SEC51["area"])


def curve(D, G_star, interaction="paper"):
    sol = jc.solve(make_scene(D=D, G=G_star * SQRT_AREA, **SEC51, interaction=interaction), LOADS)
    assert np.all(np.asarray(sol.status) == 0), (D, G_star, interaction, sol.status)
    return sol


def test_fig3_largest_spot_and_stiffness_rise_with_load():
    for D in (1.4, 1.5, 1.6):
        sol = curve(D, 1e-8)
        assert np.all(np.diff(np.asarray(sol.a_l)) > 0)
        assert np.all(np.diff(np.asarray(sol.stiffness)) > 0)
        assert np.all(np.diff(np.asarray(sol.real_area)) > 0)


def test_fig4_stiffness_rises_with_D():
    K = np.array([np.asarray(curve(D, 1e-8).stiffness_star) for D in (1.4, 1.45, 1.5, 1.55, 1.6)])
    assert np.all(np.diff(K, axis=0) > 0)


def test_fig5_stiffness_falls_with_G():
    K = np.array([np.asarray(curve(1.4, G).stiffness_star) for G in (1e-8, 2e-8, 3e-8, 4e-8, 5e-8)])
    assert np.all(np.diff(K, axis=0) < 0)


def test_fig6_interaction_ordering_and_growing_gap():
    K = {mode: np.asarray(curve(1.6, 1e-9, mode).stiffness) for mode in ("none", "paper", "series")}
    assert np.all(K["paper"] > K["none"])
    assert np.all(K["series"] < K["none"])
    gap_up, gap_down = K["paper"] / K["none"] - 1, 1 - K["series"] / K["none"]
    assert np.all(np.diff(gap_up) > 0)
    assert np.all(np.diff(gap_down) > 0)
    # "when the load is relatively small, the difference between these two models is not significant"
    assert gap_up[0] < 0.05
    assert gap_up[-1] > 2 * gap_up[0]


@pytest.mark.parametrize("model", ["xia2024", "jzz2010"])
def test_regime_shares_sum_to_one(model):
    sol = jc.solve(make_scene(D=1.4, G=1e-8 * SQRT_AREA, **SEC51, model=model), LOADS)
    np.testing.assert_allclose(np.sum(np.asarray(sol.load_share), axis=-1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(np.sum(np.asarray(sol.stiffness_share), axis=-1), 1.0, rtol=1e-12)
    plastic = sol.regimes.index("p")
    assert np.all(np.asarray(sol.stiffness_share)[:, plastic] == 0)  # plastic spots add no stiffness


def test_all_plastic_points_say_why_their_stiffness_is_zero():
    """D → 1 with a tiny G: every spot is past a_c, fully plastic; K = 0 is right and flagged as such."""
    scene = make_scene(D=1.0001, G=1e-10, E=1e9, nu=0.25, H=7.1876e9, area=1e-4, l_min=1e-9, interaction="none")
    sol = jc.solve(scene, np.array([1e-10, 1e-6, 1e-3]) * 1e9 * 1e-4)
    np.testing.assert_array_equal(np.asarray(sol.status), 0)
    np.testing.assert_array_equal(np.asarray(sol.stiffness), 0.0)
    np.testing.assert_array_equal(np.asarray(sol.fully_plastic), True)
    assert not bool(jc.solve(make_scene(**TABLE1), 22.0).fully_plastic)
