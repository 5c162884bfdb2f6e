"""Numerically hard corners of the model stay finite, continuous and correctly flagged."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import GETTERS, PARAMS, TABLE1, log_stiffness_and_gradient, make_joint, make_scene, params_of, with_params

import jaxcontact as jc
from jaxcontact.numerics import x64
from jaxcontact.studies._scipy_baseline import BaselineParameters, solve_point

E, AREA = TABLE1["E"], TABLE1["area"]


@jax.jit
def _stiffness_at_D(D, scene, loads):
    return jc.solve(eqx.tree_at(lambda s: s.surface.D, scene, D), loads).stiffness


def stiffness_at_D(scene, loads):
    """K(D) at the loads; the scene travels as an argument (traced), as equinox passes modules."""
    return lambda D: _stiffness_at_D(D, scene, loads)


@pytest.mark.parametrize("model", ["xia2024", "jzz2010"])
def test_D_equal_to_one_and_a_half_is_continuous(model):
    """At D = 1.5 the elastic load integrand is a^-1 exactly: the log limit of the closed form."""
    scene = make_scene(**TABLE1, model=model)
    loads = jnp.array([2.2, 220.0])
    f = stiffness_at_D(scene, loads)
    # K and dK/dD from one compiled program (a forward-mode derivative carries the value along).
    value_and_slope = jax.jit(lambda D: jax.jvp(f, (D,), (jnp.ones_like(D),)))
    pairs = {d: value_and_slope(jnp.asarray(d)) for d in (1.5 - 1e-10, 1.5, 1.5 + 1e-10)}
    values = {d: np.asarray(value) for d, (value, _) in pairs.items()}
    grads = {d: np.asarray(slope) for d, (_, slope) in pairs.items()}
    assert all(np.all(np.isfinite(v)) for v in values.values())
    assert all(np.all(np.isfinite(g)) for g in grads.values())
    # Values move by the gradient times 1e-10 (the step is far below any structure), no jump.
    for d in (1.5 - 1e-10, 1.5 + 1e-10):
        np.testing.assert_allclose(values[d], values[1.5] + grads[1.5] * (d - 1.5), rtol=1e-12)
        np.testing.assert_allclose(grads[d], grads[1.5], rtol=1e-6)
    # ... and the value at exactly 1.5 agrees with the independent scipy implementation.
    p = BaselineParameters(1.5, TABLE1["G"], E, TABLE1["nu"], TABLE1["H"], AREA, TABLE1["l_min"], model=model)
    for i, F in enumerate(np.asarray(loads)):
        np.testing.assert_allclose(values[1.5][i], solve_point(p, float(F))[1], rtol=1e-8)


@pytest.mark.parametrize("D", [1.01, 1.99])
@pytest.mark.parametrize("interaction", ["none", "paper", "series"])
def test_extreme_fractal_dimensions_match_scipy(D, interaction):
    params = {**TABLE1, "D": D, "G": 1e-10}
    scene = make_scene(**params, interaction=interaction)
    loads = jnp.array([1e-7, 1e-5, 1e-4]) * E * AREA
    sol = jc.solve(scene, loads)
    p = BaselineParameters(**params, interaction=interaction)
    for i, F in enumerate(np.asarray(loads)):
        a_l, K, _, status = solve_point(p, float(F))
        assert jc.status_message(sol.status[i]) == status
        np.testing.assert_allclose(sol.a_l[i], a_l, rtol=1e-8)
        if status == "ok":
            np.testing.assert_allclose(sol.stiffness[i], K, rtol=1e-7)


def test_loads_from_tiny_to_the_out_of_range_limit(table1_scene):
    joint = make_joint(table1_scene)
    F_max = float(joint.total_load(jnp.asarray(0.0))) * E * AREA  # a_l = A_a
    scene = make_scene(**TABLE1, interaction="none")  # "paper" breaks down long before F_max
    loads = jnp.array([1e-12 * E * AREA, 1e-9 * E * AREA, 0.5 * F_max, 0.999999 * F_max, 1.000001 * F_max, 10 * F_max])
    sol = jc.solve(scene, loads)
    np.testing.assert_array_equal(sol.status, [0, 0, 0, 0, 1, 1])
    assert np.all(np.isfinite(sol.stiffness[:4]))
    assert np.all(np.isnan(sol.stiffness[4:]))
    assert np.all(np.diff(np.asarray(sol.stiffness[:4])) > 0)
    assert float(sol.a_l[3]) <= AREA
    assert float(sol.a_l[3]) > 0.99 * AREA
    # The tiniest load: a_l just above the cutoff l_min², still solved to full precision.
    p = BaselineParameters(**TABLE1, interaction="none")
    a_l, K, _, _ = solve_point(p, float(loads[0]))
    assert float(sol.a_l[0]) < 100 * TABLE1["l_min"] ** 2  # within two decades of the cutoff
    np.testing.assert_allclose([sol.a_l[0], sol.stiffness[0]], [a_l, K], rtol=1e-8)


def test_l_min_close_to_sqrt_area():
    """l_min = 0.99 sqrt(A_a): a_l must lie in the sliver (0.98 A_a, A_a]."""
    params = {**TABLE1, "l_min": 0.99 * np.sqrt(TABLE1["area"])}
    scene = make_scene(**params, interaction="series")
    joint = make_joint(scene)
    F_max = float(joint.total_load(jnp.asarray(0.0))) * E * AREA
    loads = jnp.array([1e-3, 0.3, 0.9]) * F_max
    sol = jc.solve(scene, loads)
    assert np.all(np.asarray(sol.status) == 0)
    p = BaselineParameters(**params, interaction="series")
    for i, F in enumerate(np.asarray(loads)):
        a_l, K, _, _ = solve_point(p, float(F))
        np.testing.assert_allclose([sol.a_l[i], sol.stiffness[i]], [a_l, K], rtol=1e-8)
    g = jax.grad(lambda lm: jc.solve(eqx.tree_at(lambda s: s.surface.l_min, scene, lm), loads[1]).stiffness)(
        params["l_min"]
    )
    assert np.isfinite(g)


def test_mixed_batch_keeps_good_points_and_their_gradients():
    """Breakdown, out-of-range and good points together: the good ones are exactly as if alone."""
    scene = make_scene(1.5, 3e-10, 1.13e11, 0.3, 4e9, 1e-4, 1e-9)  # checkpoints: 1130 N breaks down
    good = jnp.array([1.13, 11.3, 113.0])
    batch = jnp.array([1.13, 1130.0, 11.3, 1e9, 113.0])
    sol = jc.solve(scene, batch)
    np.testing.assert_array_equal(sol.status, [0, 2, 0, 1, 0])
    alone = jc.solve(scene, good)
    np.testing.assert_array_equal(sol.stiffness[jnp.array([0, 2, 4])], alone.stiffness)
    assert np.isnan(float(sol.stiffness[1]))
    assert np.isnan(float(sol.stiffness[3]))
    assert np.isfinite(float(sol.a_l[1]))  # breakdown still has a_l
    assert np.isnan(float(sol.a_l[3]))

    # With respect to every parameter, in reverse mode (where a NaN partial times a zero cotangent
    # is NaN): the scales E and A_a too, which multiply the flagged points' NaN unless the masking
    # is done with care. The dimensionless terms divide that NaN by E and A_a after `solve` has
    # returned. K is taken in units of its value at 113 N, so that no term drowns the others.
    # The good points alone are the batch's length too (good loads, weight 0, in the bad points'
    # place), so that both gradients come from one compiled program.
    K_unit = float(alone.stiffness[2])

    def masked_total(theta, loads, weights):
        s = jc.solve(with_params(scene, theta), loads)
        terms = s.stiffness / K_unit + s.stiffness_star + s.a_l_star + s.real_area_star
        return jnp.sum(jnp.where(s.ok, weights * terms, 0.0))

    theta = params_of(scene)
    gradient = jax.jit(jax.grad(masked_total))
    g_batch = gradient(theta, batch, jnp.ones(5))
    g_good = gradient(theta, good[jnp.array([0, 0, 1, 1, 2])], jnp.array([1.0, 0.0, 1.0, 0.0, 1.0]))
    assert g_batch.shape == (7,)
    assert np.all(np.isfinite(g_batch))
    assert np.all(g_good != 0)
    np.testing.assert_allclose(g_batch, g_good, rtol=1e-12)


def test_traced_invalid_loads_get_a_status():
    scene = make_scene(**TABLE1)
    sol = jax.jit(jc.solve)(scene, jnp.array([-1.0, jnp.nan, 0.0, 22.0]))
    np.testing.assert_array_equal(sol.status, [4, 4, 4, 0])
    assert np.isfinite(float(sol.stiffness[3]))


def test_unconverged_solve_is_flagged():
    sol = jc.solve(make_scene(**TABLE1, max_steps=1), jnp.array([22.0, 2200.0]))
    np.testing.assert_array_equal(sol.status, [jc.Status.NOT_CONVERGED] * 2)
    assert np.all(np.isnan(np.asarray(sol.stiffness)))


@pytest.mark.parametrize("model, interaction", [("xia2024", "paper"), ("xia2024", "series"), ("jzz2010", None)])
def test_float32_agrees_with_float64(model, interaction):
    loads = np.logspace(-7, -4, 7) * E * AREA
    scene64 = make_scene(**TABLE1, model=model, interaction=interaction)
    ref = jc.solve(scene64, jnp.asarray(loads))
    with x64(False):
        sol = jc.solve(make_scene(**TABLE1, model=model, interaction=interaction), loads.astype(np.float32))
        assert sol.stiffness.dtype == jnp.float32
        np.testing.assert_array_equal(sol.status, ref.status)
        np.testing.assert_allclose(sol.stiffness, ref.stiffness, rtol=1e-4)
        np.testing.assert_allclose(sol.a_l, ref.a_l, rtol=1e-4)
        # Forward mode, the cheaper compile: test_api.py checks that it is reverse mode's derivative.
        K = lambda D: jc.solve(eqx.tree_at(lambda s: s.surface.D, scene64, D), np.float32(22.0)).stiffness  # noqa: E731
        g32 = jax.jvp(K, (np.float32(1.4058),), (np.float32(1.0),))[1]
    # Against float64's central difference (good to 1e-5 and better, as test_gradients.py checks),
    # from the forward program compiled above: no float64 gradient program to compile.
    h = 1e-6 * 1.4058
    up, down = (jc.solve(eqx.tree_at(lambda s: s.surface.D, scene64, 1.4058 + d), 22.0).stiffness for d in (h, -h))
    np.testing.assert_allclose(g32, (up - down) / (2 * h), rtol=1e-3)


def test_float32_does_not_overflow_at_extreme_D():
    """a_c ∝ φ^(2/(1-D)) is ~1e170 A_a at D = 1.01: float32 must still give float64's answers."""
    loads = np.array([2.2e-5, 2.2, 2200.0])
    for D in (1.01, 1.99):
        params = {**TABLE1, "D": D, "G": 1e-10}
        ref = jc.solve(make_scene(**params, interaction="series"), loads)
        with x64(False):
            sol = jc.solve(make_scene(**params, interaction="series"), loads.astype(np.float32))
        np.testing.assert_array_equal(sol.status, ref.status)
        assert np.all(np.asarray(ref.status) == 0)
        np.testing.assert_allclose(sol.stiffness, ref.stiffness, rtol=1e-4)


