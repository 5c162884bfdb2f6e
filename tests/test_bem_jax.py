"""The JAX boundary-element solve against closed forms (Hertz, a flat punch), against ContactMechanics
on the same heights (elastic and plastic), its derivatives against central differences, float32,
and bad input."""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import BEM_L as L
from helpers import BEM_SETTING

from jaxcontact import bem
from jaxcontact.numerics import x64

pytest.importorskip("ContactMechanics")
SurfaceTopography = pytest.importorskip("SurfaceTopography")

E = BEM_SETTING["E"]
UNIT_LOAD = E * L * L
LOADS = np.array([2e-5, 1e-4, 5e-4]) * UNIT_LOAD


def centred_grid(n):
    x = (np.arange(n) + 0.5) / n - 0.5
    return x[:, None], x[None, :]


@pytest.fixture(scope="module")
def hertz():
    """A paraboloid (R = 1) on a free half-space (E* = 1), loaded to a contact radius of 51 grid spacings."""
    x, y = centred_grid(256)
    a = 0.2
    return a, bem.solve(jnp.asarray(-(x * x + y * y) / 2), 1.0, 1.0, jnp.array([4 * a**3 / 3]), substrate=bem.Free())


def test_hertz_contact_radius(hertz):
    a, sol = hertz
    np.testing.assert_allclose(math.sqrt(float(sol.contact_fraction[0]) / math.pi), a, rtol=5e-3)


def test_hertz_stiffness_is_2Ea(hertz):
    a, sol = hertz
    np.testing.assert_allclose(float(sol.stiffness[0]), 2 * a, rtol=5e-3)


def test_hertz_approach_is_a_squared_over_R(hertz):
    a, sol = hertz
    np.testing.assert_allclose(float(sol.offset[0]), a * a, rtol=5e-3)


def test_a_flat_punch_has_the_stiffness_2Ea():
    """A rigid circular punch of radius a (51 grid spacings): K = 2 E* a (Sneddon)."""
    x, y = centred_grid(256)
    a = 0.2
    heights = jnp.asarray(np.where(x * x + y * y <= a * a, 0.0, -1.0))
    sol = bem.solve(heights, 1.0, 1.0, jnp.array([1e-3]), substrate=bem.Free())
    np.testing.assert_allclose(float(sol.stiffness[0]), 2 * a, rtol=5e-3)


@pytest.fixture(scope="module")
def surface():
    return bem.realisation(1.5, 1e-12, L / 32, L, 128, 0)


@pytest.fixture(scope="module")
def against_contactmechanics(surface):
    """Both solvers on the same 128² periodic surface."""
    mine = bem.solve(jnp.asarray(surface.heights()), L, E, jnp.asarray(LOADS))
    return mine, bem.bem_stiffness(surface, E, LOADS)


def test_the_stiffness_is_contactmechanics_within_1_percent(against_contactmechanics):
    mine, reference = against_contactmechanics
    np.testing.assert_allclose(np.asarray(mine.stiffness), reference.stiffness, rtol=1e-2)


def test_the_contact_fraction_is_contactmechanics_within_1_percent(against_contactmechanics):
    mine, reference = against_contactmechanics
    np.testing.assert_allclose(np.asarray(mine.contact_fraction), reference.contact_fraction, rtol=1e-2)


def test_the_offset_is_contactmechanics(against_contactmechanics):
    """The same discretisation: the same solution, to the solvers' tolerances."""
    mine, reference = against_contactmechanics
    np.testing.assert_allclose(np.asarray(mine.offset), reference.offset, rtol=1e-6)


def test_a_free_half_space_agrees_with_contactmechanics():
    surface = bem.realisation(1.5, 1e-12, L / 16, L, 64, 1)
    topography = SurfaceTopography.Topography(surface.heights(), (L, L), periodic=False)
    load = LOADS[1:2]
    mine = bem.solve(jnp.asarray(surface.heights()), L, E, jnp.asarray(load), substrate=bem.Free())
    reference = bem.bem_stiffness(topography, E, load, substrate=bem.Free())
    np.testing.assert_allclose(float(mine.stiffness[0]), reference.stiffness[0], rtol=1e-2)


