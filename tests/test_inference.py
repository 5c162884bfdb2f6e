"""What a curve determines (Fisher directions, profiles) and joint inference with a prior: against
analytic cases, closed forms and seed-model-made curves of known truth."""

import math

import numpy as np
import pytest
from helpers import ROOT, make_scene
from helpers import TABLE1_WITHOUT_INTERACTION as TRUTH
from helpers import WRONG_START as START

import jaxcontact as jc
from jaxcontact import fitting
from jaxcontact import topography as tp
from jaxcontact.fitting._identifiability import combinations, report
from jaxcontact.fitting._optimise import AbstractObjective, run_lm
from jaxcontact.fitting._prior import GaussianPrior, PriorObjective, resolve_prior
from jaxcontact.fitting._synthetic import TABLE1_F_STAR, synthetic_curve

D_AND_G = fitting.resolve(("D", "G"))
ROOT_DATA = ROOT / "data" / "table1_grinding_generated.csv"
# The seed-model curves are Table 1's without interaction (TRUTH, conftest's `table1_without_interaction`):
# what is checked is the inference, on curves of known truth.


def _rank_one_information(direction, strength=1e6, floor=1e-6):
    v = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    return strength * np.outer(v, v) + floor * np.eye(2)


def test_the_determined_combination_is_the_one_the_data_depend_on():
    """K depends on D + 0.5 ln G alone: that combination is determined, its normal is not."""
    found = combinations(D_AND_G, _rank_one_information([1.0, 0.5]))
    assert np.allclose([found[0].weights["D"], found[0].weights["G"]], np.array([1.0, 0.5]) / math.sqrt(1.25))


def test_the_determined_combinations_standard_error_is_one_over_root_information():
    found = combinations(D_AND_G, _rank_one_information([1.0, 0.5], strength=400.0))
    assert found[0].stderr == pytest.approx(1 / math.sqrt(400.0 + 1e-6), rel=1e-9)


def test_the_ridge_is_reported_as_undetermined():
    found = combinations(D_AND_G, _rank_one_information([1.0, 0.5]))
    assert [c.determined for c in found] == [True, False]


def test_the_report_names_the_fixed_combination_and_the_open_one():
    text = report(D_AND_G, combinations(D_AND_G, _rank_one_information([1.0, 0.5])))
    assert "fixes 0.89 D +0.45 ln G" in text and "open" in text and "D, G alone undetermined" in text


@pytest.fixture(scope="module")
def profiled(table1_without_interaction):
    loads, K = synthetic_curve(table1_without_interaction, TABLE1_F_STAR, noise=0.01, seed=7)
    return fitting.fit(loads, K, make_scene(**START), n_starts=8, profile=True)


@pytest.mark.parametrize("name", ["D", "G"])
def test_profile_intervals_agree_with_the_parabolic_ones_on_a_well_determined_curve(profiled, name):
    lo, hi = profiled.profiles[name].ci95
    value, se = profiled.values[name], profiled.stderr[name]
    t = profiled.profiles[name].threshold ** 0.5
    if name == "G":  # parabolic in ln G
        lo, hi, value, se = math.log(lo), math.log(hi), math.log(value), se / value
    assert (hi - lo) / (2 * t * se) == pytest.approx(1.0, abs=0.05)


def test_a_well_determined_curve_determines_every_combination(profiled):
    assert all(c.determined for c in profiled.identifiability)


class _Linear(AbstractObjective):
    """A linear model in statistical coordinates: r = X θ − y, for the prior's closed-form check."""

    def __init__(self, X, y):
        self.X, self.y, self.params, self.n_points = X, y, D_AND_G, len(y)

    def residuals(self, u):
        stat, slope = zip(*(p.stat_and_slope_from_u(x) for p, x in zip(self.params, u)))
        return self.X @ np.asarray(stat) - self.y, self.X * np.asarray(slope)


def test_the_map_estimate_is_the_gaussian_linear_closed_form():
    rng = np.random.default_rng(0)
    X = np.column_stack([rng.normal(size=20), 0.1 * rng.normal(size=20)])
    truth = np.array([1.45, math.log(3e-10)])
    sigma = 0.05
    y = X @ truth + sigma * rng.normal(size=20)
    prior = GaussianPrior((0, 1), np.array([1.5, math.log(1e-10)]), np.array([[0.02**2, 0.0], [0.0, 0.5**2]]), "test")
    precision = X.T @ X / sigma**2 + np.linalg.inv(prior.covariance)
    closed = np.linalg.solve(precision, X.T @ y / sigma**2 + np.linalg.solve(prior.covariance, prior.mean))
    objective = PriorObjective(_Linear(X, y), prior, sigma)
    u0 = np.array([p.u_from_stat(m) for p, m in zip(D_AND_G, prior.mean)])
    found = run_lm(objective, u0, 400, 1e-12).u
    assert np.allclose([p.stat_from_u(x) for p, x in zip(D_AND_G, found)], closed, rtol=0, atol=1e-7)


