"""Inverse fitting: recovery, honest intervals (coverage), multi-start agreement, flagged data."""

import json

import jax
import numpy as np
import pytest
from helpers import ROOT, TABLE1, WRONG_START, make_scene

import jaxcontact as jc
from jaxcontact import fitting
from jaxcontact.fitting._optimise import AbstractObjective
from jaxcontact.fitting._synthetic import TABLE1_F_STAR, synthetic_curve, table1_generated

TRUTH = {"D": TABLE1["D"], "G": TABLE1["G"]}
START = dict(TABLE1, D=1.55, G=1e-9)  # the scene handed to fit: wrong D and G


@pytest.fixture(scope="module")
def table1():
    return make_scene(**TABLE1)


RECOVERY_CASES = [
    # several (D, G) across the range with the default model ...
    ("xia2024", "paper", 1.25, 3e-11),
    ("xia2024", "paper", 1.4058, 2.2826e-10),
    ("xia2024", "paper", 1.6, 5e-10),
    # ... and every other model and interaction mode, each at its own (D, G)
    ("xia2024", "none", 1.6, 5e-10),
    ("xia2024", "series", 1.25, 3e-11),
    ("jzz2010", "none", 1.4058, 2.2826e-10),
]


@pytest.mark.parametrize("model, interaction, D, G", RECOVERY_CASES)
def test_noiseless_recovery(model, interaction, D, G):
    truth = make_scene(**dict(TABLE1, D=D, G=G), model=model, interaction=interaction)
    # 40 points, as in the generated Table 1 file (any length from 33 to 64 shares the compiled optimiser).
    F_star = np.geomspace(1e-10, 1e-5, 40) if model == "xia2024" else np.geomspace(1e-8, 1e-3, 40)
    loads, K = synthetic_curve(truth, F_star, noise=0.0)
    elastic = K > 0  # JZZ: K = 0 exactly while every spot is plastic (a_l < a_c); no log there
    assert elastic.sum() >= 10
    result = fitting.fit(loads[elastic], K[elastic], make_scene(**START, model=model, interaction=interaction))
    assert result.success, result.summary()
    np.testing.assert_allclose([result.values["D"], result.values["G"]], [D, G], rtol=1e-6)


def test_bfgs_and_lm_agree_on_noisy_data(table1):
    loads, K = table1_generated(table1)
    bfgs = fitting.fit(loads, K, make_scene(**START), method=fitting.BFGS())
    lm = fitting.fit(loads, K, make_scene(**START), method=fitting.LevenbergMarquardt())
    assert bfgs.success
    assert lm.success
    np.testing.assert_allclose(bfgs.values["D"], lm.values["D"], rtol=1e-7)
    np.testing.assert_allclose(bfgs.values["G"], lm.values["G"], rtol=1e-5)


def test_a_single_lm_start_converges(table1):
    """The bench's 30-point curve from one start: LM's default tolerance must sit above the
    round-off of its steps along the D–G valley (at 1e-12 it wandered for all 400 iterations)."""
    from jaxcontact.studies._bench import _data

    loads, K = _data(table1)
    result = fitting.fit(loads, K, make_scene(**dict(START, D=1.5)), method=fitting.LevenbergMarquardt(), n_starts=1)
    assert result.success, (result.iterations, result.summary())
    assert result.iterations < 50, (result.iterations, result.summary())
    assert abs(result.values["D"] - TRUTH["D"]) < 0.01


def test_generated_file_is_reproducible_and_fits_within_tolerance(table1):
    curve = fitting.load_curve(ROOT / "data" / "table1_grinding_generated.csv", table1)
    loads, K = table1_generated(table1)
    np.testing.assert_allclose(curve.loads, loads, rtol=1e-9)
    np.testing.assert_allclose(curve.stiffness, K, rtol=1e-9)
    result = fitting.fit(curve.loads, curve.stiffness, make_scene(**START))
    assert abs(result.values["D"] - TRUTH["D"]) < 0.01
    for name, value in TRUTH.items():
        lo, hi = result.ci95[name]
        assert lo < value < hi, (name, value, result.ci95[name])
    assert not result.warnings, result.warnings


