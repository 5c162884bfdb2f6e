"""The stiffness a joint has in service (docs/in-service.md): the initial unloading tangent about a
state reached by loading, and Mindlin's tangential stiffness in full stick, against closed forms,
scipy quadrature over the spot-size distribution and central differences."""

import json
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_scene, refused_type
from scipy import integrate

import jaxcontact as jc
from jaxcontact.numerics import x64

LOADS = np.geomspace(1e-10, 1e-4, 4) * TABLE1["E"] * TABLE1["area"]
# The D = 1.5 surface at H = 3 GPa: every spot fully plastic at every load (K = 0 on loading).
PLASTIC = dict(TABLE1, D=1.5, G=1e-12, l_min=1e-6, H=3e9, area=1e-4)
PLASTIC_LOADS = np.geomspace(1e-8, 1e-4, 3) * PLASTIC["E"] * PLASTIC["area"]


def _sneddon_sum(scene, solution):
    """Σ 2E √(a/π) over the spots of the Majumdar–Bhushan distribution n(a) = (D/2) a_l^(D/2) a^-(D+2)/2
    on (l_min², a_l], by scipy's quadrature, per load."""
    D, E, a_min = float(scene.surface.D), float(scene.material.E), float(scene.surface.l_min) ** 2

    def total(a_l):
        # In t = ln a: a smooth integrand over the many decades from l_min² to a_l.
        def density(t):
            a = math.exp(t)
            return 2 * E * math.sqrt(a / math.pi) * (D / 2) * a_l ** (D / 2) * a ** (-(D + 2) / 2) * a

        return integrate.quad(density, math.log(a_min), math.log(a_l), epsrel=1e-12, limit=200)[0]

    return np.array([total(a_l) for a_l in np.asarray(solution.a_l)])


@pytest.mark.parametrize("model", ["gw", "persson"])
def test_an_elastic_model_unloads_as_it_loads(model):
    scene = make_scene(**TABLE1, model=model)
    np.testing.assert_allclose(
        jc.dynamic_stiffness(scene, LOADS).stiffness, jc.solve(scene, LOADS).stiffness, rtol=1e-14
    )


@pytest.mark.parametrize(
    "options",
    [dict(model="persson"), dict(model="jzz2010")],
    ids=["persson", "jzz2010"],
)
def test_tangential_over_unloading_stiffness_is_mindlins_ratio(options):
    scene = make_scene(**dict(TABLE1, nu=0.25), **options)
    ratio = jc.tangential_stiffness(scene, LOADS).stiffness / jc.dynamic_stiffness(scene, LOADS).stiffness
    np.testing.assert_allclose(ratio, 2 * (1 - 0.25) / (2 - 0.25), rtol=1e-14)


def test_where_every_spot_is_elastic_the_seed_model_unloads_as_it_loads():
    scene = make_scene(**TABLE1, interaction="none")
    loads = np.geomspace(1e-14, 1e-12, 3) * TABLE1["E"] * TABLE1["area"]
    loading = jc.solve(scene, loads)
    assert np.all(np.asarray(loading.load_share)[:, 1:] == 0.0)  # no spot beyond the elastic regime
    np.testing.assert_allclose(jc.dynamic_stiffness(scene, loads).stiffness, loading.stiffness, rtol=1e-13)


@pytest.fixture(scope="module")
def plastic_scene():
    return make_scene(**PLASTIC, interaction="none", spot_stiffness="sneddon")


def test_the_fully_plastic_seed_model_has_no_loading_stiffness(plastic_scene):
    np.testing.assert_array_equal(jc.solve(plastic_scene, PLASTIC_LOADS).stiffness, 0.0)


def test_fully_plastic_spots_unload_with_sneddons_stiffness(plastic_scene):
    dynamic = jc.dynamic_stiffness(plastic_scene, PLASTIC_LOADS)
    np.testing.assert_allclose(dynamic.stiffness, _sneddon_sum(plastic_scene, dynamic), rtol=1e-9)


def test_jzz2010s_plastic_spots_unload_with_sneddons_stiffness():
    scene = make_scene(**TABLE1, model="jzz2010")
    dynamic = jc.dynamic_stiffness(scene, LOADS)
    np.testing.assert_allclose(dynamic.stiffness, _sneddon_sum(scene, dynamic), rtol=1e-9)


