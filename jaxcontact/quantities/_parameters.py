"""The joint's inputs (docs/model.md §1): the rough surface and the material pair.

Both are `equinox.Module`s whose float fields are stored as JAX arrays: pytree leaves, so that
`eqx.filter_grad` differentiates with respect to them, `eqx.filter_jit` traces them (a new value
does not recompile), `jax.vmap`/`eqx.filter_vmap` batch over them when they have a batch axis, and
`eqx.tree_at(lambda s: s.surface.D, scene, D)` replaces one. Valid ranges: `domain.PARAMETERS`.
"""

from __future__ import annotations

import equinox as eqx
from jaxtyping import ArrayLike, Float

from ..numerics._validate import as_array
from ._domain import PARAMETERS

Parameter = Float[ArrayLike, "*batch"]


class Surface(eqx.Module):
    """A fractal (Weierstrass–Mandelbrot) rough surface, Eq. (1).

    **Arguments:**

    - `D`: profile fractal dimension, 1 < D < 2.
    - `G`: fractal roughness (characteristic scale), m, G > 0.
    - `l_min`: lower cutoff length of the fractal range (the smallest asperity base), m, > 0.
      The elastic stiffness integral diverges at a → 0 for every D (docs/model.md §2), so results
      depend on `l_min`; the default 1 nm is the paper's implied atomic-scale cutoff.
    """

    D: Parameter = eqx.field(converter=as_array)
    G: Parameter = eqx.field(converter=as_array)
    l_min: Parameter = eqx.field(default=1e-9, converter=as_array)

    def __check_init__(self):
        for name in ("D", "G", "l_min"):
            PARAMETERS[name].check(getattr(self, name))


class Material(eqx.Module):
    """The equivalent material of the contact pair.

    **Arguments:**

    - `E`: equivalent (composite) elastic modulus, Pa, > 0.
    - `nu`: Poisson's ratio, 0 ≤ ν < 0.5 (enters the hardness coefficient κ = 0.454 + 0.41 ν, Eq. 6).
    - `H`: hardness of the softer material, Pa, > 0.
    """

    E: Parameter = eqx.field(converter=as_array)
    nu: Parameter = eqx.field(converter=as_array)
    H: Parameter = eqx.field(converter=as_array)

    def __check_init__(self):
        for name in ("E", "nu", "H"):
            PARAMETERS[name].check(getattr(self, name))
