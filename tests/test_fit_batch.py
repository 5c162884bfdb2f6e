"""Many curves at once (optimistix Levenberg–Marquardt, vmapped): the same optima,
intervals, correlations and warnings as fitting each curve with `fitting.fit`, to 1e-6."""

import numpy as np
import pytest
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH
from helpers import WRONG_START as START
from helpers import make_scene

from jaxcontact import fitting
from jaxcontact.fitting._synthetic import synthetic_curve

# Without interaction (TRUTH): the batch program compiles in a quarter of the time, and the fit is the same fit.
F_STAR = np.geomspace(1e-10, 1e-4, 20)


@pytest.fixture(scope="module")
def curves():
    scene = make_scene(**TRUTH)
    loads, K = zip(*(synthetic_curve(scene, F_STAR, noise=0.05, seed=300 + s) for s in range(6)))
    return np.array(loads), np.array(K)


@pytest.fixture(scope="module")
def batch(curves):
    return fitting.fit_batch(*curves, make_scene(**START), n_starts=4)


@pytest.fixture(scope="module")
def one_by_one(curves):
    return [fitting.fit(loads, K, make_scene(**START), n_starts=4) for loads, K in zip(*curves)]


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_batch_finds_each_curves_optimum(batch, one_by_one, name):
    looped = np.array([r.values[name] for r in one_by_one])
    assert np.allclose(batch.values[name], looped, rtol=1e-6, atol=0)


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_batch_gives_each_curves_standard_error(batch, one_by_one, name):
    looped = np.array([r.stderr[name] for r in one_by_one])
    assert np.allclose(batch.stderr[name], looped, rtol=1e-6, atol=0)


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_batch_gives_each_curves_interval(batch, one_by_one, name):
    looped = np.array([r.ci95[name] for r in one_by_one])
    assert np.allclose(batch.ci95[name], looped, rtol=1e-6, atol=0)


def test_the_batch_gives_each_curves_correlation(batch, one_by_one):
    looped = np.array([r.correlation for r in one_by_one])
    assert np.allclose(batch.correlation, looped, rtol=1e-6, atol=1e-9)


def test_the_batch_warns_as_the_fit_warns(batch, one_by_one):
    assert batch.warnings == tuple(tuple(r.warnings) for r in one_by_one)


def test_each_curves_fit_result_reports_the_fits_loss(batch, one_by_one):
    """`BatchResult.fits`: per curve the `FitResult` that `fit` returns, its loss as `fit` measures it."""
    np.testing.assert_allclose([f.loss for f in batch.fits], [r.loss for r in one_by_one], rtol=1e-6)


def test_each_curves_fit_result_holds_its_fitted_scene(batch):
    assert [float(f.scene.surface.D) for f in batch.fits] == list(batch.values["D"])


def test_each_curves_fit_result_summarises_its_fit(batch, one_by_one):
    """The summary's parameter lines (the first line says how each search went, which differs)."""
    assert batch.fits[0].summary().splitlines()[1:] == one_by_one[0].summary().splitlines()[1:]


def test_every_curve_converges(batch):
    assert batch.success.all()


def test_a_second_batch_of_the_same_shape_compiles_nothing(curves, batch):
    again = fitting.fit_batch(curves[0], curves[1] * 1.01, make_scene(**START), n_starts=4)
    assert again.compile_time < 0.1 * batch.compile_time


def test_the_intervals_cover_the_truth_in_most_curves(batch):
    lo, hi = batch.ci95["D"].T
    assert np.sum((lo < TRUTH["D"]) & (TRUTH["D"] < hi)) >= 5


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(loads=np.ones((2, 3)), stiffness=np.ones((3, 3))), r"loads \(2, 3\) and stiffness \(3, 3\) differ"),
        (dict(loads=np.ones((2, 2)), stiffness=np.ones((2, 2))), "2 points per curve cannot determine 2"),
        (
            dict(loads=-np.ones((2, 5)), stiffness=np.ones((2, 5))),
            r"no curve can be fitted: curve 0, point 0: loads = -1.0 is not positive",
        ),
    ],
)
def test_bad_batches_are_refused_by_name(kw, message):
    with pytest.raises(ValueError, match=message):
        fitting.fit_batch(kw["loads"], kw["stiffness"], make_scene(**START))


