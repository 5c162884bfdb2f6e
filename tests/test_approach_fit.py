"""The approach curve by piecewise Gauss–Legendre quadrature (`approach_quadrature`) against scipy's
adaptive quadrature of 1/K, and fits of δ(F) alone and with K(F) (`fitting.fit(..., approach=...)`)."""

import equinox as eqx
import jax
import numpy as np
import pytest
from helpers import SEC51, TABLE1, make_scene, scipy_approach
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH
from helpers import WRONG_START as START

import jaxcontact as jc
from jaxcontact import InputError, fitting
from jaxcontact.numerics import x64

LOADS = np.geomspace(2.2, 2200.0, 12)


@pytest.fixture(scope="module")
def table1_curve():
    scene = make_scene(**TABLE1)
    return scene, scipy_approach(scene, LOADS, float(LOADS[0]))


def test_quadrature_matches_scipy_on_table1(table1_curve):
    scene, expected = table1_curve
    result = jc.approach_quadrature(scene, LOADS, float(LOADS[0]), nodes=12)
    np.testing.assert_allclose(result.approach, expected, rtol=1e-9, atol=0.0)


def test_quadrature_default_nodes_within_1e7(table1_curve):
    scene, expected = table1_curve
    result = jc.approach_quadrature(scene, LOADS, float(LOADS[0]))
    np.testing.assert_allclose(result.approach[1:], expected[1:], rtol=1e-7, atol=0.0)


def test_quadrature_in_float32_within_1e5(table1_curve):
    scene, expected = table1_curve
    with x64(False):
        result = jc.approach_quadrature(make_scene(**TABLE1), LOADS.astype(np.float32), np.float32(LOADS[0]))
        assert result.approach.dtype == np.float32
        np.testing.assert_allclose(np.asarray(result.approach)[1:], expected[1:], rtol=1e-5)


def test_quadrature_across_regime_kinks():
    """A scene whose a_l crosses regime boundaries between the loads: the kinks are piece ends."""
    scene = make_scene(D=1.43, G=3.3e-10, E=200e9, nu=0.3, H=5e9, area=1e-4, l_min=2e-9, interaction="series")
    loads = np.array([3e-7, 8e-7, 3e-6, 3e-5, 1e-4]) * 200e9 * 1e-4
    F0 = 1e-6 * 200e9 * 1e-4
    assert int(np.sum(np.isfinite(np.asarray(jc.core.kink_log_loads(scene))))) > 0
    result = jc.approach_quadrature(scene, loads, F0, nodes=12)
    np.testing.assert_allclose(result.approach, scipy_approach(scene, loads, F0), rtol=1e-9, atol=0.0)


@pytest.fixture(scope="module")
def beyond_a_breakdown():
    """Interaction "paper" breaks down above F* ≈ 2e-4 (D = 1.6): the curve at loads on both sides,
    and its forward-mode derivative in D (as a fit differentiates it), from one program."""
    scene = make_scene(**dict(SEC51, D=1.6, G=1e-9 * np.sqrt(1e-4)), interaction="paper")
    loads = np.array([1e-6, 1e-5, 1e-4, 1e-3]) * 210e9 * 1e-4

    def curve(D):
        return jc.approach_quadrature(eqx.tree_at(lambda s: s.surface.D, scene, D), loads, float(loads[0]))

    return jax.jvp(curve, (1.6,), (1.0,))


def test_quadrature_flags_only_points_beyond_a_breakdown(beyond_a_breakdown):
    result, _ = beyond_a_breakdown
    assert np.asarray(result.status).tolist() == [0, 0, 0, int(jc.Status.INTERACTION_BREAKDOWN)]


def test_quadrature_gradient_finite_with_a_flagged_point(beyond_a_breakdown):
    result, tangent = beyond_a_breakdown
    ok = np.asarray(result.status) == 0
    assert np.all(np.isfinite(np.asarray(tangent.approach)[ok]))


def test_quadrature_refuses_bad_nodes(table1_curve):
    with pytest.raises(ValueError, match=r"nodes = 1 must be an integer in \[2, 64\]"):
        jc.approach_quadrature(table1_curve[0], LOADS, 2.2, nodes=1)


# The fits are of Table 1 without interaction (TRUTH): the fit of δ(F) is the same fit (the
# interaction's δ is checked against scipy above).


@pytest.fixture(scope="module")
def fit_curve(table1_without_interaction):
    scene = table1_without_interaction
    return scene, scipy_approach(scene, LOADS, float(LOADS[0]))


@pytest.fixture(scope="module")
def approach_fit(fit_curve):
    """A noiseless δ(F) from scipy's quadrature, fitted alone from a wrong start."""
    return fitting.fit(LOADS, None, make_scene(**START), approach=fit_curve[1], n_starts=3)


@pytest.fixture(scope="module")
def joint_fit(fit_curve):
    scene, delta = fit_curve
    K = np.asarray(jc.solve(scene, LOADS).stiffness)
    return fitting.fit(LOADS, K, make_scene(**START), approach=delta, n_starts=3)


@pytest.fixture(scope="module")
def noisy_approach_curves(fit_curve):
    """Two noisy δ(F) curves of the same joint (2 % of the rms approach), measured from the first load."""
    _, delta = fit_curve
    noise = 0.02 * np.sqrt(np.mean(delta**2)) * np.random.default_rng(7).standard_normal((2, LOADS.size))
    approach = delta + noise
    approach[:, 0] = 0.0
    return approach


