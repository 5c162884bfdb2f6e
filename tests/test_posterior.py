"""The posterior by NUTS: a Gaussian target of known mean and covariance, and the seed model where its
posterior is near-Gaussian, against the Laplace approximation."""

import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, WRONG_START, make_scene
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH

import jaxcontact as jc
from jaxcontact import fitting
from jaxcontact.fitting._nuts import run_chains
from jaxcontact.fitting._synthetic import synthetic_curve

MEAN = np.array([1.0, -2.0])
COVARIANCE = np.array([[1.0, 0.8], [0.8, 2.0]])


def _gaussian(x):
    d = x - jnp.asarray(MEAN)
    return -0.5 * d @ jnp.asarray(np.linalg.inv(COVARIANCE)) @ d


@pytest.fixture(scope="module")
def gaussian_chains():
    return run_chains(_gaussian, jnp.zeros(2), chains=4, warmup=300, draws=1000, seed=1)


def test_the_mean_of_a_gaussian_target_within_monte_carlo_error(gaussian_chains):
    x = gaussian_chains.positions.reshape(-1, 2)
    error = np.sqrt(np.diag(COVARIANCE) / gaussian_chains.ess)
    assert np.all(np.abs(x.mean(axis=0) - MEAN) < 4 * error)


def test_the_covariance_of_a_gaussian_target(gaussian_chains):
    x = gaussian_chains.positions.reshape(-1, 2)
    assert np.allclose(np.cov(x.T), COVARIANCE, rtol=0.15, atol=0.1)


def test_four_chains_agree(gaussian_chains):
    assert np.all(gaussian_chains.rhat < 1.01)


def test_the_same_seed_gives_the_same_samples(gaussian_chains):
    again = run_chains(_gaussian, jnp.zeros(2), chains=4, warmup=300, draws=1000, seed=1)
    assert np.array_equal(again.positions, gaussian_chains.positions)


@pytest.fixture(scope="module")
def seed_model():
    """A well-determined seed-model curve (Table 1 without interaction, 12 loads over F* = 1e-10…1e-4,
    5 % noise): the sampler compiles in a fraction of the time, and the posterior is as near-Gaussian."""
    scene = make_scene(**TRUTH)
    loads, K = synthetic_curve(scene, np.geomspace(1e-10, 1e-4, 12), noise=0.05, seed=4)
    start = make_scene(**WRONG_START)
    posterior = fitting.sample(loads, K, start, chains=4, draws=250, warmup=200, seed=0, band_samples=40)
    return posterior, fitting.fit(loads, K, start, n_starts=4), loads, K


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_seed_models_posterior_sd_is_the_laplace_one(seed_model, name):
    posterior, laplace, _, _ = seed_model
    sd = posterior.sd[name] if name == "D" else np.std(np.log(posterior.samples[name]))
    se = laplace.stderr[name] if name == "D" else laplace.stderr[name] / laplace.values[name]
    assert sd == pytest.approx(se, rel=0.25)


def test_the_seed_models_posterior_mean_is_the_estimate(seed_model):
    posterior, laplace, _, _ = seed_model
    assert abs(posterior.mean["D"] - laplace.values["D"]) < 0.5 * laplace.stderr["D"]


def test_the_predicted_band_holds_the_true_curve(seed_model):
    """The band is the parameters' uncertainty carried to K: it holds the noise-free curve at the truth."""
    posterior, _, loads, _ = seed_model
    _, lower, _, upper = posterior.band
    truth = np.asarray(jc.solve(make_scene(**TRUTH), loads).stiffness)
    assert np.sum((lower <= truth) & (truth <= upper)) >= 10


@pytest.mark.parametrize("kw, message", [({"chains": 1}, "chains = 1 must be"), ({"draws": 5}, "draws = 5 must be")])
def test_bad_sampler_settings_are_refused_by_name(kw, message):
    with pytest.raises(ValueError, match=message):
        fitting.sample([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], make_scene(**TABLE1), **kw)


def test_a_well_determined_posterior_is_a_success(seed_model):
    posterior, _, _, _ = seed_model
    assert posterior.success, posterior.warnings


@pytest.fixture(scope="module")
def steep_curve(seed_model):
    """The same loads with K ∝ F^1.5: steeper than any D < 2 gives, so that the model does not describe
    it and its least-squares optimum is on D's and G's upper search bounds."""
    _, _, loads, _ = seed_model
    K = 1e9 * (loads / loads[0]) ** 1.5 * np.exp(0.01 * np.random.default_rng(1).normal(size=loads.size))
    return fitting.sample(loads, K, make_scene(**WRONG_START), chains=4, draws=250, warmup=200, seed=0, band_samples=40)


def test_the_posterior_of_a_rejected_model_is_not_a_success(steep_curve):
    assert not steep_curve.success


def test_the_posterior_of_a_rejected_model_says_so(steep_curve):
    assert "(of a model that does not describe the data)" in steep_curve.summary()


def test_the_posterior_of_an_optimum_on_a_search_bound_names_the_bound(steep_curve):
    assert any("D = 2 is on its upper search bound 2" in w for w in steep_curve.warnings), steep_curve.warnings


def test_a_second_curve_of_the_same_shape_samples_without_compiling(seed_model, steep_curve):
    """The steep curve's posterior after the seed model's (the same scene structure, loads and
    settings): the sampler's program is kept, only its arrays differ."""
    assert steep_curve.times["compilation"] == 0.0
