"""The equivalent elastic moduli of a pair of bodies in contact, from each body's E and ν."""

from __future__ import annotations

from ..numerics._validate import check_range


def _checked(E1, nu1, E2, nu2) -> None:
    for name, value in (("E1", E1), ("E2", E2)):
        check_range(name, value, 0.0, meaning="Young's modulus, Pa")
    for name, value in (("nu1", nu1), ("nu2", nu2)):
        check_range(name, value, -1.0, 0.5, meaning="Poisson's ratio")


def contact_modulus(E1, nu1, E2, nu2):
    """The contact (composite) modulus `E*` of two elastic bodies, the `Material.E` of their joint:
    `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` (Johnson, *Contact Mechanics*, 1985, Eq. 4.22). Two steels
    (210 GPa, ν = 0.3) give 115.4 GPa.

    **Arguments:** each body's Young's modulus `E1`, `E2` (Pa, > 0) and Poisson's ratio `nu1`, `nu2`
    (in (−1, 0.5)); numbers or arrays (JAX arrays too: differentiable).

    **Returns:** `E*`, Pa.
    """
    _checked(E1, nu1, E2, nu2)
    return 1.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2)


def tangential_contact_modulus(E1, nu1, E2, nu2):
    """The tangential contact modulus `G*` of two elastic bodies (Mindlin's stick stiffness of a spot of
    radius a is `8 G* a`): `1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂`, `G_i = E_i / (2 (1 + ν_i))` (Johnson 1985,
    §7.2). For like materials `8 G*/(2 E*) = 2(1 − ν)/(2 − ν)`.

    **Arguments:** as `contact_modulus`. **Returns:** `G*`, Pa.
    """
    _checked(E1, nu1, E2, nu2)
    G1, G2 = E1 / (2.0 * (1.0 + nu1)), E2 / (2.0 * (1.0 + nu2))
    return 1.0 / ((2.0 - nu1) / G1 + (2.0 - nu2) / G2)