@pytest.fixture(scope="module")
def approach_batch(noisy_approach_curves):
    """D fitted to each curve (this load range fixes D and leaves ln G nearly open: a fit of both would
    compare two ends of a flat valley), from a wrong D."""
    delta, start = noisy_approach_curves, make_scene(**dict(TRUTH, D=START["D"]))
    batch = fitting.fit_batch(np.tile(LOADS, (2, 1)), None, start, ("D",), approach=delta, n_starts=3)
    one_by_one = [fitting.fit(LOADS, None, start, ("D",), approach=d, n_starts=3) for d in delta]
    return batch, one_by_one


def test_a_batch_of_approach_curves_finds_each_curves_optimum(approach_batch):
    batch, one_by_one = approach_batch
    np.testing.assert_allclose(batch.values["D"], [r.values["D"] for r in one_by_one], rtol=1e-6)


def test_a_batch_of_approach_curves_gives_each_curves_standard_error(approach_batch):
    batch, one_by_one = approach_batch
    np.testing.assert_allclose(batch.stderr["D"], [r.stderr["D"] for r in one_by_one], rtol=1e-6)


def test_a_batch_of_approach_curves_warns_as_the_fit_warns(approach_batch):
    batch, one_by_one = approach_batch
    assert batch.warnings == tuple(tuple(r.warnings) for r in one_by_one)


def test_a_batch_refuses_an_approach_off_zero_at_its_reference(noisy_approach_curves):
    shifted = noisy_approach_curves.copy()
    shifted[1, 0] = 1e-9
    start = make_scene(**dict(TRUTH, D=START["D"]))
    batch = fitting.fit_batch(np.tile(LOADS, (2, 1)), None, start, ("D",), approach=shifted, n_starts=3)
    assert batch.warnings[1] == (
        "curve 1: approach at the reference load 2.2 N must be 0 (it is measured relative to that load): "
        "the curve was not fitted",
    )


def test_fit_of_the_approach_alone_recovers_d(approach_fit):
    assert approach_fit.values["D"] == pytest.approx(TRUTH["D"], abs=1e-6)


def test_fit_of_the_approach_alone_recovers_g(approach_fit):
    assert approach_fit.values["G"] == pytest.approx(TRUTH["G"], rel=1e-4)


def test_joint_fit_recovers_d(joint_fit):
    assert joint_fit.values["D"] == pytest.approx(TRUTH["D"], abs=1e-6)


def test_joint_fit_reports_residuals_per_observable(joint_fit):
    assert joint_fit.residuals.shape == (LOADS.size, 2)


def test_approach_not_zero_at_the_reference_is_refused():
    with pytest.raises(InputError, match="approach at the reference load 2.2 N must be 0"):
        fitting.fit(LOADS, None, make_scene(**START), approach=np.linspace(1e-9, 1e-8, LOADS.size))


def test_one_noise_number_for_two_observables_is_refused():
    delta = np.linspace(0.0, 1e-8, LOADS.size)
    with pytest.raises(InputError, match="with both observables, give a dict"):
        fitting.fit(LOADS, np.ones(LOADS.size), make_scene(**START), approach=delta, noise=0.01)


def test_noise_of_an_unfitted_observable_is_refused():
    with pytest.raises(InputError, match="'approach' is not an observable of this fit"):
        fitting.fit(LOADS, np.ones(LOADS.size), make_scene(**START), noise={"approach": 1e-9})


def test_no_curve_is_refused():
    with pytest.raises(InputError, match="give at least one measured curve"):
        fitting.fit(LOADS, None, make_scene(**START))


def test_a_joint_fit_names_its_observables(joint_fit):
    assert joint_fit.observables == ("stiffness", "approach")


def test_a_stiffness_inconsistent_with_the_approach_is_not_described(fit_curve):
    """K 20 % above what the approach's slope says: no parameters describe both, and the fit says so."""
    scene, delta = fit_curve
    K = 1.2 * np.asarray(jc.solve(scene, LOADS).stiffness)
    noise = {"stiffness": 0.01, "approach": 1e-3 * float(np.sqrt(np.mean(delta**2)))}
    result = fitting.fit(LOADS, K, make_scene(**START), approach=delta, noise=noise, n_starts=3)
    assert not result.describes_data


def test_the_posteriors_density_of_an_approach_curve_is_its_misfit(fit_curve):
    """`sample`'s log density for δ(F) with a stated noise σ: −½ Σ ((δ_model − δ)/σ)², δ_model from
    the public quadrature of the approach, plus the log-Jacobian of the map onto the search bounds."""
    from jaxcontact.fitting._posterior import LogDensity

    scene, delta = fit_curve
    params, sigma, u = fitting.resolve(("D", "G")), 1e-9, np.array([0.3, -0.2])
    problem = fitting.Problem.of(LOADS, None, scene, ("D", "G"), approach=delta, noise=sigma)
    density = float(eqx.filter_jit(LogDensity(problem.misfit(1.0)))(u))
    values = tuple(p.from_stat(p.stat_from_u(x)) for p, x in zip(params, u))
    moved = eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, values)
    model = np.asarray(jc.approach_quadrature(moved, LOADS, float(LOADS[0])).approach)
    log_jacobian = np.sum(-np.log1p(np.exp(-u)) - np.log1p(np.exp(u)))
    assert density == pytest.approx(-0.5 * np.sum(((model - delta) / sigma) ** 2) + log_jacobian, rel=1e-9)