def test_traced_parameters_outside_their_domain_are_flagged_not_raised():
    """An optimiser may step to D = 2 exactly: every point says so, and the masked gradient is 0, not NaN."""
    scene = make_scene(**TABLE1)
    theta = params_of(scene)
    cases = [
        ("D", 2.0),
        ("D", 1.0),
        ("D", np.nan),
        ("G", 0.0),
        ("E", -1.0),
        ("H", 0.0),
        ("nu", 0.5),
        ("area", 0.0),
        ("l_min", 0.02),
    ]  # l_min² > A_a
    for name, value in cases:
        outside = with_params(scene, theta.at[PARAMS.index(name)].set(value))
        (total, status), grad = log_stiffness_and_gradient(outside, [2.2, 22.0, 220.0])
        np.testing.assert_array_equal(status, [jc.Status.INVALID_PARAMETERS] * 3, err_msg=name)
        assert float(total) == 0.0
        np.testing.assert_array_equal([GETTERS[p](grad) for p in PARAMS], 0.0, err_msg=name)


@pytest.mark.parametrize("D, G, E, nu, H", [(1.4058, 2.2826e-10, 220e9, 0.25, 100e9), (1.75, 5e-11, 7e10, 0.33, 1.2e9)])
def test_paper_interaction_stays_accurate_right_up_to_breakdown(D, G, E, nu, H):
    """The pole of 1/(1 - r) reaches the stiffness range at breakdown; K must stay exact up to it."""
    from scipy import optimize

    from jaxcontact.studies import _reference as reference

    scene = make_scene(D, G, E, nu, H, 1e-4, 1e-9)
    log_breakdown = optimize.brentq(
        lambda lf: 0.5 - float(jc.solve(scene, jnp.exp(lf)).status == 2),
        np.log(1e-9 * E * 1e-4),
        np.log(1e-1 * E * 1e-4),
        xtol=1e-13,
    )
    loads = np.exp(log_breakdown) * np.array([0.5, 0.99, 0.999, 0.9999])
    sol = jc.solve(scene, jnp.asarray(loads))
    assert np.all(np.asarray(sol.status) == 0)
    exact = [reference.stiffness(D, G, E, nu, H, 1e-4, 1e-9, F)[0] for F in loads]
    np.testing.assert_allclose(sol.stiffness, exact, rtol=1e-10)
    assert int(jc.solve(scene, np.exp(log_breakdown) * 1.0001).status) == jc.Status.INTERACTION_BREAKDOWN


