"""Two-scale contact (`bem.solve_layered`): a flat gap on a uniform layer against the layer's own law,
a stiff layer against the plain BEM, a Winkler layer against a dense numpy solve, the tilt stiffness
against the moment of tilted gaps, and derivatives against central differences."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import refused_type

import jaxcontact as jc
from jaxcontact import bem

N, L, E = 16, 1e-3, 1e11  # points a side, m, Pa
X = (np.arange(N) - (N - 1) / 2) * L / N
PARABOLOID = (X[:, None] ** 2 + X[None, :] ** 2) / (2 * 0.05)  # a 50 mm radius, m
LOADS = np.array([5.0, 20.0])  # N
K_LAYER = 3e13  # Pa/m: the layer takes a fraction of the half-space's compliance


@pytest.fixture(scope="module")
def paraboloid():
    return bem.solve_layered(PARABOLOID, L, E, LOADS, bem.WinklerLayer(K_LAYER), substrate=bem.Free())


def test_a_flat_gap_on_a_winkler_layer_is_the_layer_times_the_area():
    solution = bem.solve_layered(np.zeros((N, N)), L, E, LOADS, bem.WinklerLayer(K_LAYER))
    np.testing.assert_allclose(np.asarray(solution.stiffness), K_LAYER * L * L, rtol=1e-12)


# A Persson-like law as a table: closure u0 ln(p/p0), k_n = p/u0 (the models' own laws reach the
# layer the same way, `TabulatedLayer.from_law`, as the derivative test below does).
TABLE_P = np.geomspace(1e4, 1e8, 9)  # Pa
U0 = 1e-6  # m


def table_layer(points=TABLE_P.size):
    """The law, unloading with k_n,dyn = 3 k_n (a flattened roughness)."""
    p = TABLE_P[:points]
    return bem.TabulatedLayer(p, U0 * np.log(p / p[0]), p / U0, 3 * p / U0)


NODES = np.array([3, 6])


@pytest.fixture(scope="module")
def flat_on_a_table():
    # At pressures of the table, where the layer's slopes are the law's own.
    return bem.solve_layered(np.zeros((N, N)), L, E, TABLE_P[NODES] * L * L, table_layer())


def test_a_flat_gap_on_a_tabulated_layer_is_its_law_times_the_area(flat_on_a_table):
    np.testing.assert_allclose(np.asarray(flat_on_a_table.stiffness), TABLE_P[NODES] / U0 * L * L, rtol=1e-10)


def test_a_flat_gap_on_a_tabulated_layer_unloads_with_its_unloading_law_times_the_area(flat_on_a_table):
    expected = 3 * TABLE_P[NODES] / U0 * L * L
    np.testing.assert_allclose(np.asarray(flat_on_a_table.dynamic_stiffness), expected, rtol=1e-10)


def test_a_stiff_layer_is_the_plain_bem(paraboloid):
    stiff = bem.solve_layered(PARABOLOID, L, E, LOADS, bem.WinklerLayer(1e19), substrate=bem.Free())
    plain = bem.solve(-PARABOLOID, L, E, LOADS, substrate=bem.Free())
    np.testing.assert_allclose(np.asarray(stiff.stiffness), np.asarray(plain.stiffness), rtol=1e-4)


def dense_winkler(gap, load, k, k_unloading=None):
    """The same contact by numpy: the free half-space's compliance as a dense matrix (the operator on
    unit pressures), and an active-set iteration on `(C + I s/(E k)) x = Δ − g` with `Σ x` fixed; the
    stiffness with the layer's `k_unloading` on the active set where given."""
    from jaxcontact.bem._operator import Compliance

    s = L / N
    compliance = Compliance.build(N, bem.Free(), jnp.float64)
    C = np.stack([np.asarray(compliance(jnp.asarray(e.reshape(N, N)))).ravel() for e in np.eye(N * N)], axis=1)
    H = C + np.eye(N * N) * E / (s * k)
    g, total = gap.ravel() / s, load / (E * s * s)
    active = np.ones(N * N, bool)
    for _ in range(100):
        A = np.flatnonzero(active)
        system = np.block([[H[np.ix_(A, A)], -np.ones((A.size, 1))], [np.ones((1, A.size)), np.zeros((1, 1))]])
        solution = np.linalg.solve(system, np.r_[-g[A], total])
        x = np.zeros(N * N)
        x[A], approach = solution[:-1], solution[-1]
        residual = H @ x + g - approach
        new = (x > 0) | (~active & (residual < 0))
        if np.array_equal(new, active) and np.all(x >= 0):
            break
        active = new
    if k_unloading is not None:
        H = C + np.eye(N * N) * E / (s * k_unloading)
    inverse = np.linalg.inv(H[np.ix_(A, A)])
    return x.reshape(N, N) * E, approach * s, E * s * inverse.sum()