class _Unlogged:
    """ContactMechanics's default logger walks the call stack (`inspect.stack`) for each message."""

    pr = st = staticmethod(lambda *args, **kwargs: None)


_UNLOGGED = _Unlogged()


def _contactmechanics_plastic(heights, load, hardness, step=0.02):
    """K of ContactMechanics's plastic system by its central difference in ln F, a fresh surface per solve
    (its plastic system keeps the plastic displacement of each solve in the surface)."""
    from ContactMechanics import PeriodicFFTElasticHalfSpace, make_plastic_system

    n = heights.shape[0]
    offsets = []
    for factor in (math.exp(-step), math.exp(step)):
        topography = SurfaceTopography.PlasticTopography(
            SurfaceTopography.Topography(heights.copy(), (L, L), periodic=True), hardness
        )
        substrate = PeriodicFFTElasticHalfSpace((n, n), E, physical_sizes=(L, L), stiffness_q0=0.0)
        system = make_plastic_system(substrate=substrate, surface=topography)
        solved = system.minimize_proxy(external_force=load * factor, pentol=1e-4 * heights.std() / n, logger=_UNLOGGED)
        offsets.append(solved.offset)
    return 2 * load * math.sinh(step) / (offsets[1] - offsets[0])


@pytest.mark.parametrize("hardness", [3e8, 1e9])
def test_a_hardness_cap_agrees_with_contactmechanics_plastic_system(surface, hardness):
    heights = surface.heights()
    mine = bem.solve(jnp.asarray(heights), L, E, jnp.asarray(LOADS[1:2]), hardness=hardness)
    assert float(mine.plastic_fraction[0]) > 0  # the cap acts
    np.testing.assert_allclose(
        float(mine.stiffness[0]), _contactmechanics_plastic(heights, LOADS[1], hardness), rtol=2e-2
    )


@pytest.fixture(scope="module")
def nearly_all_capped():
    """D = 1.3 at H = 3 GPa (128²): elastic pixel pressures reach tens of GPa, so all but a few contact
    points sit at the cap, where plain capped CG has nothing left to steer and cycles."""
    heights = bem.realisation(1.3, 1e-12, L / 32, L, 128, 0).heights()
    load = 1e-4 * UNIT_LOAD
    return heights, load, bem.solve(jnp.asarray(heights), L, E, jnp.array([load]), hardness=3e9, secant=0.02)


def test_a_contact_nearly_all_at_the_cap_converges(nearly_all_capped):
    _, _, mine = nearly_all_capped
    assert int(mine.status[0]) == 0


def test_a_contact_nearly_all_at_the_cap_is_mostly_plastic(nearly_all_capped):
    _, _, mine = nearly_all_capped
    assert float(mine.plastic_fraction[0]) > 0.8 * float(mine.contact_fraction[0])


def test_a_contact_nearly_all_at_the_cap_agrees_with_contactmechanics(nearly_all_capped):
    """The secant of the same definition as ContactMechanics's plastic system (±2 % in ln F)."""
    heights, load, mine = nearly_all_capped
    np.testing.assert_allclose(
        float(mine.secant_stiffness[0]), _contactmechanics_plastic(heights, load, 3e9), rtol=1e-3
    )


def test_plasticity_softens_the_contact(surface):
    heights = jnp.asarray(surface.heights())
    elastic = bem.solve(heights, L, E, jnp.asarray(LOADS[2:]))
    plastic = bem.solve(heights, L, E, jnp.asarray(LOADS[2:]), hardness=3e8)
    assert float(plastic.stiffness[0]) < 0.95 * float(elastic.stiffness[0])


@functools.cache
def _small():
    return jnp.asarray(bem.realisation(1.5, 1e-12, L / 32, L, 128, 0).heights())


@pytest.fixture(scope="module")
def small():
    return _small()


