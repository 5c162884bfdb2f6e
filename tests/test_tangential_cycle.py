"""Partial slip and friction loops (`jc.tangential_cycle`): one spot's Cattaneo–Mindlin loop against
the Mindlin–Deresiewicz closed form and a quadrature of its Masing branches; a joint of fully plastic
spots against scipy's quadrature of the same spots; the limits (full stick, small-amplitude
dissipation ∝ u₀³, macroslip at μF); derivatives against central differences; float32; bad input."""

import functools
import math
import pathlib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_scene, refused_type
from scipy import integrate, optimize

import jaxcontact as jc
from jaxcontact.numerics import x64
from jaxcontact.physics._mindlin import backbone, loop_energy, masing_branches

MU = 0.3
# The D = 1.5 surface at H = 3 GPa: every spot fully plastic (P = H a), unloading with Sneddon's 2E√(a/π).
PLASTIC = dict(TABLE1, D=1.5, G=1e-12, l_min=1e-6, H=3e9, area=1e-4)
PRELOAD = 1e-6 * PLASTIC["E"] * PLASTIC["area"]
AMPLITUDES = np.array([1e-9, 1e-8, 3e-8, 1e-7, 3e-7, 1e-6])  # m: all stuck → all sliding


def mindlin_deresiewicz(x):
    """`W/(μP u*)` of one sphere cycled to `x = u₀/u*` in its force form (Mindlin & Deresiewicz 1953;
    Johnson 1985, Eq. 7.60, with Johnson's compliance written as u*): with `q = Q₀/μP`,
    `(24/5)[1 − (1 − q)^{5/3} − (5q/6)(1 + (1 − q)^{2/3})]`; `4x − 16/5` in gross slip."""
    if x >= 1:
        return 4 * x - 3.2
    q = 1 - (1 - x) ** 1.5
    return 4.8 * (1 - (1 - q) ** (5 / 3) - (5 * q / 6) * (1 + (1 - q) ** (2 / 3)))


@pytest.mark.parametrize("x", [0.05, 0.3, 0.7, 0.95, 1.0, 2.5])
def test_one_spots_loop_energy_is_mindlin_deresiewicz(x):
    np.testing.assert_allclose(float(loop_energy(x)), mindlin_deresiewicz(x), rtol=1e-12)


@pytest.mark.parametrize("x", [0.3, 0.95, 2.5])
def test_one_spots_loop_energy_is_the_area_between_its_masing_branches(x):
    def gap(u):
        rising, falling = masing_branches(u, x, backbone)
        return float(rising - falling)

    area = integrate.quad(gap, -x, x, epsabs=0, epsrel=1e-12, limit=200)[0]
    np.testing.assert_allclose(float(loop_energy(x)), area, rtol=1e-9)


def test_one_spots_small_amplitude_loop_keeps_its_precision():
    """x³/2 (1 + x/4 + ...): the series, where the expanded closed form loses every digit."""
    x = 1e-6
    np.testing.assert_allclose(float(loop_energy(x)), x**3 / 2 * (1 + x / 4), rtol=1e-12)


@pytest.fixture(scope="module")
def plastic():
    scene = make_scene(**PLASTIC, interaction="none", spot_stiffness="sneddon")
    return scene, jc.tangential_cycle(scene, PRELOAD, jnp.asarray(AMPLITUDES), MU)


def _scipy_cycle(scene, u0):
    """`(Q₀, W)` of the fully plastic joint by scipy: each spot P = H a, k_t = 2(1−ν)/(2−ν) 2E√(a/π),
    u* = 3μP/(2k_t) (∝ √a, so the spots below a_s slide), over the Majumdar–Bhushan distribution
    on (l_min², a_l], split at a_s; W by the Mindlin–Deresiewicz force form."""
    D, E, H, nu = (PLASTIC[k] for k in ("D", "E", "H", "nu"))
    a_l = float(jc.solve(scene, PRELOAD).a_l)
    kt_coefficient = 2 * (1 - nu) / (2 - nu) * 2 * E / math.sqrt(math.pi)

    def spot(t):
        a = math.exp(t)
        load = H * a
        slip = 1.5 * MU * load / (kt_coefficient * math.sqrt(a))
        count = (D / 2) * a_l ** (D / 2) * a ** (-(D + 2) / 2) * a  # per unit of t = ln a
        return count, load, slip

    def force(t):
        count, load, slip = spot(t)
        return count * MU * load * (1 - (1 - min(u0 / slip, 1)) ** 1.5)

    def energy(t):
        count, load, slip = spot(t)
        return count * MU * load * slip * mindlin_deresiewicz(u0 / slip)

    lower, upper = 2 * math.log(PLASTIC["l_min"]), math.log(a_l)
    boundary = 2 * math.log(u0 * kt_coefficient / (1.5 * MU * H))
    points = [boundary] if lower < boundary < upper else None
    quad = lambda f: integrate.quad(f, lower, upper, points=points, epsabs=0, epsrel=1e-12, limit=400)[0]  # noqa: E731
    return quad(force), quad(energy)


