"""The joint's inputs (MODEL.md §1): the rough surface and the material pair.

Both are `equinox.Module`s whose float fields are pytree leaves, so `jax.grad` can differentiate
with respect to any of them (e.g. through `eqx.tree_at(lambda s: s.surface.D, scene, D)`), and
`jax.vmap` can batch over them when they are arrays.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import ArrayLike, Float

from ._validate import as_float, check_range

Parameter = Float[ArrayLike, "*batch"]


class Surface(eqx.Module):
    """A fractal (Weierstrass–Mandelbrot) rough surface, Eq. (1).

    **Arguments:**

    - `D`: profile fractal dimension, 1 < D < 2.
    - `G`: fractal roughness (characteristic scale), m, G > 0.
    - `l_min`: lower cutoff length of the fractal range (the smallest asperity base), m, > 0.
      The elastic stiffness integral diverges at a → 0 for every D (MODEL.md §2), so results
      depend on `l_min`; the default 1 nm is the paper's implied atomic-scale cutoff.
    """

    D: Parameter = eqx.field(converter=as_float)
    G: Parameter = eqx.field(converter=as_float)
    l_min: Parameter = eqx.field(default=1e-9, converter=as_float)

    def __check_init__(self):
        check_range("D", self.D, 1.0, 2.0, meaning="fractal dimension")
        check_range("G", self.G, 0.0, meaning="fractal roughness, m")
        check_range("l_min", self.l_min, 0.0, meaning="lower cutoff length, m")


class Material(eqx.Module):
    """The equivalent material of the contact pair.

    **Arguments:**

    - `E`: equivalent (composite) elastic modulus, Pa, > 0.
    - `nu`: Poisson's ratio, 0 ≤ ν < 0.5 (enters the hardness coefficient κ = 0.454 + 0.41 ν, Eq. 6).
    - `H`: hardness of the softer material, Pa, > 0.
    """

    E: Parameter = eqx.field(converter=as_float)
    nu: Parameter = eqx.field(converter=as_float)
    H: Parameter = eqx.field(converter=as_float)

    def __check_init__(self):
        check_range("E", self.E, 0.0, meaning="equivalent elastic modulus, Pa")
        check_range("nu", self.nu, 0.0, 0.5, low_open=False, meaning="Poisson's ratio")
        check_range("H", self.H, 0.0, meaning="hardness, Pa")

    @property
    def kappa(self):
        """Hardness coefficient κ = 0.454 + 0.41 ν (the paper's "K", Eq. 6)."""
        return 0.454 + 0.41 * jnp.asarray(self.nu)