def test_coverage_over_40_noise_seeds(table1):
    """The 95 % intervals must cover the truth in at least 85 % of noise realisations. (Two starts
    reach the optimum of eight on each of these curves, to 1e-7 in D; that any start reaches it is
    the next test's.)"""
    covered = {"D": 0, "G": 0}
    errors = []
    for seed in range(40):
        loads, K = synthetic_curve(table1, TABLE1_F_STAR, noise=0.05, seed=1000 + seed)
        result = fitting.fit(loads, K, make_scene(**START), n_starts=2)
        assert result.success
        errors.append(result.values["D"] - TRUTH["D"])
        for name, value in TRUTH.items():
            lo, hi = result.ci95[name]
            covered[name] += lo < value < hi
    assert covered["D"] >= 34, covered
    assert covered["G"] >= 34, covered
    assert np.max(np.abs(errors)) < 0.01


def test_starts_anywhere_in_the_bounds_reach_the_same_optimum(table1):
    loads, K = table1_generated(table1)
    results = [fitting.fit(loads, K, make_scene(**START), seed=seed, n_starts=8) for seed in (1, 2, 3)]
    corners = [[1.05, 1e-14], [1.95, 1e-14], [1.05, 1e-7], [1.95, 1e-7], [1.2, 1e-12], [1.8, 1e-8]]
    results.append(fitting.fit(loads, K, make_scene(**START), starts=corners + [[1.5, 1e-10], [1.5, 1e-13]]))
    for r in results[1:]:
        np.testing.assert_allclose(r.values["D"], results[0].values["D"], rtol=1e-7)
        np.testing.assert_allclose(r.values["G"], results[0].values["G"], rtol=1e-5)


def test_short_load_range_warns_of_a_rival_optimum(table1):
    """Above F* = 1e-9 this noise draw prefers a second (D, G): the fit must say so."""
    loads, K = synthetic_curve(table1, np.geomspace(1e-9, 1e-4, 30), noise=0.05, seed=2024)
    result = fitting.fit(loads, K, make_scene(**START), n_starts=16)
    assert any("distinct optimum" in w for w in result.warnings), result.warnings


def test_flagged_points_are_named_not_dropped_silently():
    scene = make_scene(1.5, 3e-10, 1.13e11, 0.3, 4e9, 1e-4, 1e-9)  # 1130 N breaks down (checkpoints.csv)
    loads = np.concatenate([np.geomspace(1e-10, 1e-5, 20) * 1.13e11 * 1e-4, [1130.0]])
    K = np.array(jc.solve(scene, loads).stiffness)
    K[-1] = 4e11  # a measured value where the model has none
    result = fitting.fit(loads, K, make_scene(1.45, 1e-9, 1.13e11, 0.3, 4e9, 1e-4, 1e-9), n_starts=16)
    assert list(result.flagged) == [20]
    assert np.isnan(result.residuals[20])
    assert any("1130 N (interaction_breakdown)" in w for w in result.warnings)
    np.testing.assert_allclose([result.values["D"], result.values["G"]], [1.5, 3e-10], rtol=1e-6)


def test_other_parameters_can_be_fitted():
    # Without interaction: what is tested is the plumbing of other parameters (half the compile).
    truth = make_scene(**TABLE1, interaction="none")
    loads, K = synthetic_curve(truth, np.geomspace(1e-10, 1e-5, 20), noise=0.0)
    result = fitting.fit(loads, K, make_scene(**dict(TABLE1, H=3e10), interaction="none"), params="H")
    np.testing.assert_allclose(result.values["H"], TABLE1["H"], rtol=1e-6)
    result = fitting.fit(loads, K, make_scene(**dict(TABLE1, l_min=3e-9), interaction="none"), params=("l_min",))
    np.testing.assert_allclose(result.values["l_min"], TABLE1["l_min"], rtol=1e-6)