@pytest.fixture(scope="module")
def scipy_cycle(plastic):
    scene, _ = plastic
    return np.array([_scipy_cycle(scene, u0) for u0 in AMPLITUDES])


def test_the_loops_tip_is_scipys(plastic, scipy_cycle):
    _, cycle = plastic
    np.testing.assert_allclose(np.asarray(cycle.force), scipy_cycle[:, 0], rtol=1e-10)


def test_the_dissipation_is_scipys(plastic, scipy_cycle):
    _, cycle = plastic
    np.testing.assert_allclose(np.asarray(cycle.dissipation), scipy_cycle[:, 1], rtol=1e-9)


def test_at_the_smallest_amplitude_no_spot_slides(plastic):
    _, cycle = plastic
    assert float(cycle.sliding_share[0]) == 0.0


def test_at_the_largest_amplitude_every_spot_slides(plastic):
    _, cycle = plastic
    np.testing.assert_allclose(float(cycle.sliding_share[-1]), 1.0, rtol=1e-12)


def test_the_sliding_share_grows_with_the_amplitude(plastic):
    _, cycle = plastic
    assert np.all(np.diff(np.asarray(cycle.sliding_share)) > 0)


def test_in_macroslip_the_tip_is_mu_F(plastic):
    _, cycle = plastic
    np.testing.assert_allclose(float(cycle.force[-1]), MU * PRELOAD, rtol=1e-10)


def test_the_macroslip_force_is_mu_F(plastic):
    _, cycle = plastic
    np.testing.assert_allclose(float(cycle.macroslip_force), MU * PRELOAD, rtol=1e-15)


def test_the_stick_stiffness_is_the_tangential_stiffness(plastic):
    scene, cycle = plastic
    np.testing.assert_allclose(
        float(cycle.stick_stiffness), float(jc.tangential_stiffness(scene, PRELOAD).stiffness), rtol=1e-12
    )


@pytest.fixture(scope="module")
def small_amplitudes(plastic):
    scene, _ = plastic
    return jc.tangential_cycle(scene, PRELOAD, jnp.array([1e-15, 2e-15]), MU)


def test_at_small_amplitude_the_secant_is_the_stick_stiffness(small_amplitudes):
    np.testing.assert_allclose(
        float(small_amplitudes.secant_stiffness[0]), float(small_amplitudes.stick_stiffness), rtol=1e-6
    )


def test_at_small_amplitude_the_dissipation_grows_as_the_cube(small_amplitudes):
    np.testing.assert_allclose(float(small_amplitudes.dissipation[1] / small_amplitudes.dissipation[0]), 8.0, rtol=1e-6)


def test_the_damping_ratio_tends_to_coulombs_two_over_pi(plastic):
    """In gross slip W → 4μF u₀: ζ = W/(2π Q₀ u₀) → 2/π."""
    scene, _ = plastic
    cycle = jc.tangential_cycle(scene, PRELOAD, jnp.array([1e-2, 2e-2]), MU)  # the shape of `small_amplitudes`
    np.testing.assert_allclose(float(cycle.damping_ratio[0]), 2 / math.pi, rtol=1e-4)


@pytest.fixture(scope="module")
def seed_cycle():
    """The paper's Table 1 joint with its interaction."""
    scene = make_scene(**TABLE1)
    amplitudes = jnp.geomspace(1e-11, 1e-6, 6)
    return scene, amplitudes, jc.tangential_cycle(scene, 22.0, amplitudes, MU)


