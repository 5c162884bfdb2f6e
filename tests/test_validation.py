"""Bad configuration raises ValueError naming the parameter, its value and its valid range."""

import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_scene, refused_type

import jaxcontact as jc


@pytest.mark.parametrize(
    "field, value, pattern",
    [
        ("D", 1.0, r"D .*= 1 .*\(1, 2\)"),
        ("D", 2.0, r"D .*\(1, 2\)"),
        ("D", float("nan"), r"D .*\(1, 2\)"),
        ("G", 0.0, r"G .*= 0 .*\(0, inf\)"),
        ("G", -1e-10, r"G .*\(0, inf\)"),
        ("l_min", 0.0, r"l_min .*\(0, inf\)"),
    ],
)
def test_surface(field, value, pattern):
    kw = dict(D=1.4, G=1e-10, l_min=1e-9) | {field: value}
    with pytest.raises(ValueError, match=pattern):
        jc.Surface(**kw)


@pytest.mark.parametrize(
    "field, value, pattern",
    [
        ("E", 0.0, r"E .*\(0, inf\)"),
        ("nu", 0.5, r"nu .*= 0.5 .*\[0, 0.5\)"),
        ("nu", -0.1, r"nu .*\[0, 0.5\)"),
        ("H", -1.0, r"H .*\(0, inf\)"),
        ("E", float("inf"), r"E .*\(0, inf\)"),
    ],
)
def test_material(field, value, pattern):
    kw = dict(E=2e11, nu=0.3, H=1e9) | {field: value}
    with pytest.raises(ValueError, match=pattern):
        jc.Material(**kw)


def test_arrays_are_checked_elementwise():
    with pytest.raises(ValueError, match="D .*outside"):
        jc.Surface(D=jnp.array([1.4, 2.5]), G=1e-10)


@pytest.mark.parametrize(
    "kw, pattern",
    [
        (dict(area=0.0), r"area .*\(0, inf\)"),
        (dict(l_min=0.011), r"l_min .*too large for area"),
        (dict(model="gw1966"), r"model = 'gw1966' is not one of 'xia2024', 'jzz2010'"),
        (dict(interaction="both"), r"interaction = 'both' is not one of 'none', 'paper', 'series'"),
        (dict(distribution="gauss"), r"distribution = 'gauss' is not one of 'mb', 'wk'"),
        (dict(model="jzz2010", interaction="paper"), r"model 'jzz2010' has no interaction"),
        (dict(quadrature_nodes=1), r"GaussLegendre: nodes = 1 must be an integer in \[2, 1024\]"),
        (
            dict(quadrature="simpson"),
            r"quadrature = 'simpson' is not one of 'power-series', 'gauss-legendre', 'adaptive'",
        ),
        (dict(interaction="none", quadrature="adaptive"), r"interaction 'none' has no integral to do"),
        (
            dict(model="xia2024", regime_shares=False),
            r"got an unexpected keyword argument 'regime_shares'",
        ),
    ],
)
def test_scene(kw, pattern):
    params = TABLE1 | {k: kw.pop(k) for k in ("area", "l_min") if k in kw}
    with pytest.raises((ValueError, TypeError), match=pattern):
        make_scene(**params, **kw)


def test_the_paper_quadrature_is_refused_by_the_series_interaction():
    with refused_type("quadrature", r"PowerSeries\(\) is for 'paper' only"):
        make_scene(**TABLE1, interaction="series", quadrature="power-series")


@pytest.mark.parametrize(
    "kw, pattern",
    [
        (dict(max_steps=0), r"max_steps = 0 must be an integer in \[1, 10000\]"),
        (dict(tolerance=0.5), r"NewtonBisection: tolerance = 0.5 must be None or in \(0, 0.01\)"),
    ],
)
def test_solver_settings(kw, pattern):
    with pytest.raises(ValueError, match=pattern):
        jc.NewtonBisection(**kw)


def test_a_fractional_step_count_is_refused():
    with refused_type("max_steps", r"max_steps = 2.5 must be an integer"):
        jc.NewtonBisection(max_steps=2.5)


