"""The load–approach curve (docs/model.md §6) against direct quadrature of 1/K, and its command."""

import json

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import ROOT, TABLE1, make_scene, scipy_approach

import jaxcontact as jc
from jaxcontact.cli import main

LOADS = jnp.array([2.2, 7.0, 22.0, 70.0, 220.0, 2200.0])
F0 = 22.0


@pytest.mark.parametrize("model", ["xia2024", "jzz2010"])
def test_matches_quadrature_of_inverse_stiffness(model):
    scene = make_scene(**TABLE1, model=model)
    result = jc.approach(scene, LOADS, F0)
    assert np.all(np.asarray(result.status) == 0)
    expected = scipy_approach(scene, LOADS, F0, epsrel=1e-11)
    np.testing.assert_allclose(result.approach, expected, rtol=1e-8, atol=1e-22)
    assert float(result.approach[2]) == 0.0


def test_meets_its_tolerance_across_regime_kinks():
    """Issue 18.8: near the preload and across the kinks of K(F) where a_l enters a new Kogut–Etsion
    regime, δ(F) - δ(F0) is within the default rtol (1e-10) of a quadrature of 1/K."""
    scene = make_scene(D=1.43, G=3.3e-10, E=200e9, nu=0.3, H=5e9, area=1e-4, l_min=2e-9, interaction="series")
    load_scale = 200e9 * 1e-4  # E A_a
    F0 = 1e-6 * load_scale
    loads = np.array([3e-7, 8e-7, 1.6e-6, 3e-6, 1e-5, 3e-5, 1e-4]) * load_scale
    result = jc.approach(scene, loads, F0)
    expected = scipy_approach(scene, loads, F0)
    np.testing.assert_allclose(result.approach, expected, rtol=1e-10, atol=0.0)


def test_monotone_in_load(dynamics_scene):
    loads = jnp.geomspace(2.2, 2200.0, 31)
    delta = np.asarray(jc.approach(dynamics_scene, loads, 220.0).approach)
    assert np.all(np.diff(delta) > 0)
    assert delta[0] < 0 < delta[-1]


def test_one_seven_and_thirty_loads_share_one_compiled_approach(dynamics_scene):
    from jaxcontact.applications._loadapproach import _approach

    before = _approach._cached._cache_size()
    loads = np.geomspace(2.2, 2200.0, 30)
    many = jc.approach(dynamics_scene, loads, 220.0)
    few = jc.approach(dynamics_scene, loads[:7], 220.0)
    one = jc.approach(dynamics_scene, loads[3], 220.0)
    assert _approach._cached._cache_size() - before <= 1  # one bucket (32): compiled here or by a test above
    # Each call integrates only as far as its own loads reach: equal within the ODE's tolerance.
    np.testing.assert_allclose(few.approach, many.approach[:7], rtol=1e-9)
    assert one.approach.shape == one.status.shape == ()
    np.testing.assert_allclose(float(one.approach), float(many.approach[3]), rtol=1e-9)


def test_gradients_match_finite_differences():
    # Persson's K is explicit in the load: reverse mode through diffrax compiles in half the time
    # of the seed model's a_l solve, whose reverse mode inside diffrax test_dynamics.py checks.
    table1_scene = make_scene(**TABLE1, model="persson")

    # The scene is an argument, as equinox passes modules: its arrays are traced, not constants.
    # One reverse-mode program gives w·δ and its gradient for any weights w: each row of the
    # Jacobian, and the values the differences need (`jacrev`, vmapped over the outputs, compiles 1.6 times as long).
    @jax.jit
    @jax.value_and_grad
    def weighted_delta(theta, weights, scene):
        scene = eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, (theta[0], theta[1]))
        return jc.approach(scene, jnp.array([2.2, 2200.0]), F0).approach @ weights

    theta = jnp.array([TABLE1["D"], TABLE1["G"]])
    for i, weights in enumerate(jnp.eye(2)):
        _, grad = weighted_delta(theta, weights, table1_scene)
        # Relative steps large enough that the ODE tolerance (1e-10 of δ) is not what is measured.
        for j, step in enumerate((1e-5, 1e-4)):
            e = jnp.zeros(2).at[j].set(step * theta[j])
            up, down = (weighted_delta(theta + s * e, weights, table1_scene)[0] for s in (1, -1))
            np.testing.assert_allclose(grad[j], (up - down) / (2 * e[j]), rtol=1e-5, err_msg=f"dδ{i}/d{'DG'[j]}")