def test_the_seed_models_secant_falls_from_its_tangential_stiffness_to_mu_F_over_u(seed_cycle):
    scene, amplitudes, cycle = seed_cycle
    secant = np.asarray(cycle.secant_stiffness)
    assert np.all(np.diff(secant) < 0)
    assert secant[0] < float(jc.tangential_stiffness(scene, 22.0).stiffness)


@functools.cache
def _outputs():
    """ln W and ln Q₀ of the seed model (interaction 'paper') at one amplitude, beside a NaN one, and
    their statuses, as a function of θ = (D, ln μ, ln F, ln u₀): one program for every derivative and
    difference."""
    base = make_scene(**TABLE1)

    @jax.jit
    def outputs(theta):
        D, log_mu, log_F, log_u = theta
        scene = eqx.tree_at(lambda s: s.surface.D, base, D)
        amplitudes = jnp.stack([jnp.exp(log_u), jnp.nan])
        cycle = jc.tangential_cycle(scene, 22.0 * jnp.exp(log_F), amplitudes, jnp.exp(log_mu))
        return jnp.stack([jnp.log(cycle.dissipation[0]), jnp.log(cycle.force[0])]), cycle.status

    return outputs, jax.jit(jax.jacfwd(lambda theta: outputs(theta)[0]))


THETA = jnp.array([TABLE1["D"], math.log(MU), 0.0, math.log(3e-8)])


@pytest.mark.parametrize("i", range(4), ids=["D", "mu", "preload", "amplitude"])
def test_the_derivatives_match_central_differences(i):
    """At u₀ = 30 nm, where some of the preload slides; beside a NaN amplitude."""
    outputs, jacobian = _outputs()
    step = 1e-6
    central = (outputs(THETA.at[i].add(step))[0] - outputs(THETA.at[i].add(-step))[0]) / (2 * step)
    np.testing.assert_allclose(jacobian(THETA)[:, i], central, rtol=1e-6, atol=1e-9)


def test_a_traced_nan_amplitude_is_flagged_beside_a_good_one():
    outputs, _ = _outputs()
    assert np.asarray(outputs(THETA)[1]).tolist() == [0, jc.Status.INVALID_LOAD]


@pytest.fixture(scope="module")
def single_batch(seed_cycle):
    """The seed model's loops at two preloads, vmapped, in float32: one program for both facts."""
    _, amplitudes, _ = seed_cycle
    with x64(False):
        scene = make_scene(**TABLE1)
        loops = jax.vmap(lambda F: jc.tangential_cycle(scene, F, jnp.asarray(amplitudes, jnp.float32), np.float32(MU)))
        return loops(jnp.array([2.2, 22.0], jnp.float32))


def test_float32_gives_the_float64_loop_within_1e_4(seed_cycle, single_batch):
    _, _, double = seed_cycle
    assert single_batch.dissipation.dtype == jnp.float32
    np.testing.assert_allclose(np.asarray(single_batch.dissipation[1]), np.asarray(double.dissipation), rtol=1e-4)


def test_vmap_over_preloads_is_a_loop_over_them(seed_cycle, single_batch):
    """The batch's other preload against its own (float64) call, within float32's precision."""
    scene, amplitudes, _ = seed_cycle
    one = jc.tangential_cycle(scene, 2.2, amplitudes, MU).force
    np.testing.assert_allclose(np.asarray(single_batch.force[0]), np.asarray(one), rtol=1e-4)


def test_the_paper_interactions_breakdown_is_flagged():
    """On unloading the 'paper' interaction breaks down from F* ≈ 3e-5 (docs/in-service.md)."""
    scene = make_scene(**TABLE1)
    load = 1e-4 * TABLE1["E"] * TABLE1["area"]
    cycle = jc.tangential_cycle(scene, load, jnp.geomspace(1e-11, 1e-6, 6), MU)  # the shape of `seed_cycle`
    assert int(cycle.status[0]) == jc.Status.INTERACTION_BREAKDOWN


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(mu=0.0), r"mu .*\(0, inf\)"),
        (dict(mu=float("nan")), r"mu"),
        (dict(preload=-1.0), r"preload .*\(0, inf\)"),
        (dict(amplitudes=np.array([1e-8, -1e-8])), r"amplitudes .*\(0, inf\)"),
        (dict(nodes=4), r"nodes = 4 must be an integer in \[8, 256\]"),
    ],
)
def test_bad_input_is_refused_naming_the_parameter(kw, message):
    args = dict(preload=22.0, amplitudes=np.array([1e-8]), mu=MU) | kw
    nodes = args.pop("nodes", 16)
    with pytest.raises(ValueError, match=message):
        jc.tangential_cycle(jc.table1_scene(), args["preload"], args["amplitudes"], args["mu"], nodes=nodes)


