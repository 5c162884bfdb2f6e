"""The boundary-element model (`jc.BEM`) through `jc.solve`: the reference's surfaces and K, the
model contract on a surface its grid resolves, derivatives in D, G and l_min, fitting."""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING, make_scene

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.numerics import x64

pytest.importorskip("ContactMechanics")

E = BEM_SETTING["E"]
UNIT = E * L * L
LOADS = np.array([1e-4, 3e-4]) * UNIT
SMALL = dict(BEM_SETTING, l_min=L / 12)  # 5.3 grid spacings on 64²


def small_scene(**options):
    return make_scene(**SMALL, model=jc.BEM(**{"grid": 64, "realisations": 2, **options}))


@pytest.fixture(scope="module")
def scene():
    return small_scene()


def test_the_sharp_cutoff_gives_the_references_surfaces_and_stiffness():
    """Surface by surface the ContactMechanics reference (`reference_curves`) and the JAX model agree,
    the model's secant taken over the reference's step."""
    setting = dict(BEM_SETTING, l_min=L / 32)
    step = bem.BEMSettings().relative_step
    model = make_scene(**setting, model=jc.BEM(grid=128, realisations=2, rolloff=0.0, relative_step=step))
    mine = jc.solve(model, LOADS)
    reference = bem.reference_curves(model, LOADS, grid=128, realisations=2, convergence=False)
    np.testing.assert_allclose(np.asarray(mine.stiffness), reference.mean, rtol=1e-5)


def test_the_name_is_registered():
    assert isinstance(make_scene(**SMALL, model="bem").model, jc.BEM)


def test_jit_and_vmap_over_loads_give_the_eager_solve(scene):
    eager = np.asarray(jc.solve(scene, LOADS).stiffness)
    jitted = np.asarray(jax.jit(jc.solve)(scene, jnp.asarray(LOADS)).stiffness)
    mapped = np.asarray(jax.vmap(lambda F: jc.solve(scene, F).stiffness)(jnp.asarray(LOADS)))
    np.testing.assert_allclose(jitted, eager, rtol=1e-10)
    # Mapped, each load starts cold; in one call they are a warm-started sweep: equal to the tolerance.
    np.testing.assert_allclose(mapped, eager, rtol=1e-8)


def _log_stiffness(scene, theta, loads=jnp.asarray(LOADS)):
    D, log_G, log_l_min = theta
    moved = eqx.tree_at(
        lambda s: (s.surface.D, s.surface.G, s.surface.l_min), scene, (D, jnp.exp(log_G), jnp.exp(log_l_min))
    )
    sol = jc.solve(moved, loads)
    return jnp.sum(jnp.where(sol.ok, jnp.log(jnp.where(sol.ok, sol.stiffness, 1.0)), 0.0))


@pytest.fixture(scope="module")
def gradient(scene):
    theta = jnp.array([SMALL["D"], math.log(SMALL["G"]), math.log(SMALL["l_min"])])
    f = jax.jit(lambda t: _log_stiffness(scene, t))
    return f, theta, jax.grad(lambda t: _log_stiffness(scene, t))(theta)


@pytest.mark.parametrize("index, rtol", [(0, 1e-4), (1, 1e-4), (2, 1e-3)], ids=["D", "G", "l_min"])
def test_the_gradient_matches_central_differences(gradient, index, rtol):
    """Through the synthesis (a cutoff two modes wide), the solve's implicit derivative and the secant.
    Steps of 1e-6: the secant has kinks where a grid point enters contact, a few 1e-5 apart in D; the
    l_min derivative is a small number whose differences carry ~1e-4 relative noise."""
    f, theta, g = gradient
    e = jnp.zeros(3).at[index].set(1e-6)
    np.testing.assert_allclose(float(g[index]), float((f(theta + e) - f(theta - e)) / 2e-6), rtol=rtol)


def test_float32_agrees_with_float64(scene):
    double = np.asarray(jc.solve(scene, LOADS).stiffness)
    with x64(False):
        single = jc.solve(small_scene(), LOADS.astype(np.float32))
        assert single.stiffness.dtype == jnp.float32
        np.testing.assert_allclose(np.asarray(single.stiffness), double, rtol=1e-3)


