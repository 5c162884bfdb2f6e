"""The contact moduli of two bodies (Johnson 1985), against hand values and Mindlin's stiffness ratio."""

import jax
import numpy as np
import pytest

import jaxcontact as jc


def test_two_steels_have_the_contact_modulus_e_over_two_one_minus_nu_squared():
    np.testing.assert_allclose(jc.contact_modulus(210e9, 0.3, 210e9, 0.3), 210e9 / (2 * (1 - 0.09)), rtol=1e-15)


def test_steel_on_aluminium():
    """1/E* = 0.91/210 GPa + (1 − 0.33²)/70 GPa: 56.60 GPa."""
    expected = 1 / (0.91 / 210e9 + (1 - 0.33**2) / 70e9)
    np.testing.assert_allclose(jc.contact_modulus(210e9, 0.3, 70e9, 0.33), expected, rtol=1e-15)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.3, 0.45])
def test_like_materials_have_mindlins_stiffness_ratio(nu):
    """A spot's stick stiffness 8 G* a over its normal stiffness 2 E* a is 2(1 − ν)/(2 − ν)."""
    ratio = 8 * jc.tangential_contact_modulus(1e11, nu, 1e11, nu) / (2 * jc.contact_modulus(1e11, nu, 1e11, nu))
    np.testing.assert_allclose(ratio, 2 * (1 - nu) / (2 - nu), rtol=1e-14)


def test_a_rigid_partner_leaves_the_bodys_own_plane_strain_modulus():
    np.testing.assert_allclose(jc.contact_modulus(200e9, 0.3, 1e30, 0.3), 200e9 / 0.91, rtol=1e-12)


def test_the_contact_modulus_is_differentiable():
    dE1 = jax.grad(lambda E1: jc.contact_modulus(E1, 0.3, 70e9, 0.33))(210e9)
    E_star = jc.contact_modulus(210e9, 0.3, 70e9, 0.33)
    np.testing.assert_allclose(dE1, E_star**2 * 0.91 / 210e9**2, rtol=1e-6)


@pytest.mark.parametrize("args, name", [((-1.0, 0.3, 1e11, 0.3), "E1"), ((1e11, 0.6, 1e11, 0.3), "nu1")])
def test_a_value_out_of_range_is_refused_by_name(args, name):
    with pytest.raises(ValueError, match=rf"{name} \("):
        jc.contact_modulus(*args)