@pytest.fixture(scope="module")
def dense():
    return [dense_winkler(PARABOLOID, F, K_LAYER) for F in LOADS]


def test_the_pressure_is_a_dense_numpy_solves(paraboloid, dense):
    expected = np.stack([p for p, _, _ in dense])
    np.testing.assert_allclose(np.asarray(paraboloid.pressure), expected, atol=1e-8 * expected.max())


def test_the_stiffness_is_a_dense_numpy_solves(paraboloid, dense):
    np.testing.assert_allclose(np.asarray(paraboloid.stiffness), [K for _, _, K in dense], rtol=1e-8)


def test_the_contact_is_partial(paraboloid):
    assert np.all((np.asarray(paraboloid.contact_fraction) > 0.1) & (np.asarray(paraboloid.contact_fraction) < 0.9))


class ShakenDownWinkler(bem.AbstractLayer):
    """A Winkler layer that unloads with another stiffness (a flattened roughness: stiffer)."""

    stiffness: float
    unloading: float

    def closure(self, pressure):
        return pressure / self.stiffness

    def highest(self):
        return jnp.inf

    def unloads_as_it_loads(self):
        return False

    def unloading_compliance(self, pressure):
        return jnp.full_like(pressure, 1.0 / self.unloading)


def test_the_dynamic_stiffness_is_a_dense_numpy_solves_on_its_contact_set(paraboloid):
    layer = ShakenDownWinkler(K_LAYER, 3 * K_LAYER)
    solution = bem.solve_layered(PARABOLOID, L, E, LOADS, layer, substrate=bem.Free())
    expected = [dense_winkler(PARABOLOID, F, K_LAYER, 3 * K_LAYER)[2] for F in LOADS]
    np.testing.assert_allclose(np.asarray(solution.dynamic_stiffness), expected, rtol=1e-8)


def test_a_layer_that_unloads_as_it_loads_has_its_loading_stiffness_in_service(paraboloid):
    np.testing.assert_array_equal(np.asarray(paraboloid.dynamic_tilt_stiffness), np.asarray(paraboloid.tilt_stiffness))


def test_the_tilt_stiffness_is_the_moments_change_under_a_tilted_gap(paraboloid):
    # Rotating the gap by ±θ about the axis along the columns (lever along the rows) at the same load.
    theta = 1e-7
    arm = X[:, None] * np.ones((1, N))

    def moment(sign):
        tilted = bem.solve_layered(
            PARABOLOID + sign * theta * arm, L, E, LOADS, bem.WinklerLayer(K_LAYER), substrate=bem.Free()
        )
        return np.sum(np.asarray(tilted.pressure) * arm, axis=(1, 2)) * (L / N) ** 2

    central = (moment(-1) - moment(1)) / (2 * theta)
    np.testing.assert_allclose(np.asarray(paraboloid.tilt_stiffness[:, 0]), central, rtol=1e-4)


def test_the_derivatives_match_central_differences():
    def stiffness(log_k, load):
        layer = bem.WinklerLayer(jnp.exp(log_k))
        return bem.solve_layered(PARABOLOID, L, E, jnp.reshape(load, (1,)), layer, substrate=bem.Free()).approach[0]

    x0 = (math.log(K_LAYER), 10.0)
    exact = jax.grad(stiffness, argnums=(0, 1))(*x0)
    h = (1e-5, 1e-4)
    central = [
        (stiffness(x0[0] + h[0], x0[1]) - stiffness(x0[0] - h[0], x0[1])) / (2 * h[0]),
        (stiffness(x0[0], x0[1] + h[1]) - stiffness(x0[0], x0[1] - h[1])) / (2 * h[1]),
    ]
    np.testing.assert_allclose(np.asarray(exact), np.asarray(central), rtol=1e-5)