def _central(f, theta, i, step=1e-6):
    e = jnp.zeros_like(theta).at[i].set(step)
    return (f(theta + e) - f(theta - e)) / (2 * step)


@functools.cache
def _weighted_outputs(hardness):
    """`w · (Σ offset, Σ mean_gap)` and its gradient in θ = (heights' scale, ln E, ln H, ln F), one
    program per hardness for both outputs, the derivatives and the differences alike."""
    loads = jnp.array([1e-4, 3e-4]) * UNIT_LOAD
    heights = _small()

    def f(theta, weights):
        s, log_E, log_H, log_F = theta
        sol = bem.solve(
            s * heights,
            L,
            jnp.exp(log_E),
            loads * jnp.exp(log_F),
            hardness=None if hardness is None else jnp.exp(log_H),
        )
        return weights @ jnp.stack([jnp.sum(sol.offset), jnp.sum(sol.mean_gap)])

    return jax.jit(jax.value_and_grad(f))


@pytest.mark.parametrize("hardness", [None, 3e8], ids=["elastic", "plastic"])
@pytest.mark.parametrize("output", ["offset", "mean_gap"])
def test_gradients_match_central_differences(hardness, output):
    """With respect to a scale factor of the heights, ln E, ln H and ln F."""
    value_and_grad = _weighted_outputs(hardness)
    weights = jnp.array([1.0, 0.0]) if output == "offset" else jnp.array([0.0, 1.0])
    theta = jnp.array([1.0, math.log(E), math.log(3e8), 0.0])
    gradient = value_and_grad(theta, weights)[1]
    differences = jnp.array([_central(lambda t: value_and_grad(t, weights)[0], theta, i) for i in range(4)])
    np.testing.assert_allclose(gradient, differences, rtol=1e-4, atol=1e-6 * float(jnp.max(jnp.abs(differences))))


def test_the_tangent_stiffness_is_proportional_to_the_modulus(small):
    """dK/dE = K/E exactly; the tangent depends on the contact set alone (zero derivative in the heights)."""
    load = jnp.array([1e-4]) * UNIT_LOAD
    K = lambda modulus, s: bem.solve(s * small, L, modulus, load).stiffness[0]  # noqa: E731
    dK_dE, dK_ds = jax.grad(K, argnums=(0, 1))(jnp.asarray(E), 1.0)
    np.testing.assert_allclose(float(dK_dE), float(K(E, 1.0)) / E, rtol=1e-10)
    assert float(dK_ds) == 0.0


def test_float32_agrees_with_float64_within_1e_3(surface):
    heights = surface.heights()
    double = bem.solve(jnp.asarray(heights), L, E, jnp.asarray(LOADS))
    with x64(False):
        single = bem.solve(
            jnp.asarray(heights, jnp.float32), np.float32(L), np.float32(E), jnp.asarray(LOADS, jnp.float32)
        )
        assert single.stiffness.dtype == jnp.float32
        np.testing.assert_allclose(np.asarray(single.stiffness), np.asarray(double.stiffness), rtol=1e-3)


def test_a_batch_of_maps_is_vmapped(small):
    load = jnp.array([1e-4]) * UNIT_LOAD
    batch = jax.vmap(lambda h: bem.solve(h, L, E, load).stiffness)(jnp.stack([small, small[::-1]]))
    np.testing.assert_allclose(
        batch[:, 0], [float(bem.solve(h, L, E, load).stiffness[0]) for h in (small, small[::-1])], rtol=1e-9
    )


def test_a_load_past_full_contact_is_flagged(small):
    sol = bem.solve(small, L, E, jnp.array([1e-4, 1.0]) * UNIT_LOAD)
    np.testing.assert_array_equal(sol.status, [0, 1])
    assert np.isnan(float(sol.stiffness[1])) and np.isfinite(float(sol.stiffness[0]))


