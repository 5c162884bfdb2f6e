"""Log-area Gauss–Legendre quadrature against the closed forms, across the whole D range."""

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