def test_result_is_complete_and_serialisable(table1):
    loads, K = table1_generated(table1)
    result = fitting.fit(loads, K, make_scene(**START))
    assert result.params == ("D", "G")
    assert result.iterations > 0
    assert result.wall_time > 0
    c = result.correlation
    np.testing.assert_allclose(c, c.T)
    np.testing.assert_allclose(np.diag(c), 1.0)
    assert abs(c[0, 1]) < 1
    assert result.residuals.shape == loads.shape
    assert np.all(np.isfinite(result.residuals))
    rms = np.sqrt(np.mean(result.residuals**2))
    assert 0.03 < rms < 0.07  # 5 % noise
    # The curve is padded to 64 points with copies of its first point: they must weigh nothing.
    np.testing.assert_allclose(result.loss, 0.5 * np.mean(result.residuals**2), rtol=1e-12)
    reversed_ = fitting.fit(loads[::-1], K[::-1], make_scene(**START))
    # To the optimiser's precision: BFGS stops on the loss's relative progress (1e-15), which fixes
    # a point along the ill-conditioned D–G valley to about √1e-15 ≈ 3e-8 (G's relative
    # uncertainty here is ~1e-1). With scipy 1.12 the two land 3e-8 apart in G, with 1.17 closer.
    np.testing.assert_allclose(
        [reversed_.values["D"], reversed_.values["G"]], [result.values["D"], result.values["G"]], rtol=1e-7
    )
    json.dumps(result.to_dict())
    assert isinstance(result.scene, jc.Scene)
    assert float(result.scene.surface.D) == result.values["D"]


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(params="D,Q"), r"'Q' cannot be fitted"),
        (dict(params=("D", "D")), r"names a parameter twice"),
        (dict(params=fitting.LevenbergMarquardt()), r"params = LevenbergMarquardt\(\) must be parameter names"),
    ],
)
def test_bad_arguments(table1, kw, message):
    with pytest.raises(ValueError, match=message):
        fitting.fit([1.0, 2.0, 3.0], [1e8, 2e8, 3e8], table1, **kw)


@pytest.mark.parametrize(
    "text, message",
    [
        ("load,K\n1,2\n", "lacks the columns 'load_N,stiffness_N_per_m'"),
        ("load_N,stiffness_N_per_m\n1,2\n3,x\n5,6\n", "line 3, column stiffness_N_per_m: 'x' is not a number"),
        ("load_N,stiffness_N_per_m\n1,2\n-3,4\n5,6\n", "line 3, column load_N: -3 must be a positive finite number"),
        # The file's own line numbers: comments and blank lines count.
        ("# a\n# b\nload_N,stiffness_N_per_m\n\n1,2\n3,4\n5,6\n7,8\nnan,9\n", "line 9, column load_N: nan must be"),
        ("load_N,stiffness_N_per_m\n1,2\n3,4,5\n5,6\n", "line 3 has 3 fields, the header has 2"),
        ("load_N,stiffness_N_per_m\n1,2\n", "1 data rows; a fit needs at least 3"),
        ("# only a comment\n", "no header row"),
    ],
)
def test_csv_errors(table1, text, message):
    with pytest.raises(fitting.DataError, match=message):
        fitting.parse_curve(text, table1, "c.csv")


def test_a_byte_order_mark_is_accepted(table1):
    curve = fitting.parse_curve("\ufeffload_N,stiffness_N_per_m\n1,2\n3,4\n5,6\n", table1, "excel.csv")
    np.testing.assert_array_equal(curve.loads, [1.0, 3.0, 5.0])


def test_a_directory_is_not_called_missing(table1, tmp_path):
    with pytest.raises(fitting.DataError, match="is a directory"):
        fitting.load_curve(tmp_path, table1)


def test_dimensionless_columns(table1):
    curve = fitting.parse_curve("F_star,K_star\n1e-6,1.04576\n2e-6,2\n3e-6,3\n", table1)
    np.testing.assert_allclose(curve.loads[0], 22.0)
    np.testing.assert_allclose(curve.stiffness[0], 1.04576 * 220e9 * 1e-2)


def test_cli_fit_exits_1_when_the_model_does_not_describe_the_data(tmp_path, capsys):
    """Exit codes (docs/cli.md): 1 is a fit that ran and wrote its files but is not usable."""
    from jaxcontact.cli import main

    data = tmp_path / "kN.csv"
    curve = np.loadtxt(ROOT / "data" / "table1_grinding_generated.csv", delimiter=",", skiprows=6)
    np.savetxt(
        data,
        np.column_stack([curve[:, 0] / 1000.0, curve[:, 1]]),
        delimiter=",",
        header="load_N,stiffness_N_per_m",
        comments="",
    )
    assert main(["fit", str(data), "--out", str(tmp_path), "--no-progress"]) == 1
    out = capsys.readouterr().out
    assert "95% CI not reported: the model does not describe the data" in out
    assert (tmp_path / "fit.png").is_file()