def test_a_traced_bad_load_is_flagged_and_the_rest_keeps_finite_gradients(small):
    def f(loads):
        sol = bem.solve(small, L, E, loads)
        return jnp.sum(jnp.where(sol.status == 0, sol.offset, 0.0)), sol.status

    loads = jnp.array([1e-4, jnp.nan, 3e-4]) * UNIT_LOAD
    (value, status), gradient = jax.value_and_grad(f, has_aux=True)(loads)
    np.testing.assert_array_equal(status, [0, 4, 0])
    assert np.all(np.isfinite(np.asarray(gradient)))


@pytest.mark.parametrize(
    "heights, message",
    [
        (np.full((16, 16), np.nan), "NaN or infinite"),
        (np.zeros((4, 4)), "at least 8 points a side"),
    ],
)
def test_bad_maps_are_refused(heights, message):
    with pytest.raises(ValueError, match=message):
        bem.solve(jnp.asarray(heights), L, E, jnp.array([1.0]))


@pytest.mark.parametrize("sizes", [(L, 2.5 * L), (L, L / 2)])
def test_a_map_of_oblong_pixels_or_sides_is_refused_by_the_jax_curve(sizes):
    # The JAX solve's kernel is a square's: on 16 x 16 points over L x 2.5 L its K was 0.92-3.6 times
    # ContactMechanics's, with status ok.
    from SurfaceTopography import Topography

    heights = np.random.default_rng(0).normal(size=(16, 16 if sizes[1] > L else 8)) * 1e-7
    with pytest.raises(ValueError, match="square map of square pixels"):
        bem.jax_curve(Topography(heights, sizes, periodic=True, unit="m"), E, np.array([1e-4]) * UNIT_LOAD)


def test_a_negative_load_is_refused(small):
    with pytest.raises(ValueError, match=r"loads \(N\) = .* is outside its valid range"):
        bem.solve(small, L, E, jnp.array([-1.0]))


def _sorted_sizes(jaxpr) -> set:
    """The operand sizes of every `sort` in `jaxpr` and the programs inside it (loops, branches)."""
    sizes = set()
    for equation in jaxpr.eqns:
        if equation.primitive.name == "sort":
            sizes.add(int(np.prod(equation.invars[0].aval.shape)))
        for value in equation.params.values():
            for inner in value if isinstance(value, (tuple, list)) else (value,):
                if isinstance(inner, jax.extend.core.ClosedJaxpr):
                    sizes |= _sorted_sizes(inner.jaxpr)
                elif isinstance(inner, jax.extend.core.Jaxpr):
                    sizes |= _sorted_sizes(inner)
    return sizes


@pytest.mark.parametrize("hardness, sorts_the_grid", [(None, False), (1e9, True)])
def test_only_a_capped_solve_carries_the_plastic_mixing_step(hardness, sorts_the_grid):
    """The mixing step sorts the grid: under `vmap` a `lax.cond` computes it at every iteration whether
    taken or not, so an elastic solve must not trace it at all."""
    solve = lambda h: bem.solve(h, L, E, jnp.asarray(LOADS[:1]), hardness=hardness).offset  # noqa: E731
    sizes = _sorted_sizes(jax.make_jaxpr(solve)(jnp.zeros((16, 16))).jaxpr)
    assert (16 * 16 in sizes) == sorts_the_grid


def _loops(function, *args) -> int:
    """The `while` loops of `function`'s optimised program (XLA removes those whose results are unused)."""
    return jax.jit(function).lower(*args).compile().as_text().count(" while(")


def test_the_offsets_derivative_adds_no_linear_solve():
    """The secant stiffness and its forward derivative run the same loops (the sweep, the constrained
    iteration, `x1`): the offset's tangent is a dot product with `x1`, not a solve per direction."""
    h = jnp.asarray(np.random.default_rng(0).normal(size=(16, 16)))
    secant = lambda s: bem.solve(s * h, 1.0, 1.0, jnp.array([0.05, 0.1]), secant=0.02).secant_stiffness  # noqa: E731
    assert _loops(lambda s: jax.jvp(secant, (s,), (1.0,)), 1.0) == _loops(secant, 1.0)
