"""A `Scene`: the joint (surface, material, nominal area) and the model to apply to it."""

from __future__ import annotations

import warnings

import equinox as eqx

from ..models.base import AbstractContactModel
from ..numerics.validate import InputError, PlausibilityWarning, as_array, concrete
from ..registry import build_model
from .domain import PARAMETERS, implausible
from .parameters import Material, Parameter, Surface


class Scene(eqx.Module):
    """Everything the load → stiffness map needs besides the loads.

    **Arguments:**

    - `surface`: the `Surface` (D, G, l_min).
    - `material`: the `Material` (E, ν, H).
    - `area`: nominal contact area `A_a`, m², with `l_min² < area`.
    - `model`: the contact model, an object (`Xia2024(interaction=SeriesInteraction())`,
      `JZZ2010()`, any `AbstractContactModel`) or a name of `jaxcontact.MODELS` ("xia2024", the
      default: Xia, Qu & Liu 2024; "jzz2010": Jiang, Zheng & Zhu 2010, MODEL.md §5; "gw":
      Greenwood–Williamson; "persson": Persson's theory, MODEL.md §9).
    - `interaction`, `distribution`, `quadrature`, `quadrature_nodes`, `quadrature_tolerance`,
      `spot_stiffness`: with
      a model *name*, its options by name (`interaction="series"`, `distribution="wk"`,
      `quadrature="gauss-legendre"`, ...), mapped to objects by `jaxcontact.build_model`; see
      `Xia2024` for what each means. With a model object, leave them out.
    - `regime_shares`: whether to split load and stiffness by the model's regimes
      (`Solution.load_share`, `stiffness_share`); with False those fields are None and nothing is
      spent on them.
    - `max_steps`: cap on the a_l solve's Newton/bisection steps (static).
    - `solver_tolerance`: tolerance on `ln a_l`; `None` picks 64 ε of the working dtype (static).

    Float fields (of `surface`, `material` and `area`) are JAX arrays, pytree leaves: differentiate
    with `eqx.filter_grad` or `jax.grad` through `eqx.tree_at`, batch with `jax.vmap`. The model
    and the numerical settings are static: changing them compiles a different program.
    """

    surface: Surface
    material: Material
    area: Parameter
    model: AbstractContactModel
    regime_shares: bool = eqx.field(static=True)
    max_steps: int = eqx.field(static=True)
    solver_tolerance: float | None = eqx.field(static=True)

    def __init__(
        self,
        surface: Surface,
        material: Material,
        area,
        model: AbstractContactModel | str = "xia2024",
        interaction=None,
        distribution=None,
        regime_shares: bool = True,
        quadrature_nodes: int | None = None,
        quadrature=None,
        quadrature_tolerance: float | None = None,
        spot_stiffness=None,
        max_steps: int = 64,
        solver_tolerance: float | None = None,
    ):
        if not isinstance(surface, Surface):
            raise InputError(f"surface must be a jaxcontact.Surface, got {type(surface).__name__}")
        if not isinstance(material, Material):
            raise InputError(f"material must be a jaxcontact.Material, got {type(material).__name__}")
        if not isinstance(regime_shares, bool):
            raise InputError(f"regime_shares = {regime_shares!r} must be true or false")
        if isinstance(max_steps, bool) or not isinstance(max_steps, int) or not 1 <= max_steps <= 10_000:
            raise InputError(f"max_steps = {max_steps!r} must be an integer in [1, 10000]")
        if solver_tolerance is not None and not 0.0 < solver_tolerance < 1e-2:
            raise InputError(f"solver_tolerance = {solver_tolerance!r} must be None or in (0, 0.01)")
        self.surface = surface
        self.material = material
        self.area = as_array(area)
        self.model = build_model(
            model,
            interaction=interaction,
            distribution=distribution,
            quadrature=quadrature,
            quadrature_nodes=quadrature_nodes,
            quadrature_tolerance=quadrature_tolerance,
            spot_stiffness=spot_stiffness,
        )
        self.regime_shares = regime_shares
        self.max_steps = max_steps
        self.solver_tolerance = solver_tolerance

    def with_options(self, **options) -> Scene:
        """The same joint with other choices: `options` as `Scene` takes them, by name
        (`interaction="none"`, `regime_shares=False`, ...); the rest as in this scene.

        The model's options are carried by name (`AbstractContactModel.options`), so give a
        model object, or every setting of a non-default quadrature, where that matters. A new
        `model` starts from its own defaults.
        """
        current = dict(
            regime_shares=self.regime_shares, max_steps=self.max_steps, solver_tolerance=self.solver_tolerance
        )
        if "model" not in options:
            current.update(self.model.options())
            if "interaction" in options and "quadrature" not in options:
                # The default quadrature depends on the interaction ("power-series" is for "paper" only).
                current.pop("quadrature", None)
        return Scene(self.surface, self.material, self.area, **{**current, **options})

    def __check_init__(self):
        PARAMETERS["area"].check(self.area)
        for message in implausible(self):
            # A unit mistake (E in GPa) gives NaN with a status, not an error: say so where it is made.
            warnings.warn(message, PlausibilityWarning, stacklevel=3)
        l_min, area = concrete(self.surface.l_min), concrete(self.area)
        if l_min is not None and area is not None and not (l_min**2 < area).all():
            raise InputError(
                f"l_min = {l_min} m is too large for area = {area} m²: l_min² must be smaller than the nominal area"
            )


def stack_scenes(scenes) -> Scene:
    """Stack scenes that differ only in float values into one batched scene (for `jax.vmap`).

    Every float field becomes an array with a leading batch axis; the static choices must agree.
    """
    import jax
    import jax.numpy as jnp

    scenes = list(scenes)
    if not scenes:
        raise InputError("stack_scenes needs at least one scene")
    structures = {jax.tree.structure(s) for s in scenes}
    if len(structures) != 1:
        raise InputError("stack_scenes: the scenes differ in model, interaction, distribution or settings")
    return jax.tree.map(lambda *xs: jnp.stack([jnp.asarray(x) for x in xs]), *scenes)