def test_a_bad_load_is_flagged_and_leaves_the_others_and_their_gradient(scene):
    loads = jnp.asarray([LOADS[0], jnp.nan, LOADS[1]])  # traced: a status, not an error
    sol = jax.jit(jc.solve)(scene, loads)
    np.testing.assert_array_equal(sol.status, [0, jc.Status.INVALID_LOAD, 0])
    alone = np.asarray(jc.solve(scene, LOADS).stiffness)
    # The stand-in for the bad load sits in the warm-started sweep: equal to the solve's tolerance.
    np.testing.assert_allclose(np.asarray(sol.stiffness)[[0, 2]], alone, rtol=1e-8)
    theta = jnp.array([SMALL["D"], math.log(SMALL["G"]), math.log(SMALL["l_min"])])
    gradient = jax.jit(jax.grad(lambda t, F: _log_stiffness(scene, t, F)))(theta, loads)
    assert np.all(np.isfinite(np.asarray(gradient)))


def test_a_load_past_full_contact_leaves_the_others_gradient_finite(scene):
    """The closed interface's singular system must not leak into D, G, l_min's derivatives."""
    loads = jnp.asarray([LOADS[0], 1e3 * UNIT, LOADS[1]])
    theta = jnp.array([SMALL["D"], math.log(SMALL["G"]), math.log(SMALL["l_min"])])
    gradient = jax.jit(jax.grad(lambda t, F: _log_stiffness(scene, t, F)))(theta, loads)
    assert np.all(np.isfinite(np.asarray(gradient)))


def test_a_grid_too_coarse_for_l_min_is_flagged(scene):
    """l_min is a traced leaf: the module's compiled model flags it (2 grid spacings on 64²)."""
    coarse = eqx.tree_at(lambda s: s.surface.l_min, scene, jnp.asarray(L / 32))
    np.testing.assert_array_equal(jc.solve(coarse, LOADS).status, [jc.Status.INVALID_PARAMETERS] * 2)


def test_plasticity_lowers_the_stiffness(scene):
    elastic = np.asarray(jc.solve(scene, LOADS).stiffness)
    plastic = np.asarray(jc.solve(small_scene(plastic=True), LOADS).stiffness)
    assert np.all(plastic < elastic)


# The study's surface is elastic by a hardness far below any metal's (`studies._plasticity.elastic`).
@pytest.mark.filterwarnings("ignore::jaxcontact.numerics._validate.PlausibilityWarning")
def test_a_fit_to_its_own_curve_recovers_D_and_G():
    """Noiseless, the fits study's surface of seed 0 (one realisation on 64², 8 loads; its compiled
    programs are the study's): the model fitted to its own curve (as users call the fit) returns its
    D and G."""
    from jaxcontact import fitting
    from jaxcontact.studies._bem_fits import study_truth

    truth, loads = study_truth(make_scene(**BEM_SETTING), 1.5)
    truth = truth.with_model(jc.BEM(grid=64, realisations=1, seed=0))
    stiffness = np.asarray(jc.solve(truth, loads).stiffness)
    start = eqx.tree_at(lambda s: (s.surface.D, s.surface.G), truth, (1.45, 2e-12))
    result = fitting.fit(loads, stiffness, start, params=("D", "G"), n_starts=1)
    np.testing.assert_allclose([result.values["D"], result.values["G"]], [1.5, BEM_SETTING["G"]], rtol=1e-3)


@pytest.fixture(scope="module")
def plasticity():
    from jaxcontact.studies._plasticity import plasticity_rows

    rows = plasticity_rows(
        make_scene(**SMALL), hardnesses=(1e11, 3e8), Ds=(1.5,), fractions=(0.03,), grid=64, realisations=1
    )
    return {row["H_Pa"]: row for row in rows}


def test_a_cap_above_every_pressure_leaves_the_bem_elastic(plasticity):
    assert abs(plasticity[1e11]["bem_change"]) < 1e-8


def test_the_capped_bem_softens(plasticity):
    """The finding of docs/validation.md: at the same load, plastic points add no stiffness."""
    assert plasticity[3e8]["bem_change"] < -0.005


