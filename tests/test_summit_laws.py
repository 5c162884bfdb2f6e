"""Measured asperities with Kogut–Etsion elastic–plastic summits (`jc.KogutEtsionSummits`), and
summits given by their initial gaps (`MeasuredAsperities.from_gaps`), against scipy's quadrature of
the Kogut–Etsion fits written out from the paper, central differences and the fully plastic closed
form; on the Brake–Reuss joint's measured statistics where ../shared/data is present."""

import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_measured_asperities import AREA, ETA, GAUSSIAN, HEIGHTS, JOINT, E, R, ScipyGW, scene_of

import jaxcontact as jc
from jaxcontact import bem
from jaxcontact.numerics import x64

NU = 0.3
HARDNESS = 1e9  # Pa: ω_c = 8.2 nm, so the table's 2 µm reach every band (ω/ω_c up to ~240)
LOADS = np.array([0.3, 3.0, 30.0, 3000.0])  # N; the last presses the flat below the lowest summit


def kogut_etsion(w, radius=R, E=E, H=HARDNESS, nu=NU):
    """One summit's (load, area) at interference w: Kogut & Etsion (2002), their Table/Eqs. as printed."""
    kappa = 0.454 + 0.41 * nu
    w_c = (math.pi * kappa * H / (2 * E)) ** 2 * radius
    A_c = math.pi * radius * w_c
    P_c = 2 / 3 * kappa * H * A_c
    x = w / w_c
    if x < 1:
        return 4 / 3 * E * math.sqrt(radius) * w**1.5, math.pi * radius * w
    if x < 6:
        return 1.03 * P_c * x**1.425, 0.93 * A_c * x**1.136
    if x < 110:
        return 1.40 * P_c * x**1.263, 0.94 * A_c * x**1.146
    return H * 2 * math.pi * radius * w, 2 * math.pi * radius * w


def breaks(radius=R, E=E, H=HARDNESS, nu=NU):
    w_c = (math.pi * (0.454 + 0.41 * nu) * H / (2 * E)) ** 2 * radius
    return (w_c, 6 * w_c, 110 * w_c)


def plastic_scene(heights=HEIGHTS, pdf=GAUSSIAN, H=HARDNESS, **kw):
    scene = scene_of(jc.MeasuredAsperities(R, ETA, heights, pdf, summits=jc.KogutEtsionSummits()), **kw)
    return eqx.tree_at(lambda s: s.material.H, scene, H)


@pytest.fixture(scope="module")
def reference():
    return ScipyGW(HEIGHTS, GAUSSIAN, R, ETA, E, AREA, summit=kogut_etsion, breaks=breaks())


@pytest.fixture(scope="module")
def solved():
    scene = plastic_scene()
    return (
        jc.solve(scene, LOADS, outputs=jc.Outputs(regime_shares=True)),
        jc.dynamic_stiffness(scene, LOADS),
        jc.tangential_stiffness(scene, LOADS),
    )


def test_every_band_of_the_fits_carries_load(solved):
    shares = np.asarray(solved[0].load_share)[-1]
    assert np.all(shares > 1e-5), shares


@pytest.fixture(scope="module")
def law():
    return jc.interface_law(plastic_scene(), np.geomspace(*LOADS[[0, 2]], 21) / AREA)


def test_the_interface_closure_is_the_change_of_scipys_separation(law, reference):
    """`jc.interface_law` integrates dp/k_n: the fits' jumps in K must add up to the flat's travel,
    by brentq on scipy's load (0.3 → 30 N)."""
    expected = reference.separation(LOADS[0]) - reference.separation(LOADS[2])
    np.testing.assert_allclose(float(law.closure[-1] - law.closure[0]), expected, rtol=1e-6)


def test_a_layer_from_the_law_unloads_with_its_dynamic_stiffness(law):
    """`bem.TabulatedLayer.from_law` carries k_n,dyn (the two-scale contact's dynamic stiffness)."""
    layer = bem.TabulatedLayer.from_law(law)
    np.testing.assert_allclose(layer.unloading_compliance(law.pressure), 1 / law.dynamic_stiffness, rtol=1e-12)


def test_the_loading_stiffness_is_central_differences_of_scipys_load(solved, reference):
    """K = −dF/dd, the jumps of the fits included, against scipy's F at d ± h."""

    def stiffness(F):
        d = reference.separation(F)
        h = 1e-5 * (d if d > 0 else 1e-6)
        return -(reference.load(d + h) - reference.load(d - h)) / (2 * h)

    np.testing.assert_allclose(solved[0].stiffness, [stiffness(F) for F in LOADS], rtol=1e-6)


def test_the_unloading_stiffness_is_sneddons_sum_at_the_top(solved, reference):
    """Each summit unloads with 2E a of its contact radius at the top, a = √(A/π) (EKK 2005)."""
    expected = [
        reference.summed(lambda w: 2 * E * math.sqrt(kogut_etsion(w)[1] / math.pi), reference.separation(F))
        for F in LOADS
    ]
    np.testing.assert_allclose(solved[1].stiffness, expected, rtol=1e-8)


def test_the_real_area_is_scipys(solved, reference):
    expected = [reference.summed(lambda w: kogut_etsion(w)[1], reference.separation(F)) for F in LOADS]
    np.testing.assert_allclose(solved[0].real_area, expected, rtol=1e-8)


def test_plastic_summits_unload_stiffer_than_they_load(solved):
    assert np.all(np.asarray(solved[1].stiffness) > 1.4 * np.asarray(solved[0].stiffness))


