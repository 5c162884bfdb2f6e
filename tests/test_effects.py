"""Effects are static: what a scene does not ask for is not in its compiled program."""

import jax
import jax.extend
import jax.numpy as jnp
import numpy as np
from helpers import TABLE1, make_joint, make_scene

import jaxcontact as jc
from jaxcontact.physics import wang_komvopoulos_psi

LOADS = jnp.array([2.2, 22.0, 220.0])


def all_equations(jaxpr):
    """Every equation of a closed jaxpr, sub-jaxprs (while, cond, custom_jvp, pjit) included."""
    out = []
    for eqn in jaxpr.eqns:
        out.append(eqn)
        for sub in jax.extend.core.jaxprs_in_params(eqn.params):
            out.extend(all_equations(sub))
    return out


def program(scene, outputs=jc.Outputs()):
    closed = jax.make_jaxpr(lambda s, F: jc.solve(s, F, outputs=outputs))(jax.tree.map(jnp.asarray, scene), LOADS)
    return closed, all_equations(closed.jaxpr)


def has_quadrature_nodes(closed, eqns, nodes):
    """True where an array with a trailing axis of `nodes` (the Gauss–Legendre nodes) exists."""
    shapes = [
        getattr(v.aval, "shape", ()) for e in eqns for v in list(e.invars) + list(e.outvars) if hasattr(v, "aval")
    ]
    shapes += [np.shape(c) for c in closed.consts]
    return any(len(s) and s[-1] == nodes for s in shapes)


def test_without_interaction_the_pressure_never_reaches_the_stiffness():
    joint = make_joint(make_scene(**TABLE1, interaction="none"))
    jaxpr = jax.make_jaxpr(lambda la, lp: joint.response(la, lp).regime_stiffness)(-20.0, -13.0).jaxpr
    pressure = jaxpr.invars[1]
    assert all(pressure not in e.invars for e in all_equations(jaxpr))
    with_interaction = make_joint(make_scene(**TABLE1, interaction="paper"))
    jaxpr = jax.make_jaxpr(lambda la, lp: with_interaction.response(la, lp).regime_stiffness)(-20.0, -13.0).jaxpr
    assert any(jaxpr.invars[1] in e.invars for e in all_equations(jaxpr))


def test_interaction_quadrature_only_when_asked():
    nodes = 37  # an unusual count, so that no other array has this trailing size
    for interaction, expected in (
        (jc.NoInteraction(), False),
        (jc.PaperInteraction(jc.GaussLegendre(nodes)), True),
        (jc.SeriesInteraction(jc.GaussLegendre(nodes)), True),
        # The default for "paper" sums the pole term's series: no nodes at all.
        (jc.PaperInteraction(), False),
    ):
        closed, eqns = program(make_scene(**TABLE1, model=jc.Xia2024(interaction=interaction)))
        assert has_quadrature_nodes(closed, eqns, nodes) == expected, interaction


def test_regime_shares_only_when_asked():
    scene, lean = make_scene(**TABLE1), jc.Outputs(regime_shares=False)
    sol = jc.solve(scene, LOADS, outputs=lean)
    assert sol.load_share is None
    assert sol.stiffness_share is None
    # Same numbers (XLA may fuse the two programs differently: last-bit differences only).
    np.testing.assert_allclose(sol.stiffness, jc.solve(scene, LOADS).stiffness, rtol=1e-14)
    assert len(program(scene, lean)[1]) < len(program(scene)[1])


def test_mb_distribution_has_no_wk_root_find():
    # ψ's equation is the only user of log1p in the forward program (the default quadrature).
    def log1ps(eqns):
        return sum(e.primitive.name == "log1p" for e in eqns)

    psi_solve = log1ps(all_equations(jax.make_jaxpr(wang_komvopoulos_psi)(jnp.asarray(1.4)).jaxpr))
    assert psi_solve > 0
    assert log1ps(program(make_scene(**TABLE1, distribution="wk"))[1]) == psi_solve
    assert log1ps(program(make_scene(**TABLE1))[1]) == 0
