"""Log-area Gauss–Legendre quadrature against the closed forms, across the whole D range."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_joint, make_scene

import jaxcontact as jc
from jaxcontact.numerics import integrate_log_area
from jaxcontact.physics._interaction import stiffness_without_interaction


@pytest.mark.parametrize("D", [1.01, 1.1, 1.25, 1.4058, 1.5, 1.65, 1.8, 1.99])
def test_quadrature_reproduces_closed_forms(D):
    params = {**TABLE1, "D": D, "G": 1e-10}
    joint = make_joint(make_scene(**params, interaction="none"))
    for log_a_l in (-20.0, -12.0, -3.0):
        lower, upper = joint.intervals(jnp.asarray(log_a_l))
        n = joint.distribution(jnp.asarray(log_a_l))
        laws = {
            "load": joint.load_laws * n,
            "stiffness": stiffness_without_interaction(joint.load_laws, joint.interference_law) * n,
        }
        for name, law in laws.items():
            closed = law.integral(lower, upper)
            expanded = law.expanded()
            quad = integrate_log_area(lambda t: expanded(t) * jnp.exp(t), lower, upper, 48)
            np.testing.assert_allclose(quad, closed, rtol=1e-12, atol=1e-300, err_msg=f"{name} D={D} {log_a_l}")


def test_interacting_stiffness_converges_with_nodes():
    """Gauss–Legendre on the remainder is converged at 32 nodes: tripling them changes K by less than 1e-10."""
    results = []
    for nodes in (32, 96):
        scene = make_scene(**TABLE1, interaction="paper", quadrature="gauss-legendre", quadrature_nodes=nodes)
        results.append(np.asarray(jc.solve(scene, jnp.array([2.2, 220.0, 2200.0, 1.0e4])).stiffness))
    np.testing.assert_allclose(results[0], results[1], rtol=1e-10)


def test_the_pole_remainder_agrees_across_quadratures():
    """Interaction "paper": the power series, Gauss–Legendre and adaptive quadax agree on K.

    Each regime's correction is its own chain (`joint._paper_correction`), whatever the
    quadrature; the quadratures share nothing with the power series but the split into rows.
    The loads run from the elastic regime to 0.996 of the breakdown load (F* = 9.812e-4,
    2.159e4 N here), where the remainder is largest.
    """
    loads = jnp.array([2.2, 220.0, 2200.0, 2.0e4, 2.15e4])
    stiffness = {}
    for quadrature in ("power-series", "gauss-legendre", "adaptive"):
        scene = make_scene(**TABLE1, interaction="paper", quadrature=quadrature, quadrature_nodes=32)
        solution = jc.solve(scene, loads)
        assert np.all(np.asarray(solution.status) == 0)
        stiffness[quadrature] = np.asarray(solution.stiffness)
    for quadrature in ("gauss-legendre", "adaptive"):
        np.testing.assert_allclose(stiffness[quadrature], stiffness["power-series"], rtol=1e-12, err_msg=quadrature)


def _paper_scene(together, D=TABLE1["D"]):
    quadrature = jc.PowerSeries(regimes_together=together)
    return make_scene(**dict(TABLE1, D=D), model=jc.Xia2024(interaction=jc.PaperInteraction(quadrature=quadrature)))


# Loads across every regime of the Table 1 scene, up to its breakdown.
LAYOUT_LOADS = np.geomspace(1e-10, 1e-5, 12) * 220e9 * 1e-4


@functools.cache
def _log_stiffness_and_derivative_in_D(together):
    """Σ ln K at `LAYOUT_LOADS` and its derivative in D, with the regimes laid out as `together` says."""

    def total(D):
        return jnp.sum(jnp.log(jc.solve(_paper_scene(together, D), LAYOUT_LOADS).stiffness))

    return jax.jit(lambda D: jax.jvp(total, (D,), (jnp.ones_like(D),)))(jnp.asarray(TABLE1["D"]))


def test_the_regimes_laid_out_together_give_the_per_regime_stiffness():
    apart, together = (_log_stiffness_and_derivative_in_D(t)[0] for t in (False, True))
    np.testing.assert_allclose(together, apart, rtol=1e-14)


def test_the_regimes_laid_out_together_give_the_per_regime_derivative_in_D():
    apart, together = (_log_stiffness_and_derivative_in_D(t)[1] for t in (False, True))
    np.testing.assert_allclose(together, apart, rtol=1e-12)


def test_a_solve_of_few_loads_lays_the_regimes_out_together():
    """The default layout (`regimes_together=None`) makes the program of 32 loads much smaller than
    that of 256, which keeps a chain per regime."""
    scene = jc.table1_scene()

    def size(n):
        jaxpr = jax.make_jaxpr(lambda F: jc.solve(scene, F).stiffness)(jnp.geomspace(1.0, 1e3, n))
        return len(str(jaxpr))

    assert size(32) < 0.8 * size(256)