def test_the_command_on_its_embedded_scene(dynamics_scene, tmp_path, capsys):
    """`jaxcontact approach`: the curve the library gives for the same scene (the same compiled program)."""
    assert main(["approach", "--out", str(tmp_path), "--format", "json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    rows = payload["rows"]
    assert payload["reference_load_N"] == 220.0
    assert len(rows) == 31
    delta = np.array([r["approach_m"] for r in rows])
    assert np.all(np.diff(delta) > 0)
    assert delta[0] < 0 < delta[-1]
    expected = jc.approach(dynamics_scene, np.array([r["F_N"] for r in rows]), 220.0).approach
    np.testing.assert_allclose(delta, np.asarray(expected), rtol=1e-12)
    assert (tmp_path / "approach.png").stat().st_size > 10_000


def test_run_adds_the_approach_only_when_asked(tmp_path, capsys):
    assert main(["run", "--out", str(tmp_path / "a"), "--format", "json"]) == 0
    assert "approach_m" not in json.loads(capsys.readouterr().out)["rows"][0]
    assert (
        main(
            [
                "run",
                str(ROOT / "data" / "scenes" / "table1_dynamics.toml"),
                "--out",
                str(tmp_path / "b"),
                "--format",
                "json",
            ]
        )
        == 0
    )
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert all(np.isfinite(r["approach_m"]) for r in rows)


def test_flagged_points():
    # 1130 N breaks down with "paper": the program of the tests above.
    scene = make_scene(1.5, 3e-10, 1.13e11, 0.3, 4e9, 1e-4, 1e-9)
    result = jc.approach(scene, jnp.array([1.13, 113.0, 1130.0]), 11.3)
    np.testing.assert_array_equal(result.status, [0, 0, jc.Status.INTERACTION_BREAKDOWN])
    assert np.all(np.isfinite(np.asarray(result.approach)[:2]))
    assert np.isnan(float(result.approach[2]))


def test_bad_reference_load(table1_scene):
    with pytest.raises(ValueError, match="not a valid load"):
        jc.approach(table1_scene, LOADS, -1.0)


def test_where_programs_are_kept_a_later_call_reads_the_approach_untraced(dynamics_scene, tmp_path, monkeypatch):
    from jaxcontact.applications import _loadapproach as loadapproach
    from jaxcontact.cli import _exported as exported

    traced = []

    def cheap(scene, loads, reference_load, rtol, max_steps):  # stands in for the ODE solve
        traced.append(loads.shape)
        delta = (loads - reference_load) * scene.surface.D
        return loadapproach.Approach(loads, reference_load, delta, jnp.zeros(loads.shape, jnp.int32))

    monkeypatch.setattr(loadapproach, "_approach", cheap)
    monkeypatch.setattr("equinox._errors.EQX_ON_ERROR", "nan")  # as the executable sets it (`compat`)
    loads = np.geomspace(2.2, 2200.0, 7)
    with exported.exported_programs(tmp_path):
        first = jc.approach(dynamics_scene, loads, 22.0)
        again = jc.approach(dynamics_scene, loads, 22.0)
    assert len(traced) == 1  # the second call ran the program kept on disk
    np.testing.assert_array_equal(again.approach, first.approach)


def test_while_equinox_checks_through_host_callbacks_the_approach_is_not_exported(
    dynamics_scene, tmp_path, monkeypatch
):
    """No exported program can hold a host callback: tracing the solve to export it would be for nothing."""
    from jaxcontact.cli import _exported as exported

    monkeypatch.setattr("equinox._errors.EQX_ON_ERROR", "raise")
    with exported.exported_programs(tmp_path):
        jc.approach(dynamics_scene, np.geomspace(2.2, 2200.0, 7), 22.0)
    assert not list(tmp_path.glob("approach-*"))