def test_amplitudes_of_more_than_one_axis_are_refused():
    with refused_type("amplitudes", r"amplitudes has shape \(2, 2\)"):
        jc.tangential_cycle(jc.table1_scene(), 22.0, np.ones((2, 2)), MU)


@pytest.fixture(scope="module")
def summits():
    """Measured-asperity statistics (a tabulated Gaussian), its scipy twin, and its cycle at 3 N."""
    from test_measured_asperities import AREA, ETA, GAUSSIAN, HEIGHTS, R, ScipyGW, scene_of
    from test_measured_asperities import E as modulus

    scene = scene_of(jc.MeasuredAsperities(R, ETA, HEIGHTS, GAUSSIAN))
    reference = ScipyGW(HEIGHTS, GAUSSIAN, R, ETA, modulus, AREA)
    return scene, reference, jc.tangential_cycle(scene, 3.0, jnp.asarray(SUMMIT_AMPLITUDES), MU)


SUMMIT_AMPLITUDES = np.array([1e-9, 1e-8, 3e-8, 1e-7])  # m: stick → every summit sliding
RATIO = 2 * (1 - 0.3) / (2 - 0.3)  # k_t/k_n, ν = 0.3


def test_the_summits_backbone_is_mu_times_the_load_shed_by_a_raised_flat(summits):
    """Hertz summits of interference w slide at u* = μw/ratio, so the backbone is
    Q(u) = μ[F(d) − F(d + u·ratio/μ)] (Greenwood–Williamson with Cattaneo–Mindlin), by scipy."""
    _, reference, cycle = summits
    d = reference.separation(3.0)
    expected = [MU * (3.0 - reference.load(d + u * RATIO / MU)) for u in SUMMIT_AMPLITUDES]
    np.testing.assert_allclose(np.asarray(cycle.force), expected, rtol=1e-9)


def test_the_summits_dissipation_is_scipys(summits):
    """Σ over summits of the Mindlin–Deresiewicz loop of each (force form), by scipy over the table."""
    _, reference, cycle = summits
    d = reference.separation(3.0)
    z, pdf = reference.z, reference.pdf

    def energy(u0):
        def per_height(h):
            w = h - d
            load = reference.scale * 4 / 3 * w**1.5
            slip = MU * w / RATIO
            return np.interp(h, z, pdf) * MU * load * slip * mindlin_deresiewicz(u0 / slip)

        inside = list(z[(z > d) & (z < z[-1])]) + ([d + u0 * RATIO / MU] if d + u0 * RATIO / MU < z[-1] else [])
        return integrate.quad(per_height, d, z[-1], points=sorted(inside), limit=8 * z.size, epsabs=0, epsrel=1e-11)[0]

    np.testing.assert_allclose(np.asarray(cycle.dissipation)[1:], [energy(u) for u in SUMMIT_AMPLITUDES[1:]], rtol=1e-7)


def test_the_summits_stick_stiffness_is_their_tangential_stiffness(summits):
    scene, _, cycle = summits
    np.testing.assert_allclose(
        float(cycle.stick_stiffness), float(jc.tangential_stiffness(scene, 3.0).stiffness), rtol=1e-12
    )


