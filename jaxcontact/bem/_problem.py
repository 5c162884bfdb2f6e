"""A map in grid units, the problem every boundary-element solve works on (`_operator`)."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from ._fft import AbstractFFT, LocalFFT
from ._operator import AbstractSubstrate, Compliance
from ._tangential import tangential_compliance


class GridProblem(eqx.Module):
    """A map in grid units (`_operator`): its compliance, heights over `scale` (their rms, or 1 for a
    flat map), the hardness cap, and the factors back to SI: a load in grid units times
    `load_unit` is newtons, an offset times `scale` metres, a tangent times `stiffness_unit` N/m."""

    compliance: Compliance
    tangential: Compliance | None
    heights: Float[Array, "n n"]
    cap: Float[ArrayLike, ""]
    scale: Float[ArrayLike, ""]
    load_unit: Float[ArrayLike, ""]
    stiffness_unit: Float[ArrayLike, ""]
    capped: bool = eqx.field(static=True)
    preconditioned: bool = eqx.field(static=True, default=True)

    @classmethod
    def build(
        cls,
        heights,
        size,
        modulus,
        hardness,
        substrate: AbstractSubstrate,
        preconditioned: bool = True,
        nu=None,
        fft: AbstractFFT = LocalFFT(),
    ) -> GridProblem:
        """`hardness` None is the elastic contact (known before tracing: the iteration then has no
        plastic branch to carry); `preconditioned`, the iteration's search (`_ccg.contact_cg`); `nu`,
        None or Poisson's ratio for the tangential stiffness in full stick; `fft`, where the FFTs run
        (`_fft`), the heights laid out for it."""
        heights = fft.place(heights)
        n = heights.shape[-1]
        rms = jax.lax.stop_gradient(jnp.std(heights))
        scale = jnp.where(rms > 0, rms, 1.0)  # a flat map (a punch) is in its own units
        spacing = size / n
        if hardness is None:
            cap = jnp.asarray(jnp.inf, heights.dtype)
        else:
            cap = hardness * spacing / (modulus * scale)
        compliance = Compliance.build(n, substrate, heights.dtype, fft)
        tangential = None if nu is None else tangential_compliance(compliance, substrate, nu)
        unit = modulus * spacing
        capped = hardness is not None
        return cls(compliance, tangential, heights / scale, cap, scale, unit * scale, unit, capped, preconditioned)