def test_cli_fit(tmp_path, capsys):
    from jaxcontact.cli import main

    data = str(ROOT / "data" / "table1_grinding_generated.csv")
    assert main(["fit", data, "--format", "json", "--out", str(tmp_path), "--method", "lm"]) == 0
    payload = json.loads(capsys.readouterr().out)
    lo, hi = payload["ci95"]["D"]
    assert lo < TRUTH["D"] < hi
    assert payload["success"]
    assert (tmp_path / "fit.png").stat().st_size > 10_000
    assert jax.config.jax_enable_x64


def test_identical_points_are_refused(table1):
    with pytest.raises(jc.InputError, match="1 distinct values among 3 points cannot determine 2 parameters"):
        fitting.fit([5.0, 5.0, 5.0], [1e8, 1e8, 1e8], table1)


@pytest.fixture(scope="module")
def wrong_unit_fit(table1):
    """The generated curve with its loads in kN but read as N."""
    curve = fitting.load_curve(ROOT / "data" / "table1_grinding_generated.csv", table1)
    return fitting.fit(curve.loads / 1000.0, curve.stiffness, make_scene(**START))


def test_loads_in_the_wrong_unit_are_called_a_misfit(wrong_unit_fit):
    """The fit converges somewhere, and says that its misfit is far beyond the data's own scatter."""
    misfits = [w for w in wrong_unit_fit.warnings if "the model does not describe these data" in w]
    assert len(misfits) == 1, wrong_unit_fit.warnings


def test_a_misfit_reports_no_intervals(wrong_unit_fit):
    """Issue 35.11: intervals of a model that does not describe the data are not reported."""
    assert not wrong_unit_fit.describes_data
    assert all(np.isnan(wrong_unit_fit.ci95[name]).all() for name in wrong_unit_fit.params)


def test_a_misfit_says_why_its_intervals_are_missing(wrong_unit_fit):
    lines = wrong_unit_fit.summary().splitlines()[1:3]
    assert all(line.endswith("95% CI not reported: the model does not describe the data") for line in lines), lines


def test_a_wide_interval_of_D_stays_in_its_domain(table1):
    """Three points over a decade with 20 % noise: D's interval would reach past (1, 2) unclipped."""
    loads, K = synthetic_curve(table1, TABLE1_F_STAR[[0, 20, 39]], noise=0.2, seed=3)
    result = fitting.fit(loads, K, make_scene(**START), n_starts=4)
    lo, hi = result.ci95["D"]
    assert 1.0 <= lo < hi <= 2.0, result.summary()


@pytest.mark.parametrize("starts", [0, -3])
def test_a_number_of_starts_below_one_is_refused(table1, starts):
    with pytest.raises(jc.InputError, match=rf"n_starts = {starts} must be an integer in \[1, 1024\]"):
        fitting.fit([1.0, 2.0, 3.0], [1e8, 2e8, 3e8], table1, n_starts=starts)


def test_zero_stiffness_does_not_beat_a_finite_misfit(table1):
    """A flat curve no parameters fit well: the fit must not escape to where every spot is plastic
    and K = 0 (which ln 0 would make a flagged point with a capped penalty)."""
    loads = TABLE1_F_STAR[:30] * TABLE1["E"] * TABLE1["area"]
    result = fitting.fit(loads, np.full(loads.size, 1e9), make_scene(**START))
    sol = jc.solve(result.scene, loads)
    assert int(np.sum(np.asarray(sol.fully_plastic))) == 0, result.summary()


def test_no_rival_optimum_is_announced_for_the_best_one_itself(table1):
    """A noiseless curve plus three loads beyond full contact: the starts meet at the truth; no
    warning may name that same optimum as a distinct rival."""
    loads, K = synthetic_curve(table1, TABLE1_F_STAR, noise=0.0)
    loads = np.concatenate([loads, [1e9, 2e9, 3e9]])
    K = np.concatenate([K, [1e11, 1e11, 1e11]])
    result = fitting.fit(loads, K, make_scene(**START))
    assert abs(result.values["D"] - TRUTH["D"]) < 1e-6
    assert not [w for w in result.warnings if "distinct optimum" in w], result.warnings


def test_a_curve_made_by_another_model_is_called_a_misfit(table1):
    """A JZZ curve (5 % noise) fitted with xia2024: whatever the optimum, the fit says that the model
    does not describe the data, instead of reporting a G 230x off as a success without a word."""
    loads, K = synthetic_curve(make_scene(**TABLE1, model="jzz2010"), TABLE1_F_STAR, noise=0.05, seed=7)
    result = fitting.fit(loads, K, make_scene(**START))
    misfits = [w for w in result.warnings if "the model does not describe these data" in w]
    assert len(misfits) == 1, result.summary()