def test_the_derivative_in_a_tabulated_laws_values_matches_central_differences():
    # The tilt stiffness with respect to the table's closures (all scaled): a model's parameters reach
    # the layer through them (`interface_law`'s own derivatives are checked in test_interface.py).
    def tilt(scale):
        layer = bem.TabulatedLayer(TABLE_P, scale * U0 * np.log(TABLE_P / TABLE_P[0]), TABLE_P / (scale * U0))
        return bem.solve_layered(PARABOLOID, L, E, LOADS, layer, substrate=bem.Free()).tilt_stiffness[0, 0]

    # One program gives the tilt stiffness and its derivative, for the exact derivative and the
    # differences alike.
    tangent = jax.jit(lambda scale: jax.jvp(tilt, (scale,), (jnp.ones_like(scale),)))
    h = 1e-6
    central = (tangent(jnp.asarray(1.0 + h, float))[0] - tangent(jnp.asarray(1.0 - h, float))[0]) / (2 * h)
    _, exact = tangent(jnp.asarray(1.0, float))
    np.testing.assert_allclose(float(exact), float(central), rtol=1e-5)


def test_float32_agrees_with_float64(paraboloid):
    from jaxcontact.numerics import x64

    with x64(False):
        single = bem.solve_layered(
            PARABOLOID.astype(np.float32),
            np.float32(L),
            np.float32(E),
            LOADS.astype(np.float32),
            bem.WinklerLayer(np.float32(K_LAYER)),
            substrate=bem.Free(),
        )
        assert single.stiffness.dtype == jnp.float32
    np.testing.assert_allclose(np.asarray(single.stiffness), np.asarray(paraboloid.stiffness), rtol=1e-3)


@pytest.fixture(scope="module")
def with_a_bad_load():
    solve = jax.jit(lambda f: bem.solve_layered(PARABOLOID, L, E, f, bem.WinklerLayer(K_LAYER), substrate=bem.Free()))
    return solve(jnp.array([LOADS[0], jnp.nan]))


def test_a_traced_bad_load_is_flagged(with_a_bad_load):
    assert int(with_a_bad_load.status[1]) == jc.Status.INVALID_LOAD


def test_a_traced_bad_load_leaves_the_good_one(with_a_bad_load, paraboloid):
    np.testing.assert_allclose(float(with_a_bad_load.stiffness[0]), float(paraboloid.stiffness[0]), rtol=1e-10)


def test_a_layer_that_is_not_one_is_refused():
    with refused_type("layer", "layer = 3.0 must be bem.WinklerLayer"):
        bem.solve_layered(PARABOLOID, L, E, LOADS, 3.0)


def test_a_point_pressed_beyond_the_layers_table_is_flagged():
    # A table to 1 MPa; the loads alone are 5 and 20 MPa over the map.
    solution = bem.solve_layered(PARABOLOID, L, E, LOADS, table_layer(5), substrate=bem.Free())
    assert np.all(np.asarray(solution.status) == jc.Status.LOAD_OUT_OF_RANGE)


@pytest.mark.parametrize(
    "arguments, message",
    [
        ((TABLE_P[::-1], TABLE_P, TABLE_P), r"pressure must be positive and increasing"),
        ((TABLE_P, TABLE_P, TABLE_P, -TABLE_P), r"unloading_stiffness positive \(Pa/m\)"),
        ((TABLE_P, TABLE_P[:-1], TABLE_P), r"shapes \(9,\), \(8,\), \(9,\): give 1-D arrays of one length"),
    ],
)
def test_a_bad_table_is_refused_by_name(arguments, message):
    with pytest.raises(ValueError, match=message):
        bem.TabulatedLayer(*arguments)