def test_series_interaction_where_every_spot_is_plastic_gives_zero_not_nan():
    """All spots plastic (D → 1, tiny G): the "series" stiffness is 0 like the others, not NaN with status ok."""
    scene = make_scene(D=1.0001, G=1e-10, E=1e9, nu=0.25, H=7.1876e9, area=1e-4, l_min=1e-9, interaction="series")
    sol = jc.solve(scene, np.array([1e-10, 1e-6, 1e-3]) * 1e9 * 1e-4)
    np.testing.assert_array_equal(np.asarray(sol.status), 0)
    np.testing.assert_array_equal(np.asarray(sol.stiffness), 0.0)


def test_a_nan_load_leaves_the_gradient_with_respect_to_the_scales_finite(table1_scene):
    """loads [22, 2200, NaN], loss = masked Σ ln K: d/dE and d/dA_a equal those of [22, 2200] alone."""
    with_nan = log_stiffness_and_gradient(table1_scene, [22.0, 2200.0, np.nan])[1]
    without = log_stiffness_and_gradient(table1_scene, [22.0, 2200.0])[1]
    for name in ("E", "area"):
        value = float(GETTERS[name](with_nan))
        assert np.isfinite(value), name
        np.testing.assert_allclose(value, float(GETTERS[name](without)), rtol=1e-12, err_msg=name)


