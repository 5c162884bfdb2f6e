"""The joint as an interface law per unit area, for the integration points of a finite-element or
structural model (docs/applications.md, "Interface laws for FE"): nominal pressure p ↦ closure δ(p),
normal stiffness k_n(p) = K/A_a and contact fraction, and the pressure–overclosure table that CalculiX
and Abaqus read."""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Int

from ..core import Outputs, Scene, solve
from ..numerics import InputError, check_positive
from ..physics import Unloading, mindlin_ratio
from ..quantities import Status
from ._approach_sum import approach_quadrature


class InterfaceLaw(eqx.Module):
    """Result of `interface_law`: per nominal pressure, the interface's closure and stiffness per unit area.

    **Fields:**

    - `pressure`: nominal pressure p = F/A_a, Pa.
    - `reference_pressure`: the pressure p0 at which the closure is zero, Pa.
    - `closure`: δ(p) − δ(p0), the approach of the two surfaces' mean planes (m) beyond its value at
      p0 (docs/model.md §6); negative below p0.
    - `normal_stiffness`: k_n(p) = K(p A_a)/A_a, the loading tangent per unit area, Pa/m (N/m per m²).
    - `dynamic_stiffness`: k_n,dyn(p), the initial unloading tangent per unit area about p reached by
      loading (`jc.dynamic_stiffness`; docs/in-service.md), Pa/m.
    - `tangential_stiffness`: k_t(p), Mindlin's full-stick tangential stiffness per unit area
      (`jc.tangential_stiffness`), Pa/m: the stick slope of an FE code's friction law.
    - `contact_fraction`: A_r/A_a.
    - `status`: per point, as `Solution.status` (0 = ok); where it is not 0 the other fields are NaN.
    - `unloading_status`: per point, the status of the unloading state behind `dynamic_stiffness` and
      `tangential_stiffness` (NaN where it is not 0); `INVALID_PARAMETERS` throughout for a model
      without an unloading law.
    - `nominal_area`: the scene's A_a (m²): a fractal model's law per unit area depends on it (its
      largest spot grows with the area), so a law belongs to the nominal area it was computed for.
    """

    pressure: Float[Array, " pressures"]
    reference_pressure: Float[Array, ""]
    closure: Float[Array, " pressures"]
    normal_stiffness: Float[Array, " pressures"]
    dynamic_stiffness: Float[Array, " pressures"]
    tangential_stiffness: Float[Array, " pressures"]
    contact_fraction: Float[Array, " pressures"]
    status: Int[Array, " pressures"]
    unloading_status: Int[Array, " pressures"]
    nominal_area: Float[Array, ""]
    # The per-pressure fields, in the order the CSV and the command's table give them.
    columns: ClassVar[tuple[str, ...]] = (
        "pressure",
        "closure",
        "normal_stiffness",
        "dynamic_stiffness",
        "tangential_stiffness",
        "contact_fraction",
        "status",
        "unloading_status",
    )