@pytest.fixture(scope="module")
def mixed(curves, batch):
    """The batch's curves (the same shape: nothing compiled) with curve 2 replaced by pure noise, and a
    negative stiffness at point 7 of curve 4."""
    loads, K = curves[0].copy(), curves[1].copy()
    K[2] = 10 ** np.random.default_rng(5).uniform(8, 11, K.shape[1])
    K[4, 7] = -1.0
    return fitting.fit_batch(loads, K, make_scene(**START), n_starts=4)


def test_a_curve_that_was_not_fitted_has_no_fit_result(mixed):
    assert mixed.fits[4] is None


def test_a_pure_noise_curve_among_good_ones_is_not_a_success(mixed):
    assert not mixed.success[2]


def test_a_pure_noise_curve_is_said_to_have_measured_nothing(mixed):
    assert any("determines no combination" in w for w in mixed.warnings[2])


def test_a_curve_with_a_bad_point_is_not_a_success(mixed):
    assert not mixed.success[4]


def test_the_bad_points_warning_names_its_curve_and_point(mixed):
    expected = "curve 4, point 7: stiffness = -1.0 is not positive and finite: the curve was not fitted"
    assert mixed.warnings[4] == (expected,)


def test_the_good_curves_beside_bad_ones_are_fitted_as_alone(mixed, batch):
    good = [0, 1, 3, 5]
    np.testing.assert_allclose(mixed.values["D"][good], batch.values["D"][good], rtol=1e-12)


PRIOR = {"D": fitting.Normal(TRUTH["D"], 0.005)}


@pytest.fixture(scope="module")
def prior_fits(curves):
    """The batch's curves with a prior on D, weighed at a stated noise: batch and one by one, both by
    Levenberg–Marquardt. (On curve 1 the MAP objective has two local optima 0.24 standard errors
    apart, Δχ² = 0.24, on either side of a regime kink; from these starts Levenberg–Marquardt,
    MINPACK's as the batch's, ends in one and BFGS in the other.)"""
    batch = fitting.fit_batch(*curves, make_scene(**START), n_starts=4, prior=PRIOR, noise=0.05)
    lm = fitting.LevenbergMarquardt()
    looped = [
        fitting.fit(loads, K, make_scene(**START), method=lm, n_starts=4, prior=PRIOR, noise=0.05)
        for loads, K in zip(*curves)
    ]
    return batch, looped


@pytest.mark.parametrize("name", ["D", "G"])
def test_a_batch_with_a_prior_finds_each_curves_map_estimate(prior_fits, name):
    batch, looped = prior_fits
    np.testing.assert_allclose(batch.values[name], [r.values[name] for r in looped], rtol=1e-6)


@pytest.mark.parametrize("name", ["D", "G"])
def test_a_batch_with_a_prior_gives_each_curves_laplace_standard_error(prior_fits, name):
    batch, looped = prior_fits
    np.testing.assert_allclose(batch.stderr[name], [r.stderr[name] for r in looped], rtol=1e-6)


def test_a_batch_with_a_prior_says_how_much_each_curve_measured(prior_fits):
    batch, looped = prior_fits
    shares = [info["D"]["curve_share"] for info in batch.information]
    np.testing.assert_allclose(shares, [r.information["D"]["curve_share"] for r in looped], rtol=1e-6)


def test_a_batch_with_a_prior_warns_as_the_fit_warns(prior_fits):
    batch, looped = prior_fits
    assert batch.warnings == tuple(tuple(r.warnings) for r in looped)


def test_a_batch_with_a_prior_weighs_each_curve_by_its_own_residual_scale(curves, one_by_one):
    # Unstated, each curve's noise is its residuals' scale fitted alone: `fit` with that noise stated.
    batch = fitting.fit_batch(*curves, make_scene(**START), n_starts=4, prior=PRIOR)
    scales = [np.sqrt(np.nansum(r.residuals**2) / (np.isfinite(r.residuals).sum() - 2)) for r in one_by_one]
    looped = [
        fitting.fit(loads, K, make_scene(**START), n_starts=4, prior=PRIOR, noise=float(s))
        for loads, K, s in zip(*curves, scales)
    ]
    np.testing.assert_allclose(batch.stderr["D"], [r.stderr["D"] for r in looped], rtol=1e-6)
