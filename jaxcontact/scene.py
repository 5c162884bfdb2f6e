"""A `Scene`: the joint (surface, material, nominal area) and the model choices to apply to it."""

from __future__ import annotations

import equinox as eqx

from ._validate import as_float, check_choice, check_range, concrete
from .distribution import DISTRIBUTIONS
from .interaction import INTERACTION_SIGNS
from .quadrature import QUADRATURES
from .parameters import Material, Parameter, Surface

MODELS = ("xia2024", "jzz2010")
INTERACTIONS = tuple(INTERACTION_SIGNS)


class Scene(eqx.Module):
    """Everything the load → stiffness map needs besides the loads.

    **Arguments:**

    - `surface`: the `Surface` (D, G, l_min).
    - `material`: the `Material` (E, ν, H).
    - `area`: nominal contact area `A_a`, m², with `l_min² < area`.
    - `model`: "xia2024" (Xia, Qu & Liu 2024, the default) or "jzz2010" (Jiang, Zheng & Zhu 2010,
      the comparator of the paper's Figs. 7–8, MODEL.md §5).
    - `interaction`: "paper" (default for xia2024, `ω = ξ - σ` as Eqs. 23–26 print), "series"
      (`ω = ξ + σ`) or "none"; xia2024 only (jzz2010 takes "none" or nothing).
    - `distribution`: "mb" (Majumdar–Bhushan, Eq. 30) or "wk" (Wang–Komvopoulos correction).
    - `regime_shares`: whether to split load and stiffness by regime (`Solution.load_share`,
      `stiffness_share`); with False those fields are None and nothing is spent on them.
    - `quadrature`: how the one integral without a closed form, the interaction part of the
      stiffness, is done. "power-series" (the default for "paper"): its pole term summed to
      round-off (`pole_integral`), no nodes. "gauss-legendre" (the default for "series"):
      `quadrature_nodes` fixed nodes per regime. "adaptive": quadax Gauss–Kronrod to relative
      `quadrature_tolerance`. See `jaxcontact accuracy` for what each costs.
    - `quadrature_nodes`: Gauss–Legendre nodes per regime (static). For "paper", 16 are within
      3e-12 of an mpmath reference up to 0.9998 of the breakdown load and 24 reach K's own
      conditioning there.
    - `max_steps`: cap on the a_l solve's Newton/bisection steps (static).
    - `solver_tolerance`: tolerance on `ln a_l`; `None` picks 64 ε of the working dtype (static).

    Float fields (of `surface`, `material` and `area`) are pytree leaves: differentiate with
    respect to them with `eqx.tree_at`, batch over them with `jax.vmap`. The choices and the
    numerical settings are static: changing them compiles a different program.
    """

    surface: Surface
    material: Material
    area: Parameter
    model: str = eqx.field(static=True)
    interaction: str = eqx.field(static=True)
    distribution: str = eqx.field(static=True)
    regime_shares: bool = eqx.field(static=True)
    quadrature_nodes: int = eqx.field(static=True)
    quadrature: str = eqx.field(static=True)
    quadrature_tolerance: float = eqx.field(static=True)
    max_steps: int = eqx.field(static=True)
    solver_tolerance: float | None = eqx.field(static=True)

    def __init__(self, surface: Surface, material: Material, area, model: str = "xia2024",
                 interaction: str | None = None, distribution: str = "mb", regime_shares: bool = True,
                 quadrature_nodes: int = 16, quadrature: str | None = None, quadrature_tolerance: float = 1e-10,
                 max_steps: int = 64, solver_tolerance: float | None = None):
        if not isinstance(surface, Surface):
            raise ValueError(f"surface must be a jaxcontact.Surface, got {type(surface).__name__}")
        if not isinstance(material, Material):
            raise ValueError(f"material must be a jaxcontact.Material, got {type(material).__name__}")
        check_choice("model", model, MODELS)
        if interaction is None:
            interaction = "paper" if model == "xia2024" else "none"
        check_choice("interaction", interaction, INTERACTIONS)
        if model == "jzz2010" and interaction != "none":
            raise ValueError(f"interaction = {interaction!r} applies to model 'xia2024' only; "
                             "model 'jzz2010' has no interaction (use 'none' or leave it out)")
        check_choice("distribution", distribution, DISTRIBUTIONS)
        if not isinstance(regime_shares, bool):
            raise ValueError(f"regime_shares = {regime_shares!r} must be true or false")
        if not isinstance(quadrature_nodes, int) or not 2 <= quadrature_nodes <= 1024:
            raise ValueError(f"quadrature_nodes = {quadrature_nodes!r} must be an integer in [2, 1024]")
        if quadrature is None:
            quadrature = "power-series" if interaction == "paper" else "gauss-legendre"
        check_choice("quadrature", quadrature, QUADRATURES)
        if quadrature == "power-series" and interaction not in ("paper", "none"):
            raise ValueError(f"quadrature = 'power-series' applies to interaction 'paper' only (got interaction = "
                             f"{interaction!r}); use 'gauss-legendre' or 'adaptive'")
        if not 0.0 < quadrature_tolerance < 1e-1:
            raise ValueError(f"quadrature_tolerance = {quadrature_tolerance!r} must be in (0, 0.1)")
        if not isinstance(max_steps, int) or not 1 <= max_steps <= 10_000:
            raise ValueError(f"max_steps = {max_steps!r} must be an integer in [1, 10000]")
        if solver_tolerance is not None and not 0.0 < solver_tolerance < 1e-2:
            raise ValueError(f"solver_tolerance = {solver_tolerance!r} must be None or in (0, 0.01)")
        self.surface = surface
        self.material = material
        self.area = as_float(area)
        self.model = model
        self.interaction = interaction
        self.distribution = distribution
        self.regime_shares = regime_shares
        self.quadrature_nodes = quadrature_nodes
        self.quadrature = quadrature
        self.quadrature_tolerance = quadrature_tolerance
        self.max_steps = max_steps
        self.solver_tolerance = solver_tolerance

    def __check_init__(self):
        check_range("area", self.area, 0.0, meaning="nominal contact area, m²")
        l_min, area = concrete(self.surface.l_min), concrete(self.area)
        if l_min is not None and area is not None and not (l_min**2 < area).all():
            raise ValueError(f"l_min = {l_min} m is too large for area = {area} m²: "
                             "l_min² must be smaller than the nominal area")


def stack_scenes(scenes) -> Scene:
    """Stack scenes that differ only in float values into one batched scene (for `jax.vmap`).

    Every float field becomes an array with a leading batch axis; the static choices must agree.
    """
    import jax
    import jax.numpy as jnp

    scenes = list(scenes)
    if not scenes:
        raise ValueError("stack_scenes needs at least one scene")
    structures = {jax.tree.structure(s) for s in scenes}
    if len(structures) != 1:
        raise ValueError("stack_scenes: the scenes differ in model, interaction, distribution or settings")
    return jax.tree.map(lambda *xs: jnp.stack([jnp.asarray(x) for x in xs]), *scenes)