def interface_law(
    scene: Scene,
    pressures: Float[ArrayLike, " pressures"],
    reference_pressure: float | Float[ArrayLike, ""] | None = None,
    *,
    nodes: int | None = None,
    in_service: bool = True,
) -> InterfaceLaw:
    """The interface law of `scene` per unit area at nominal `pressures`.

    **Arguments:**

    - `scene`: the joint (surface, material, nominal area A_a) and its model.
    - `pressures`: nominal pressures p (Pa), 1-D, positive and finite.
    - `reference_pressure`: p0 (Pa), where the closure is zero (default: the smallest of `pressures`,
      which must then be concrete). Persson's closure grows without bound as p → 0 (p ∝ e^(−u/u0)),
      so a closure is always relative to a stated pressure.
    - `nodes`: Gauss–Legendre nodes per piece of the closure's quadrature (`approach_quadrature`, whose
      pieces run between consecutive pressures, p0 and the model's kinks). Default: from the spacing
      of concrete pressures (`quadrature_nodes`), which keeps the closure within ~1e-12 of a 16-node
      rule; 8 for traced ones.
    - `in_service`: also the unloading and tangential stiffness (one more solve, for a model that
      does not unload as it loads); False leaves those columns NaN with `unloading_status`
      `INVALID_PARAMETERS`, for a caller that wants the closure alone.

    **Returns:** an `InterfaceLaw`. Differentiable with respect to the pressures and the scene's
    parameters; `vmap` over scenes or pressure arrays as `solve`.
    """
    if not isinstance(in_service, bool):
        raise InputError(f"in_service = {in_service!r} must be true or false")
    pressures = jnp.asarray(pressures)
    if pressures.ndim != 1 or pressures.size == 0:
        raise InputError(f"pressures has shape {pressures.shape}: give a 1-D array of nominal pressures (Pa)")
    # Checked here, so that a message speaks of pressures in Pa (the solve's own check names loads in N).
    check_positive("pressures", pressures, "Pa", "pressure")
    if reference_pressure is None:
        if isinstance(pressures, jax.core.Tracer):
            raise InputError("reference_pressure = None needs concrete pressures: give it when tracing them")
        reference_pressure = float(np.min(np.asarray(pressures)))
    else:
        check_positive("reference_pressure", reference_pressure, "Pa", "pressure")
    if nodes is None:
        nodes = 8 if isinstance(pressures, jax.core.Tracer) else quadrature_nodes(pressures, reference_pressure)
    area = scene.area
    loads = pressures * area
    solution = solve(scene, loads)
    closure = approach_quadrature(scene, loads, reference_pressure * area, nodes=nodes)
    status = jnp.where(solution.status != Status.OK, solution.status, closure.status)
    ok = status == Status.OK
    dynamic, unloading_status = _unloading(scene, loads, status, solution.stiffness, in_service)
    unloaded = unloading_status == Status.OK
    return InterfaceLaw(
        pressure=pressures.astype(solution.stiffness.dtype),
        reference_pressure=jnp.asarray(reference_pressure, solution.stiffness.dtype),
        closure=jnp.where(ok, closure.approach, jnp.nan),
        normal_stiffness=jnp.where(ok, solution.stiffness / area, jnp.nan),
        dynamic_stiffness=jnp.where(unloaded, dynamic / area, jnp.nan),
        tangential_stiffness=jnp.where(unloaded, mindlin_ratio(scene.material.nu) * dynamic / area, jnp.nan),
        contact_fraction=jnp.where(ok, solution.real_area / area, jnp.nan),
        status=status,
        unloading_status=unloading_status,
        nominal_area=jnp.asarray(area, solution.stiffness.dtype),
    )


_UNLOADING = Outputs(regime_shares=False, stiffness=Unloading())


def _unloading(scene: Scene, loads, status, loading, wanted: bool):
    """The unloading stiffness (N/m) at `loads` and its status, which is the loading `status` where that
    is not ok; the `loading` stiffness itself for a model that unloads as it loads (no second solve);
    `INVALID_PARAMETERS` where they are not `wanted`."""
    if not wanted:
        return jnp.full(loads.shape, jnp.nan), jnp.full(loads.shape, Status.INVALID_PARAMETERS, jnp.int32)
    if scene.model.unloads_as_it_loads():
        return loading, status
    unloading = solve(scene, loads, outputs=_UNLOADING)
    return unloading.stiffness, jnp.where(status != Status.OK, status, unloading.status).astype(jnp.int32)


# The widest step in ln p (between consecutive pressures and p0) up to which 2 and 4 Gauss–Legendre
# nodes per piece give the closure within ~1e-12 of a 16-node rule. Measured on the Table 1 scene with
# the seed model, JZZ, GW and Persson, 10 to 1000 pressures over four decades: 2 nodes 4e-13 at
# 0.009 (2e-10 at 0.046); 4 nodes 7e-13 at 0.24 (2e-8 at 1.0); 8 nodes 3e-14 at 1.0.
FEWER_NODES = ((0.01, 2), (0.25, 4))


def quadrature_nodes(pressures, reference_pressure) -> int:
    """Nodes per piece for the closure at concrete `pressures` from `reference_pressure`: the fewest
    that `FEWER_NODES` allows for the widest step in ln p, else 8."""
    if isinstance(reference_pressure, jax.core.Tracer):
        return 8
    log_p = np.log(np.unique(np.append(np.asarray(pressures, dtype=float), float(reference_pressure))))
    widest = float(np.max(np.diff(log_p))) if log_p.size > 1 else 0.0
    return next((n for width, n in FEWER_NODES if widest <= width), 8)