def test_the_command_lines_lbfgs_is_bfgs():
    """The name of earlier versions' optimiser, kept for scripts of the command line."""
    assert fitting.METHODS["lbfgs"]() == fitting.BFGS()


def test_the_optimisers_jacobian_matches_finite_differences(table1):
    """`∂r/∂u` as the optimisers see it: the model's forward-mode Jacobian in statistical
    coordinates times the reparameterisation's slope, against central differences in `u`."""
    from jaxcontact.core import prepare
    from jaxcontact.fitting._observed import observations
    from jaxcontact.fitting._optimise import Objective

    loads, K = table1_generated(table1)
    params = fitting.resolve(("D", "G"))
    scene, _ = prepare(make_scene(**START), loads)
    data = observations(loads, K, None, None, None, np.float64, 64)[0]
    objective = Objective(scene, params, data, loads.size)
    u = np.array([-0.4, 0.3])
    r, J = objective(u)
    assert r.shape == (loads.size,)
    h = 1e-6
    for i in range(2):
        step = np.eye(2)[i] * h
        fd = (objective(u + step)[0] - objective(u - step)[0]) / (2 * h)
        np.testing.assert_allclose(J[:, i], fd, rtol=1e-5, atol=1e-7 * np.max(np.abs(fd)))


@pytest.mark.parametrize("name", ["D", "G"])
def test_the_reparameterisation_slope_matches_finite_differences(name):
    p = fitting.PARAMETERS[name]
    for u in (-3.0, 0.2, 4.0):
        stat, slope = p.stat_and_slope_from_u(u)
        fd = (p.stat_from_u(u + 1e-6) - p.stat_from_u(u - 1e-6)) / 2e-6
        assert slope == pytest.approx(fd, rel=1e-7)
        assert p.u_from_stat(stat) == pytest.approx(u, rel=1e-9)


def test_model_stiffness_is_the_solves_stiffness(table1):
    """The fit's program evaluated against ln K = 0 gives K itself: equal to `jc.solve`'s, over
    more loads than one padded block (70 = 64 + 6), with the out-of-range load flagged as NaN."""
    loads = np.concatenate([np.geomspace(1e-9, 1e-4, 69), [10.0]]) * TABLE1["E"] * TABLE1["area"]
    K = fitting.model_stiffness(table1, ("D", "G"), loads)
    expected = np.asarray(jc.solve(table1, loads).stiffness)
    np.testing.assert_allclose(K[:69], expected[:69], rtol=1e-12)
    assert np.isnan(K[69]) and np.isnan(expected[69])


class _Linear(AbstractObjective):
    """A linear least-squares objective `r = J u − y` (the optimisers' interface), settled at `settle`."""

    def __init__(self, settle):
        rng = np.random.default_rng(3)
        self.J = rng.normal(size=(12, 2))
        self.y = self.J @ np.array([0.3, -0.2]) + 0.05 * rng.normal(size=12)
        self.params, self.n_points, self.settle = ("a", "b"), 12, settle
        self.best = np.linalg.lstsq(self.J, self.y, rcond=None)[0]
        self.s2 = float(np.sum((self.J @ self.best - self.y) ** 2)) / 10

    def residuals(self, u):
        return self.J @ np.asarray(u) - self.y, self.J

    def away(self, chi2):
        """A point whose χ² exceeds the optimum's by `chi2` (in units of the residuals' scale)."""
        direction = np.array([1.0, 0.5])
        excess = float(np.sum((self.J @ direction) ** 2)) / self.s2
        return self.best + direction * np.sqrt(chi2 / excess)


@pytest.mark.parametrize("chi2, expected", [(0.02, False), (0.005, True)])
def test_a_fit_is_settled_within_the_chi2_decrement_it_is_given(chi2, expected):
    """χ² 0.02 above the optimum (0.14 standard errors) is not settled at 1e-2; 0.005 (0.07) is."""
    from jaxcontact.fitting._optimise import settled

    objective = _Linear(1e-2)
    assert settled(objective, objective.away(chi2)) is expected


def test_a_model_smooth_to_round_off_is_never_settled_early():
    from jaxcontact.fitting._optimise import settled

    objective = _Linear(0.0)
    assert not settled(objective, objective.away(1e-12))