def test_outputs_settings():
    with refused_type("regime_shares", r"regime_shares = 'no' must be true or false"):
        jc.Outputs(regime_shares="no")


@pytest.mark.parametrize(
    "loads, pattern",
    [
        (-1.0, r"loads = -1.0 N is not a valid load.*\(0, inf\)"),
        (jnp.array([1.0, jnp.nan]), r"loads\[1\] = nan N"),
        ([1.0, 0.0], r"loads\[1\] = 0.0 N"),
        (jnp.array([1.0, jnp.inf]), r"loads\[1\] = inf N"),
        (np.array([[2.0, 1.0], [-np.inf, 3.0]]), r"loads\[1, 0\] = -inf N"),
    ],
)
def test_concrete_bad_loads(table1_scene, loads, pattern):
    with pytest.raises(ValueError, match=pattern):
        jc.solve(table1_scene, loads)


def test_a_scene_refuses_a_tuple_for_its_surface():
    with refused_type("surface", "surface must be a jaxcontact.Surface"):
        jc.Scene(surface=(1.4, 1e-10), material=jc.Material(2e11, 0.3, 1e9), area=1e-4)


def test_a_surface_refuses_a_boolean_for_D():
    with pytest.raises(ValueError, match="expected a number"):
        jc.Surface(D=True, G=1e-10)


def test_solve_names_an_argument_that_is_not_a_scene():
    with refused_type("scene", r"scene = None must be a Scene"):
        jc.solve(None, 10.0)


def test_a_scene_with_array_parameters_is_refused_by_solve_with_the_way_to_batch():
    scene = jc.Scene(jc.Surface(D=[1.3, 1.4], G=1e-10), jc.Material(2e11, 0.3, 1e11), 1e-4)
    with pytest.raises(jc.InputError, match=r"D has shape \(2,\): solve takes one scene.*jax.vmap"):
        jc.solve(scene, 10.0)


# F* = 10 (above E A_a: more than full contact could carry) beside two valid loads.
THROWN_LOADS = np.array([10.0, 10.0 * TABLE1["E"] * TABLE1["area"], 100.0])


def test_throw_names_each_point_without_a_valid_result(table1_scene):
    named = re.escape(f"loads[1] = {THROWN_LOADS[1]:.6g} N: LOAD_OUT_OF_RANGE")
    with pytest.raises(jc.StatusError, match=rf"1 of 3 points .*{named}"):
        jc.solve(table1_scene, THROWN_LOADS, throw=True)


def test_throw_leaves_a_valid_solve_as_it_is(table1_scene):
    loads = THROWN_LOADS[[0, 2]]
    thrown = jc.solve(table1_scene, loads, throw=True).stiffness
    np.testing.assert_array_equal(np.asarray(thrown), np.asarray(jc.solve(table1_scene, loads).stiffness))


def test_throw_under_jit_raises_the_status_message():
    scene = make_scene(**{**TABLE1, "interaction": "none"})
    solved = jax.jit(lambda F: jc.solve(scene, F, throw=True).stiffness)
    with pytest.raises(Exception, match=re.escape(jc.Status.LOAD_OUT_OF_RANGE.message)):
        solved(jnp.asarray(THROWN_LOADS)).block_until_ready()


@pytest.mark.parametrize("setting", [dict(max_steps=10), dict(solver_tolerance=1e-9)])
def test_root_finder_settings_are_refused_by_a_model_that_finds_no_state(setting):
    name = next(iter(setting))
    with pytest.raises(jc.InputError, match=rf"{name} applies to models that solve .* model 'persson' finds none"):
        make_scene(**TABLE1, model="persson", **setting)


def test_the_gw_model_solves_with_the_root_finder_it_holds():
    loads = np.geomspace(1e-7, 1e-4, 5) * TABLE1["E"] * TABLE1["area"]
    one_step = jc.solve(
        make_scene(**TABLE1, model=jc.GreenwoodWilliamson(root_finder=jc.NewtonBisection(max_steps=1))), loads
    )
    np.testing.assert_array_equal(one_step.status, jc.Status.NOT_CONVERGED)