def test_loads_too_small_to_resolve_are_flagged_not_wrong(table1_scene):
    """a_l within round-off of a_min: K ∝ ln(a_l/a_min) there cannot be computed, so it is flagged."""
    scene = table1_scene.with_model("xia2024", interaction="none")
    tiny = np.array([2.0066919810107414e-19, 2.0066919810102448e-21])  # K was 1.2 % and 40x off, status ok
    sol = jc.solve(scene, tiny)
    np.testing.assert_array_equal(np.asarray(sol.status), jc.Status.UNRESOLVED_LOAD)
    assert int(jc.solve(scene, 2.2e7 * 1e-16).status) == 0  # ln(a_l/a_min) = 0.011: resolved


def test_float32_flags_what_it_cannot_resolve_and_gets_the_rest_right():
    params = dict(D=1.5, G=1e-8, E=220e9, nu=0.25, H=100e9, area=1e-6, l_min=1e-7)
    loads = np.array([1e-12, 1e-8]) * 220e9 * 1e-6
    reference = np.asarray(jc.solve(make_scene(**params), loads).stiffness)
    with x64(False):
        sol = jc.solve(make_scene(**params), loads.astype(np.float32))
        np.testing.assert_array_equal(np.asarray(sol.status), [jc.Status.UNRESOLVED_LOAD, 0])
        np.testing.assert_allclose(float(sol.stiffness[1]), reference[1], rtol=1e-4)


def test_an_enormous_G_is_flagged_instead_of_one_answer_for_two_loads():
    """G = 1e300 m: every load puts a_l within round-off of a_min (it gave one a_l and K for two loads)."""
    sol = jc.solve(make_scene(**{**TABLE1, "G": 1e300}), np.array([22.0, 2200.0]))
    np.testing.assert_array_equal(np.asarray(sol.status), jc.Status.UNRESOLVED_LOAD)