def test_a_tight_prior_holds_D_and_the_curve_gives_G(table1_without_interaction):
    loads, K = synthetic_curve(table1_without_interaction, TABLE1_F_STAR, noise=0.05, seed=3)
    result = fitting.fit(loads, K, make_scene(**START), n_starts=4, prior={"D": fitting.Normal(TRUTH["D"], 1e-4)})
    assert result.values["D"] == pytest.approx(TRUTH["D"], abs=3e-4)


def test_the_report_says_how_much_came_from_the_curve(table1_without_interaction):
    loads, K = synthetic_curve(table1_without_interaction, TABLE1_F_STAR, noise=0.05, seed=3)
    wide = fitting.fit(loads, K, make_scene(**START), n_starts=4, prior={"D": fitting.Normal(1.4, 0.5)})
    assert wide.information["D"]["curve_share"] > 0.99


@pytest.fixture(scope="module")
def half_informed(table1_without_interaction):
    """A curve of 20 points and a prior on D that each carry about half of D's information."""
    loads, K = synthetic_curve(table1_without_interaction, TABLE1_F_STAR[::2], noise=0.05, seed=5)
    prior = {"D": fitting.Normal(TRUTH["D"], 0.002)}
    return loads, K, prior, fitting.fit(loads, K, make_scene(**START), n_starts=4, prior=prior)


def _quantile(result):
    low, high = result.ci95["D"]
    return (high - low) / (2 * result.stderr["D"])


def test_an_estimated_noise_widens_the_interval_by_satterthwaites_t(half_informed):
    """σ from the curve's N − p residuals: Student's t with (N − p)/s² degrees of freedom, s the curve's
    share of D's precision (scipy's quantile)."""
    from scipy import stats

    loads, _, _, result = half_informed
    share = result.information["D"]["curve_share"]
    assert 0.05 < share < 0.95, share  # a case where neither side decides alone
    dof = (loads.size - 2) / share**2
    assert _quantile(result) == pytest.approx(stats.t.ppf(0.975, dof), rel=1e-9)


def test_a_stated_noise_gives_the_normal_quantile(half_informed, table1_without_interaction):
    from scipy import stats

    loads, K, prior, _ = half_informed
    result = fitting.fit(loads, K, make_scene(**START), n_starts=4, prior=prior, noise=0.05)
    assert _quantile(result) == pytest.approx(stats.norm.ppf(0.975), rel=1e-6)


def test_joint_inference_covers_the_truth_over_seeds(table1_without_interaction):
    """Seed-model curves (5 % noise) with a surface prior drawn around the truth at its own covariance."""
    covariance = np.array([[0.02**2, 0.9 * 0.02 * 0.6], [0.9 * 0.02 * 0.6, 0.6**2]])
    truth = np.array([TRUTH["D"], math.log(TRUTH["G"])])
    rng = np.random.default_rng(11)
    covered = 0
    for seed in range(20):
        loads, K = synthetic_curve(table1_without_interaction, TABLE1_F_STAR[::2], noise=0.05, seed=2000 + seed)
        mean = rng.multivariate_normal(truth, covariance)
        prior = _surface(mean[0], math.exp(mean[1]), covariance)
        result = fitting.fit(loads, K, make_scene(**START), n_starts=4, prior=prior)
        covered += all(lo < v < hi for v, (lo, hi) in zip((TRUTH["D"], TRUTH["G"]), result.ci95.values()))
    assert covered >= 17


def _surface(D, G, covariance):
    """A characterisation as `fitting.fit` reads one: D, G and their (D, ln G) covariance (no power
    law of a spectrum, so the prior is a Gaussian in (D, ln G)); the rest is filler."""
    empty = (np.zeros(0), np.zeros(0))
    return tp.Characterisation(
        D=D,
        G=G,
        G_structure_function=math.nan,
        l_min=1e-6,
        band=(1e-6, 1e-4),
        method="psd",
        stderr={},
        ci95={},
        covariance=np.asarray(covariance),
        correlation=math.nan,
        groups=1,
        estimates=np.zeros((0, 2)),
        spectrum=empty,
        fit=empty,
        diagnostics=(),
        kind=tp.Areal(),
        reliability_cutoff=None,
    )