def test_the_tangential_stiffness_is_mindlins_ratio_of_the_unloading_one(solved):
    ratio = 2 * (1 - NU) / (2 - NU)
    np.testing.assert_allclose(solved[2].stiffness, ratio * np.asarray(solved[1].stiffness), rtol=1e-12)


def test_fully_plastic_summits_carry_the_hardness_over_their_area():
    """H so low that every summit in contact is past 110 ω_c bar the lowest 1e-4 of them: F = H A_r."""
    solution = jc.solve(plastic_scene(H=1e7), 0.3)
    np.testing.assert_allclose(float(solution.real_area) * 1e7, 0.3, rtol=2e-4)


def test_the_gradients_in_hardness_and_radius_are_central_differences():
    scene = plastic_scene()

    # One compiled program gives K and its gradient, for the exact derivatives and the differences alike.
    @jax.jit
    @functools.partial(jax.value_and_grad, argnums=(0, 1))
    def K(H, radius):
        moved = eqx.tree_at(lambda s: (s.material.H, s.model.radius), scene, (H, radius))
        return jc.solve(moved, 3.0).stiffness

    # Strongly typed float64 throughout: a weakly typed argument (`jnp.asarray(1.0)`) is another program.
    x0 = (jnp.asarray(HARDNESS, float), jnp.asarray(R, float))
    grad = K(*x0)[1]
    for i, h in enumerate((1e-6 * HARDNESS, 1e-6 * R)):
        step = [jnp.zeros(()), jnp.zeros(())]
        step[i] = jnp.asarray(h, float)
        up, down = K(*(x + s for x, s in zip(x0, step)))[0], K(*(x - s for x, s in zip(x0, step)))[0]
        np.testing.assert_allclose(grad[i], (up - down) / (2 * h), rtol=1e-5)


def test_float32_agrees_with_float64(solved):
    with x64(False):
        single = jc.solve(plastic_scene(), LOADS.astype(np.float32)).stiffness
    np.testing.assert_allclose(single, solved[0].stiffness, rtol=2e-4)


def test_the_friction_loop_stick_slope_is_the_tangential_stiffness(solved):
    cycle = jc.tangential_cycle(plastic_scene(), 3.0, jnp.asarray([1e-9, 1e-8]), 0.3)
    np.testing.assert_allclose(float(cycle.stick_stiffness), float(solved[2].stiffness[1]), rtol=1e-10)


def test_a_pdf_of_gaps_is_read_from_the_first_summits_to_touch():
    """A skewed PDF of gaps g (dense near g = 0): F(δ) = η A ∫ (4/3) E √R (δ − g)^(3/2) φ(g) dg by scipy."""
    gaps = HEIGHTS
    pdf = np.exp(-gaps / 0.3e-6)
    model = jc.MeasuredAsperities.from_gaps(R, ETA, gaps, pdf)
    reference = ScipyGW(gaps[-1] - gaps[::-1], pdf[::-1], R, ETA, E, AREA)
    expected = [reference.scale * 2 * reference.J(0.5, reference.separation(F)) for F in LOADS[:3]]
    np.testing.assert_allclose(jc.solve(scene_of(model), LOADS[:3]).stiffness, expected, rtol=1e-8)


@pytest.mark.skipif(not JOINT.is_file(), reason=f"{JOINT} is absent: the measured joint data live beside the project")
def test_the_brake_reuss_joint_with_plastic_summits_is_scipys():
    """The measured statistics (Porter & Brake 2023; gaps as tmdsimpy reads them) over a patch of 362
    summits at 12.25 kN, H = 2.8 × the 331.7 MPa yield stress of tmdsimpy's example."""
    from scipy import io

    data = io.loadmat(JOINT)
    z_max = data["z_max"].item()
    gaps, pdf = data["normzinterp"].ravel() * z_max, data["pzinterp"].ravel() / z_max
    radius, density = data["Re"].item(), data["area_density"].item()
    E_star, H, area = 192.31e9 / (2 * (1 - NU**2)), 2.8 * 331.7e6, 362 / density
    model = jc.MeasuredAsperities.from_gaps(radius, density, gaps, pdf, summits=jc.KogutEtsionSummits())
    scene = eqx.tree_at(lambda s: s.material.H, scene_of(model, area=area, E=E_star), H)
    summit = lambda w: kogut_etsion(w, radius, E_star, H)  # noqa: E731
    reference = ScipyGW(z_max - gaps[::-1], pdf[::-1], radius, density, E_star, area, summit, breaks(radius, E_star, H))
    d = reference.separation(12250.0)
    expected = reference.summed(lambda w: 2 * E_star * math.sqrt(summit(w)[1] / math.pi), d)
    np.testing.assert_allclose(float(jc.dynamic_stiffness(scene, 12250.0).stiffness), expected, rtol=1e-7)


def test_a_traced_bad_load_is_flagged_and_leaves_the_others_and_their_derivative(solved):
    scene = plastic_scene()

    @jax.jit
    def solve(H):
        solution = jc.solve(eqx.tree_at(lambda s: s.material.H, scene, H), jnp.array([3.0, jnp.nan]))
        return solution.stiffness, solution.status

    (values, status), (tangent, _) = jax.jvp(solve, (jnp.asarray(HARDNESS),), (jnp.asarray(1.0),))
    assert int(status[1]) == jc.Status.INVALID_LOAD
    np.testing.assert_allclose(float(values[0]), float(solved[0].stiffness[1]), rtol=1e-12)
    assert np.isfinite(float(tangent[0])) and float(tangent[0]) != 0.0