def test_the_papers_spot_law_unloads_with_its_family_factor_over_every_spot():
    """`FamilyDerivative()`: the elastic regime's law, (2π/3)(3-D)/(2-D) times Sneddon's, for every spot."""
    scene = make_scene(**TABLE1, interaction="none")
    dynamic = jc.dynamic_stiffness(scene, LOADS)
    D = TABLE1["D"]
    factor = (2 * math.pi / 3) * (3 - D) / (2 - D)
    np.testing.assert_allclose(dynamic.stiffness, factor * _sneddon_sum(scene, dynamic), rtol=1e-9)


@pytest.fixture(scope="module")
def tangential_and_gradient():
    """K_t at 22 N as a function of (D, ν) and its gradient: one program for both."""
    scene = make_scene(**TABLE1, interaction="series")

    @jax.jit
    @jax.value_and_grad
    def K_t(theta):
        moved = eqx.tree_at(lambda s: (s.surface.D, s.material.nu), scene, (theta[0], theta[1]))
        return jc.tangential_stiffness(moved, 22.0).stiffness

    return K_t, jnp.array([TABLE1["D"], TABLE1["nu"]])


@pytest.mark.parametrize("i", [0, 1], ids=["D", "nu"])
def test_the_tangential_stiffness_gradient_matches_central_differences(tangential_and_gradient, i):
    K_t, theta = tangential_and_gradient
    step = jnp.zeros(2).at[i].set(1e-6 * theta[i])
    central = (K_t(theta + step)[0] - K_t(theta - step)[0]) / (2 * step[i])
    np.testing.assert_allclose(K_t(theta)[1][i], central, rtol=1e-6)


def test_float32_agrees_with_float64(plastic_scene):
    reference = jc.tangential_stiffness(plastic_scene, PLASTIC_LOADS).stiffness
    with x64(False):
        single = jc.tangential_stiffness(plastic_scene, PLASTIC_LOADS.astype(np.float32)).stiffness
        assert single.dtype == jnp.float32
    np.testing.assert_allclose(single, reference, rtol=1e-4)


def test_a_stiffness_given_by_name_is_refused_with_its_object():
    with refused_type("stiffness", r"stiffness = 'unloading': give the object, jaxcontact.Unloading\(\)"):
        jc.Outputs(stiffness="unloading")


PLASTIC_SCENE_FILE = """title = "fully plastic"
[surface]
D = 1.5
G = 1e-12
l_min = 1e-6
[material]
E = {E}
nu = {nu}
H = 3e9
[joint]
area = 1e-4
[effects]
interaction = "none"
spot_stiffness = "sneddon"
stiffness = "{stiffness}"
[loads]
values = {loads}
"""


def _scene_file(tmp_path, stiffness):
    path = tmp_path / "plastic.toml"
    loads = "[" + ", ".join(f"{x:.17g}" for x in PLASTIC_LOADS) + "]"
    path.write_text(PLASTIC_SCENE_FILE.format(E=PLASTIC["E"], nu=PLASTIC["nu"], stiffness=stiffness, loads=loads))
    return path


def test_run_solves_the_stiffness_its_option_names(plastic_scene, tmp_path, capsys):
    from jaxcontact.cli import main

    argv = ["run", str(_scene_file(tmp_path, "loading")), "--stiffness", "unloading", "--out", str(tmp_path)]
    assert main([*argv, "--format", "json"]) == 0
    K = [row["K_N_per_m"] for row in json.loads(capsys.readouterr().out)["rows"]]
    np.testing.assert_allclose(K, jc.dynamic_stiffness(plastic_scene, PLASTIC_LOADS).stiffness, rtol=1e-12)


def test_a_stiffness_the_scene_file_does_not_know_is_refused_by_name(tmp_path, capsys):
    from jaxcontact.cli import main

    assert main(["run", str(_scene_file(tmp_path, "dynamic")), "--out", str(tmp_path)]) == 2
    assert "stiffness = 'dynamic' must be one of 'loading', 'unloading', 'tangential'" in capsys.readouterr().err