def test_bfgs_ends_at_the_first_settled_iterate():
    """With a decrement every point passes (1e6), BFGS from far off ends after one iteration, where
    without one (0) it needs more."""
    from jaxcontact.fitting._optimise import run_bfgs

    start = _Linear(0.0).away(1e4)
    assert run_bfgs(_Linear(0.0), start, 400, 1e-15).iterations > 1
    assert run_bfgs(_Linear(1e6), start, 400, 1e-15).iterations == 1


def test_a_settled_fit_is_converged():
    from jaxcontact.fitting._optimise import run_bfgs

    objective = _Linear(1e-2)
    assert run_bfgs(objective, objective.away(1e4), 400, 1e-15).converged


@pytest.fixture(scope="module")
def beyond_the_bound(table1):
    """K ∝ F^1.5 over five decades of load: steeper than any D < 2 gives; the optimum is on D's bound."""
    loads = np.geomspace(1e-9, 1e-4, 12) * TABLE1["E"] * TABLE1["area"]
    K = 1e9 * (loads / loads[0]) ** 1.5 * np.exp(0.01 * np.random.default_rng(0).normal(size=12))
    return fitting.fit(loads, K, make_scene(**WRONG_START))


def test_a_fit_on_a_search_bound_is_not_a_success(beyond_the_bound):
    assert not beyond_the_bound.success


def test_a_fit_on_a_search_bound_names_the_bound(beyond_the_bound):
    assert any("D = 2 is on its upper search bound 2" in w for w in beyond_the_bound.warnings)


@pytest.fixture(scope="module")
def random_stiffness(table1):
    """Twelve stiffness values drawn at random over three decades: a curve of pure noise."""
    loads = np.geomspace(1e-9, 1e-4, 12) * TABLE1["E"] * TABLE1["area"]
    return fitting.fit(loads, 10 ** np.random.default_rng(0).uniform(8, 11, 12), make_scene(**WRONG_START))


def test_a_fit_to_pure_noise_is_not_a_success(random_stiffness):
    assert not random_stiffness.success


def test_a_fit_to_pure_noise_says_it_measured_nothing(random_stiffness):
    assert any("determines no combination" in w for w in random_stiffness.warnings)


def _evaluated_linear():
    """`_Linear` as the fit sees D and G, with its optimum evaluated (remembered as the lowest point)."""
    from jaxcontact.fitting import resolve

    objective = _Linear(0.0)
    objective.params = resolve(("D", "G"))
    objective(objective.best)
    return objective


def test_a_fit_that_ends_above_a_point_it_evaluated_has_stalled():
    from jaxcontact.fitting._optimise import stalled

    objective = _evaluated_linear()
    assert "stalled" in stalled(objective, objective.loss(objective.away(4.0)), 2)


def test_a_fit_within_one_chi2_of_the_lowest_point_it_evaluated_has_not_stalled():
    from jaxcontact.fitting._optimise import stalled

    objective = _evaluated_linear()
    assert stalled(objective, objective.loss(objective.away(0.5)), 2) is None


def test_a_rivals_delta_chi2_is_measured_in_the_loss_the_starts_were_ranked_by():
    """Two starts 0.2 apart in D: the rival's Δχ² is 2N (loss_rival − loss_best) / s², never negative."""
    from jaxcontact.fitting import resolve
    from jaxcontact.fitting._statistics import rival_optima

    params = resolve(("D", "G"))
    u_all = np.array([[p.u_from_stat(s) for p, s in zip(params, stat)] for stat in ([1.4, -23.0], [1.6, -23.0])])
    losses = np.array([0.010, 0.0101])
    warnings = rival_optima(params, u_all, 0, np.diag([1e-4, 1e-2]), losses, 30, s2=0.001)
    assert "(Δχ² = 6.00)" in warnings[0]


def test_log_residuals_are_the_models_log_stiffness_less_the_data():
    scene = make_scene(**{**TABLE1, "interaction": "none"})
    params, loads = fitting.resolve(("D", "G")), np.array([10.0, 100.0, 1000.0])
    data = np.log(np.array([1e9, 5e9, 2e10]))
    stat = np.array([p.to_stat(float(p.get(scene))) for p in params])
    r, ok = fitting.log_residuals(stat, scene, params, loads, data)
    expected = np.log(np.asarray(jc.solve(scene, loads).stiffness)) - data
    np.testing.assert_allclose(np.asarray(r), expected, rtol=1e-12)
