"""F_t(a_l) piece by piece (the a_l solve's residual) against the joint's full regime sums."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, log_total_load_slopes, make_joint, make_scene, total_loads

import jaxcontact as jc
from jaxcontact.core import prepare
from jaxcontact.models import GenericLoadPieces, PowerLawLoadPieces


@eqx.filter_jit
def piece_log_loads(pieces, log_a_l, piece):
    """ln F_t* on one piece, its slope in ln a_l* by autodiff, and the pieces' own (closed-form) slope."""

    def log_load(x):
        return pieces.log_load(x, piece)

    return (
        jax.vmap(log_load)(log_a_l),
        jax.vmap(jax.grad(log_load))(log_a_l),
        jax.vmap(lambda x: pieces.log_load_slope(x, piece))(log_a_l),
    )


def joint_of(**kw):
    scene, _ = prepare(make_scene(**{**TABLE1, **kw}), 1.0)
    return make_joint(scene)


@pytest.mark.parametrize("D, distribution", [(1.4058, "mb"), (1.05, "mb"), (1.5, "wk"), (1.93, "mb")])
def test_closed_form_pieces_equal_the_full_regime_sums(D, distribution):
    joint = joint_of(D=D, distribution=distribution)
    pieces = joint.load_pieces()
    assert isinstance(pieces, PowerLawLoadPieces)
    knots = np.asarray(pieces.knots)
    assert np.all(np.diff(knots) >= 0)
    assert knots[0] == float(joint.log_a_min)
    assert knots[-1] == 0.0
    np.testing.assert_allclose(pieces.knot_log_loads[1:], np.log(total_loads(joint, pieces.knots[1:])), rtol=1e-13)
    for piece in range(4):
        lo, hi = knots[piece], knots[piece + 1]
        if hi <= lo:
            continue
        x = jnp.linspace(lo, hi, 9)[1:]
        got, slope, closed_form_slope = piece_log_loads(pieces, x, jnp.int32(piece))
        np.testing.assert_allclose(got, jnp.log(total_loads(joint, x)), rtol=1e-13, atol=1e-13)
        # The slopes too (inside the piece: at a kink the full sum has no single slope).
        np.testing.assert_allclose(slope[:-1], log_total_load_slopes(joint, x[:-1]), rtol=1e-11)
        np.testing.assert_allclose(closed_form_slope[:-1], log_total_load_slopes(joint, x[:-1]), rtol=1e-11)


def test_locate_brackets_the_solution():
    joint = joint_of()
    pieces = joint.load_pieces()
    log_loads = jnp.linspace(float(pieces.knot_log_loads[1]) - 8.0, float(pieces.knot_log_loads[-1]) - 1e-6, 400)
    piece, lower, upper, guess = eqx.filter_jit(lambda p, x: jax.vmap(p.locate)(x))(pieces, log_loads)
    scene = make_scene(**TABLE1, interaction="none")
    root = np.log(np.asarray(jc.solve(scene, np.exp(np.asarray(log_loads)) * TABLE1["E"] * TABLE1["area"]).a_l_star))
    assert np.all((lower <= root + 1e-12) & (root <= upper + 1e-12))
    assert np.all((lower <= guess) & (guess <= upper))
    assert set(np.unique(piece)) == {0, 1, 2, 3}  # the sweep crosses every regime boundary


def test_jzz2010_uses_the_generic_pieces_with_its_one_kink():
    joint = joint_of(model="jzz2010", interaction="none")
    pieces = joint.load_pieces()
    assert isinstance(pieces, GenericLoadPieces)
    np.testing.assert_allclose(pieces.knots[1], np.clip(float(joint.log_a_c), float(joint.log_a_min), 0.0))


def test_hard_loads_fall_back_to_the_optimistix_loop():
    # Near a_min, ln F_t ~ ln(a_l - a_min): a few straight-line Newton steps from the piece's
    # end are not enough, and the loop must finish the job (max_steps = 4 leaves it no steps).
    loads = np.geomspace(1e-14, 1e-11, 12) * TABLE1["E"] * TABLE1["area"]
    short = jc.solve(
        make_scene(**TABLE1, model=jc.Xia2024(interaction=jc.NoInteraction(), root_finder=jc.NewtonBisection(4))), loads
    )
    full = jc.solve(make_scene(**TABLE1, interaction="none"), loads)
    assert np.any(np.asarray(short.status) == jc.Status.NOT_CONVERGED)
    np.testing.assert_array_equal(full.status, 0)
    # F_t(a_l) reproduces every load.
    joint = joint_of(interaction="none")
    F = total_loads(joint, jnp.log(full.a_l_star))
    np.testing.assert_allclose(F, full.load_star, rtol=1e-12)