def test_gw_summits_backbone_is_mu_times_the_load_shed_by_a_raised_flat():
    """GW's Gaussian summits (McCool's statistics of the Table 1 spectrum): Q(u) = μ[F(h) − F(h + ŵ_s)],
    ŵ_s = u·ratio/(μσ_s), with F(h) = (4/3) E η A √R σ^(3/2) I_{3/2}(h) by scipy's quadrature."""
    from jaxcontact.models._greenwood_williamson import summit_statistics
    from jaxcontact.quantities import nondimensionalise

    scene = make_scene(**TABLE1, model="gw")
    log_eta, log_R, log_sigma = (float(x) for x in summit_statistics(nondimensionalise(scene)))
    unit_load, sigma = TABLE1["E"] * TABLE1["area"], math.exp(log_sigma) * math.sqrt(TABLE1["area"])

    def load(h):
        tail = integrate.quad(lambda s: (s - h) ** 1.5 * math.exp(-s * s / 2), h, h + 40, epsabs=0, epsrel=1e-13)[0]
        return unit_load * 4 / 3 * math.exp(log_eta + 0.5 * log_R + 1.5 * log_sigma) * tail / math.sqrt(2 * math.pi)

    h = optimize.brentq(lambda h: load(h) - 22.0, -1.0, 40.0, xtol=1e-15)
    ratio = 2 * (1 - TABLE1["nu"]) / (2 - TABLE1["nu"])
    amplitudes = np.array([1e-10, 1e-9, 1e-8, 1e-7])
    expected = [MU * (22.0 - load(h + u * ratio / (MU * sigma))) for u in amplitudes]
    np.testing.assert_allclose(jc.tangential_cycle(scene, 22.0, jnp.asarray(amplitudes), MU).force, expected, rtol=1e-9)


@pytest.mark.parametrize("model", ["persson"])
def test_a_model_without_single_spots_is_refused_by_name(model):
    scene = make_scene(**TABLE1, model=model)
    with pytest.raises(ValueError, match=f"model = '{model}'"):
        jc.tangential_cycle(scene, 22.0, np.array([1e-8]), MU)


DEFAULT_SCENE = pathlib.Path(jc.__file__).parent / "scenes" / "table1_grinding.toml"
CLI_AMPLITUDES = ["--amplitudes", "1e-9", "1e-7", "--points", "3"]


@pytest.fixture(scope="module")
def cli_cycle(tmp_path_factory):
    """`jaxcontact cycle` on the embedded Table 1 scene, and the rows of its CSV."""
    import csv

    from jaxcontact.cli import main

    out = tmp_path_factory.mktemp("cycle")
    assert (
        main(["cycle", "--mu", "0.3", "--preload", "22", *CLI_AMPLITUDES, "--out", str(out), "--format", "json"]) == 0
    )
    with open(out / "cycle.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return out, rows


def test_the_cycle_command_writes_the_libraries_loop_tips(cli_cycle):
    _, rows = cli_cycle
    expected = jc.tangential_cycle(jc.table1_scene(), 22.0, jnp.geomspace(1e-9, 1e-7, 3), 0.3).force
    np.testing.assert_allclose([float(r["Q0_N"]) for r in rows], np.asarray(expected), rtol=1e-12)


def test_the_cycle_command_draws_its_loops(cli_cycle):
    out, _ = cli_cycle
    assert (out / "cycle.png").stat().st_size > 10_000


def test_the_cycle_command_reads_friction_from_the_scene_file(tmp_path, capsys):
    import json

    from jaxcontact.cli import main

    scene = tmp_path / "scene.toml"
    scene.write_text(DEFAULT_SCENE.read_text() + "\n[friction]\nmu = 0.2\npreload = 22.0\n")
    assert main(["cycle", str(scene), *CLI_AMPLITUDES, "--out", str(tmp_path), "--format", "json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert (payload["mu"], payload["macroslip_force_N"]) == (0.2, 0.2 * 22.0)


def test_the_cycle_command_without_a_friction_coefficient_or_a_path_says_so(tmp_path, capsys):
    from jaxcontact.cli import main

    assert main(["cycle", "--out", str(tmp_path)]) == 2
    assert "nothing to cycle: give --mu MU ([friction] mu) for friction loops" in capsys.readouterr().err


def test_a_scene_files_bad_friction_coefficient_is_refused_by_name(tmp_path, capsys):
    from jaxcontact.cli import main

    scene = tmp_path / "scene.toml"
    scene.write_text(DEFAULT_SCENE.read_text() + "\n[friction]\nmu = -0.2\n")
    assert main(["cycle", str(scene), "--out", str(tmp_path)]) == 2
    assert "friction.mu = -0.2 must be > 0" in capsys.readouterr().err