@pytest.mark.parametrize(
    "prior, message",
    [
        ({"E": fitting.Normal(2e11, 1e10)}, "prior on 'E', which is not fitted"),
        ({"D": fitting.Bounds(1.6, 1.3)}, r"prior\['D'\] bounds \[1.6, 1.3\] must satisfy"),
        ({"D": "1.4"}, r"prior\['D'\] = '1.4' must be"),
    ],
)
def test_a_bad_prior_names_the_parameter(prior, message):
    with pytest.raises(ValueError, match=message):
        resolve_prior(prior, D_AND_G)


def test_a_normal_prior_refuses_a_negative_sd():
    with pytest.raises(ValueError, match=r"Normal: sd = -0.1 must be > 0"):
        fitting.Normal(1.4, -0.1)


def test_a_topography_that_cannot_be_characterised_is_one_line(tmp_path, capsys):
    from jaxcontact.cli import main

    flat = tmp_path / "flat.txt"
    np.savetxt(flat, np.zeros((64, 64)))
    code = main(["fit", str(ROOT_DATA), "--topography", str(flat), "--size", "1e-4", "1e-4", "--out", str(tmp_path)])
    assert (code, "flat" in capsys.readouterr().err) == (2, True)


@pytest.fixture(scope="module")
def characterised_map():
    """A 128² synthesised surface (D = 1.5), characterised: its spectrum's fit is the prior's source."""
    from jaxcontact.bem import synthesised_surface
    from jaxcontact.topography import characterise

    return characterise(synthesised_surface(1.5, 1e-12, 100e-6 / 32, 100e-6, 128, 1))


def test_a_topography_prior_lives_in_its_spectrums_coordinates(characterised_map):
    prior, _ = resolve_prior(characterised_map, D_AND_G)
    assert prior.kind == tp.Areal()


def test_the_spectral_prior_linearised_at_the_estimate_is_the_characterisations_covariance(characterised_map):
    """At the estimate, ∂φᵀ Σ⁻¹ ∂φ inverted is the (D, ln G) covariance that `characterise` forms by its own
    (finite-difference) delta method: the two coordinate maps are each other's inverse."""
    prior, _ = resolve_prior(characterised_map, D_AND_G)
    np.testing.assert_allclose(
        np.linalg.inv(prior.precision(prior.first_start)), characterised_map.covariance, rtol=1e-4
    )


def test_the_spectral_prior_is_centred_on_the_estimate(characterised_map):
    prior, _ = resolve_prior(characterised_map, D_AND_G)
    residuals, _ = prior.linearised(prior.first_start)
    np.testing.assert_allclose(residuals, 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def small_map_joint_fits():
    """20 seeds: a 64² map of a D = 1.5 surface characterised (D uncertain by ±0.3, a thin curved ridge
    in (D, ln G)) as the prior of a Persson-made curve of the same D and G (10 loads, 3 % noise)."""
    from helpers import BEM_L, BEM_SETTING

    from jaxcontact.bem import synthesised_surface
    from jaxcontact.topography import characterise

    D, G, L = 1.5, 1e-12, BEM_L
    truth = make_scene(**dict(BEM_SETTING, D=D, G=G, l_min=L / 16), model="persson")
    loads = np.geomspace(1e-5, 1e-3, 10) * BEM_SETTING["E"] * L * L
    K = np.asarray(jc.solve(truth, loads).stiffness)
    results = []
    for seed in range(20):
        prior = characterise(synthesised_surface(D, G, L / 16, L, 64, seed))
        noisy = K * np.exp(0.03 * np.random.default_rng(seed).standard_normal(loads.size))
        results.append(fitting.fit(loads, noisy, truth, n_starts=4, method=fitting.LevenbergMarquardt(), prior=prior))
    return D, G, results


def test_joint_inference_with_a_small_maps_prior_covers_d(small_map_joint_fits):
    """In its spectrum's coordinates the prior keeps the bend that a Gaussian in (D, ln G) loses."""
    D, _, results = small_map_joint_fits
    assert sum(r.ci95["D"][0] <= D <= r.ci95["D"][1] for r in results) >= 17


def test_joint_inference_with_a_small_maps_prior_covers_g(small_map_joint_fits):
    _, G, results = small_map_joint_fits
    assert sum(r.ci95["G"][0] <= G <= r.ci95["G"][1] for r in results) >= 17
