"""Cross-check against the plain scipy implementation (quad + brentq) on random valid scenes."""

import jax.numpy as jnp
import numpy as np
import pytest
from helpers import make_scene

import jaxcontact as jc
from jaxcontact.studies._scipy_baseline import BaselineParameters, solve_point

rng = np.random.default_rng(20241121)
CASES = [
    dict(
        D=float(rng.uniform(1.05, 1.95)),
        G=float(10 ** rng.uniform(-12, -9)),
        E=float(10 ** rng.uniform(10.5, 11.7)),
        nu=float(rng.uniform(0, 0.45)),
        H=float(10 ** rng.uniform(8.5, 10.5)),
        area=float(10 ** rng.uniform(-5, -3)),
        l_min=float(10 ** rng.uniform(-9.5, -8)),
    )
    for _ in range(4)
]


@pytest.mark.parametrize("case", CASES, ids=[f"D={c['D']:.3f}" for c in CASES])
@pytest.mark.parametrize(
    "model, interaction, distribution",
    [
        ("xia2024", "none", "mb"),
        ("xia2024", "paper", "wk"),
        ("xia2024", "series", "mb"),
        ("jzz2010", "none", "wk"),
    ],
)
def test_matches_scipy_baseline(case, model, interaction, distribution):
    loads = np.array([1e-7, 1e-6, 1e-5]) * case["E"] * case["area"]
    sol = jc.solve(
        make_scene(**case, model=model, interaction=interaction, distribution=distribution), jnp.asarray(loads)
    )
    p = BaselineParameters(**case, model=model, interaction=interaction, distribution=distribution)
    for i, F in enumerate(loads):
        a_l, K, A_r, status = solve_point(p, float(F))
        assert jc.status_message(sol.status[i]) == status
        if status in ("ok", "interaction_breakdown"):
            np.testing.assert_allclose([sol.a_l[i], sol.real_area[i]], [a_l, A_r], rtol=1e-8)
        if status == "ok":
            np.testing.assert_allclose(sol.stiffness[i], K, rtol=1e-8, atol=1e-300)


def test_bench_compares_with_the_baseline_of_the_same_scene():
    """`jaxcontact bench` times the scipy baseline on the scene's own parameters and choices."""
    from jaxcontact.studies._curve import _baseline

    p = _baseline(make_scene(**CASES[0], interaction="series", distribution="wk"))
    names = ("D", "G", "E", "nu", "H", "area", "l_min")
    assert tuple(getattr(p, k) for k in names) == tuple(CASES[0][k] for k in names)
    assert (p.interaction, p.distribution) == ("series", "wk")


def test_bench_refuses_a_spot_stiffness_the_baseline_does_not_implement():
    from jaxcontact.studies._curve import _baseline

    with pytest.raises(ValueError, match="spot_stiffness = 'sneddon'"):
        _baseline(make_scene(**CASES[0], spot_stiffness="sneddon"))


def test_bench_times_the_users_call_under_jax_defaults():
    """The plain call's verdict is taken in a fresh process with JAX's defaults: asynchronous
    dispatch, which the test process (x64 switched on, nothing else) has too, and the command line
    does not; the child's curve is timed against its own scipy run."""
    from jaxcontact.studies._bench_user import curve_as_users_call_it

    scene = make_scene(**CASES[0], interaction="none")
    result = curve_as_users_call_it(scene, rounds=1, repeats=2, only=("plain",))
    assert result["async_dispatch"] is True
    timed = {name for name, value in result.items() if isinstance(value, dict) and value["median_s"] > 0}
    assert timed == {"scipy", "plain", "jit"}