def test_the_seed_models_elastic_reference_has_every_spot_elastic():
    """At `ELASTIC_HARDNESS` a_c lies above every spot (D = 1.7, l_min = L/128, 12 % contact)."""
    from jaxcontact.studies._compare import loads_for_fractions
    from jaxcontact.studies._plasticity import elastic

    with pytest.warns(jc.PlausibilityWarning):
        scene = elastic(make_scene(**dict(BEM_SETTING, D=1.7, l_min=L / 128))).with_model("xia2024", interaction="none")
        loads = loads_for_fractions(scene, (0.12,))
    sol = jc.solve(scene, loads, outputs=jc.Outputs(regime_shares=True))
    np.testing.assert_array_equal(np.asarray(sol.load_share)[0], [1.0, 0.0, 0.0, 0.0])


def test_the_studys_surface_map_is_the_surface_the_model_solves():
    """`studies._bem_fits.surface_map`, the map the joint-inference study characterises, solved by
    `bem.solve` gives the BEM model's own K (one realisation, tangent stiffness)."""
    from jaxcontact.studies._bem_fits import surface_map

    model = jc.BEM(grid=64, realisations=1, seed=3, relative_step=0.0)
    scene = make_scene(**SMALL, model=model)
    heights = surface_map(scene, model).heights()
    direct = bem.solve(jnp.asarray(heights), L, E, jnp.asarray(LOADS))
    np.testing.assert_allclose(np.asarray(jc.solve(scene, LOADS).stiffness), np.asarray(direct.stiffness), rtol=1e-6)


@pytest.fixture(scope="module")
def scale_row():
    """The scale study's row at D = 1.5, L/l_min = 16 (64², 2 realisations), and its scene."""
    from jaxcontact.studies._scale import scale_rows

    scene = make_scene(**BEM_SETTING)
    return scale_rows(scene, Ds=(1.5,), divisions=(16,), realisations=2)[0], scene


def test_the_scale_studys_bem_is_the_bem_models_mean_over_its_realisations(scale_row):
    row, scene = scale_row
    at = eqx.tree_at(lambda s: s.surface.l_min, scene, jnp.asarray(L / 16))
    # The study measures the models against the reference's secant.
    model = jc.BEM(grid=64, realisations=2, rolloff=0.0, relative_step=bem.BEMSettings().relative_step)
    K = float(jc.solve(at.with_model(model), jnp.asarray([row["F_N"]])).stiffness[0])
    np.testing.assert_allclose(row["K_bem_N_per_m"], K, rtol=1e-6)


def test_the_scale_studys_band_holds_the_ratio_to_the_mean(scale_row):
    row, _ = scale_row
    assert row["ratio_persson_low"] < row["ratio_persson"] < row["ratio_persson_high"]


def _slope_ratios(scene, loads=jnp.asarray(LOADS), half_width=0.01, points=5):
    """The local d ln K/dD at `points` values of D across D ± `half_width`, over the mean slope there."""

    def log_K(D):
        return jnp.log(jc.solve(eqx.tree_at(lambda s: s.surface.D, scene, D), loads).stiffness)

    Ds = SMALL["D"] + np.linspace(-half_width, half_width, points)
    slope = jax.jit(jax.jacfwd(log_K))
    local = np.array([slope(jnp.asarray(D)) for D in Ds])
    mean = (np.asarray(log_K(Ds[-1])) - np.asarray(log_K(Ds[0]))) / (2 * half_width)
    return local / mean


def test_the_default_secant_is_smooth_enough_for_a_gradient_to_fit(scene):
    """Its local slope in D stays within 20 % of the mean slope over D ± 0.01 (the reference's secant,
    ε = 0.02, swings 0.53–1.59× here)."""
    ratios = _slope_ratios(scene)
    assert np.all(np.abs(ratios - 1) < 0.2), ratios


@pytest.fixture(scope="module")
def study_fits():
    """The fits study (`compare --fits`) at D = 1.5 on its first seed, the BEM model alone (each seed
    is a program of its own: coverage over 20 seeds at each of D = 1.3, 1.5, 1.7 is the study's,
    docs/fitting.md)."""
    from jaxcontact.studies._bem_fits import bem_fit_rows

    return bem_fit_rows(make_scene(**BEM_SETTING), Ds=(1.5,), seeds=range(1), models=("bem",))


@pytest.mark.parametrize("prior", [False, True], ids=["curve alone", "with the map's prior"])
def test_the_bem_models_interval_holds_the_true_d(study_fits, prior):
    (row,) = [r for r in study_fits if r["prior"] == prior]
    assert row["D_low"] <= 1.5 <= row["D_high"], (row["D_low"], row["D_high"])
