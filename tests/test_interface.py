"""The interface law per unit area (`jc.interface_law`) against scipy's quadrature of A_a/K, and its
pressure–overclosure table read by a real FE code: CalculiX presses two elastic blocks together
through it."""

import contextlib
import io
import json
import os
import re
import shutil
import subprocess

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import TABLE1, make_scene, refused_type, scipy_approach

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.applications import interface_csv, pressure_overclosure, stick_friction
from jaxcontact.cli import main
from jaxcontact.numerics import x64

P0 = 1e4  # Pa
PRESSURES = np.geomspace(P0, 1e8, 40)  # the exported table's pressures


@pytest.fixture(scope="module")
def scene():
    return make_scene(**TABLE1)


@pytest.fixture(scope="module")
def law(scene):
    return jc.interface_law(scene, PRESSURES)


def test_the_closure_is_scipys_quadrature_of_area_over_stiffness(scene, law):
    area = TABLE1["area"]
    expected = scipy_approach(scene, PRESSURES[::8] * area, P0 * area)
    np.testing.assert_allclose(np.asarray(law.closure)[::8], expected, rtol=1e-6, atol=1e-20)


def test_the_default_nodes_for_these_pressures_give_the_eight_node_closure(scene, law):
    # 40 pressures over four decades: steps of 0.24 in ln p, where 4 nodes per piece are chosen.
    eight = jc.interface_law(scene, PRESSURES, nodes=8, in_service=False)
    np.testing.assert_allclose(law.closure[1:], eight.closure[1:], rtol=1e-11)


def test_the_stiffness_per_area_is_the_solves_over_the_nominal_area(scene, law):
    K = np.asarray(jc.solve(scene, PRESSURES * TABLE1["area"]).stiffness)
    np.testing.assert_allclose(law.normal_stiffness, K / TABLE1["area"], rtol=1e-12)


def test_the_closure_is_zero_at_the_reference_pressure(law):
    assert float(law.closure[0]) == 0.0


def test_the_closures_gradient_in_d_is_central_differences(table1_without_interaction):
    # Without interaction: the interaction's own gradients are checked in test_gradients.py. One
    # program gives the value for the differences and the gradient.
    @jax.jit
    @jax.value_and_grad
    def closure(D, scene):
        scene = eqx.tree_at(lambda s: s.surface.D, scene, D)
        return jc.interface_law(scene, jnp.array([1e6]), P0, in_service=False).closure[0]

    D, h = jnp.asarray(TABLE1["D"]), 1e-6
    fd = (closure(D + h, table1_without_interaction)[0] - closure(D - h, table1_without_interaction)[0]) / (2 * h)
    np.testing.assert_allclose(closure(D, table1_without_interaction)[1], fd, rtol=1e-5)


def test_the_table_starts_at_zero_and_ascends(scene, law):
    block = pressure_overclosure(scene, law).splitlines()
    rows = np.array([[float(v) for v in line.split(",")] for line in block[block.index("0., 0.") :]])
    assert rows[0].tolist() == [0.0, 0.0]
    assert np.all(np.diff(rows[:, 1]) > 0)


def test_the_table_leaves_out_flagged_pressures(scene):
    # The table's pressures with the last past F* = 1 (the same shape: the same compiled programs).
    law = jc.interface_law(scene, np.append(PRESSURES[:-1], 1e12))
    block = pressure_overclosure(scene, law)
    assert int(law.status[-1]) == int(jc.Status.LOAD_OUT_OF_RANGE)
    assert block.rstrip().splitlines()[-1].startswith(f"{PRESSURES[-2]:.9e},")


def test_a_table_with_nothing_above_the_reference_is_refused(scene, law):
    highest = eqx.tree_at(lambda law: law.reference_pressure, law, law.pressure[-1])
    with pytest.raises(InputError, match=r"no pressure above the reference p0 = 1e\+08 Pa has status ok"):
        pressure_overclosure(scene, highest)


def test_the_header_names_measured_summits_not_the_unused_surface():
    model = jc.MeasuredAsperities(1e-4, 1e9, np.linspace(0.0, 1e-6, 5), np.ones(5), summits=jc.KogutEtsionSummits())
    scene = make_scene(**TABLE1).with_model(model)
    header = [line for line in interface_csv(scene, jc.interface_law(scene, np.geomspace(1e5, 1e6, 3))).splitlines()][
        :2
    ]
    assert header == [
        f"# jaxcontact {jc.__version__} interface law, model measured-asperities, summits kogut-etsion",
        "# measured summits R = 0.0001 m, density 1e+09 1/m^2, height PDF on 5 points over 1e-06 m",
    ]


def test_the_csv_names_the_nominal_area_it_belongs_to(scene, law):
    text = interface_csv(scene, law)
    assert "# nominal area A_a = 0.0001 m^2" in text
    assert text.splitlines()[5].startswith(
        "pressure_Pa,closure_m,normal_stiffness_Pa_per_m,dynamic_stiffness_Pa_per_m,"
    )


# Two 10 mm steel cubes (ν = 0: a uniaxial stress, so that every node can be held laterally), the lower
# one on its bottom face, the upper one pressed on its top face, in contact through the exported table.
BLOCKS = """*NODE
1, 0., 0., 0.
2, 0.01, 0., 0.
3, 0.01, 0.01, 0.
4, 0., 0.01, 0.
5, 0., 0., 0.01
6, 0.01, 0., 0.01
7, 0.01, 0.01, 0.01
8, 0., 0.01, 0.01
9, 0., 0., 0.01
10, 0.01, 0., 0.01
11, 0.01, 0.01, 0.01
12, 0., 0.01, 0.01
13, 0., 0., 0.02
14, 0.01, 0., 0.02
15, 0.01, 0.01, 0.02
16, 0., 0.01, 0.02
*ELEMENT, TYPE=C3D8, ELSET=LOWER
1, 1, 2, 3, 4, 5, 6, 7, 8
*ELEMENT, TYPE=C3D8, ELSET=UPPER
2, 9, 10, 11, 12, 13, 14, 15, 16
*NSET, NSET=ALL
1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16
*NSET, NSET=BOTTOM
1, 2, 3, 4
*NSET, NSET=TOP
13, 14, 15, 16
*SURFACE, NAME=LOWERTOP
1, S2
*SURFACE, NAME=UPPERBOTTOM
2, S1
*MATERIAL, NAME=STEEL
*ELASTIC
{E_block}, 0.
*SOLID SECTION, ELSET=LOWER, MATERIAL=STEEL
*SOLID SECTION, ELSET=UPPER, MATERIAL=STEEL
*SURFACE INTERACTION, NAME=ROUGH
{table}*CONTACT PAIR, INTERACTION=ROUGH, TYPE=NODE TO SURFACE
UPPERBOTTOM, LOWERTOP
*BOUNDARY
ALL, 1, 2
BOTTOM, 3
*TIME POINTS, NAME=QUARTERS
0.25, 0.5, 0.75, 1.0
*STEP, INC=1000
*STATIC
0.01, 1.0
*DLOAD
2, P2, {pressure}
*NODE PRINT, NSET=TOP, TIME POINTS=QUARTERS
U
*CONTACT PRINT, TIME POINTS=QUARTERS
CDIS, CSTR
*END STEP
"""
E_BLOCK, P_MAX, HEIGHT = 210e9, 5e7, 0.01


def _run_calculix(work, text):
    if shutil.which("ccx") is None:
        pytest.skip("CalculiX is not installed (Debian: apt-get install calculix-ccx; .ci/run installs it)")
    (work / "stack.inp").write_text(text)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    run = subprocess.run(["ccx", "-i", "stack"], cwd=work, capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 0 and "ERROR" not in run.stdout, run.stdout[-2000:]
    return (work / "stack.dat").read_text()


@pytest.fixture(scope="module")
def calculix(scene, law, tmp_path_factory):
    """CalculiX's contact pressure, contact closure and top displacement at p = ¼, ½, ¾ and 1 of P_MAX."""
    table = pressure_overclosure(scene, law)
    text = _run_calculix(
        tmp_path_factory.mktemp("calculix"), BLOCKS.format(E_block=E_BLOCK, table=table, pressure=P_MAX)
    )

    def blocks(title):
        found = re.findall(title + r".*?time\s+(\S+)\s*\n\s*\n((?:\s*\d+(?:\s+\S+){3}\s*\n)+)", text)
        return {
            round(float(t), 6): np.array([[float(v) for v in line.split()[1:]] for line in b.strip().splitlines()])
            for t, b in found
        }

    return blocks(r"contact stress"), blocks(r"relative contact displacement"), blocks(r"displacements \(vx,vy,vz\)")


# The same stack pressed to P_SHEAR, then sheared by a force on its top (upper block free to slide in
# x, held in y), through the table and a *FRICTION block whose stick slope is the library's k_t.
SHEARED = (
    BLOCKS.replace(
        "*BOUNDARY\nALL, 1, 2\n",
        "*NSET, NSET=LOWERALL\n1, 2, 3, 4, 5, 6, 7, 8\n*NSET, NSET=UPPERALL\n9, 10, 11, 12, 13, 14, 15, 16\n"
        "*BOUNDARY\nLOWERALL, 1, 2\nUPPERALL, 2, 2\n",
    )
    .replace("*SURFACE INTERACTION, NAME=ROUGH\n{table}", "*SURFACE INTERACTION, NAME=ROUGH\n{table}{friction}")
    .replace(
        "*END STEP\n",
        "*END STEP\n*STEP, INC=1000\n*STATIC\n0.1, 1.0\n*CLOAD\nTOP, 1, {force}\n"
        "*CONTACT PRINT\nCDIS, CSTR\n*END STEP\n",
        1,
    )
)
P_SHEAR, MU = 1e6, 0.5


@pytest.fixture(scope="module")
def calculix_shear(scene, law, tmp_path_factory):
    """CalculiX's tangential contact stress and slip of the sheared stack (the last step's)."""
    tau = 0.1 * MU * P_SHEAR  # well inside stick
    text = SHEARED.format(
        E_block=E_BLOCK,
        table=pressure_overclosure(scene, law),
        friction=stick_friction(scene, MU, P_SHEAR),
        pressure=P_SHEAR,
        force=tau * HEIGHT**2 / 4,  # per top node
    )
    text = _run_calculix(tmp_path_factory.mktemp("shear"), text)
    stress = re.findall(r"contact stress.*?\n\n((?:\s*\d+(?:\s+\S+){3}\s*\n)+)", text)[-1]
    slip = re.findall(r"relative contact displacement.*?\n\n((?:\s*\d+(?:\s+\S+){3}\s*\n)+)", text)[-1]
    values = lambda block: np.array([[float(v) for v in line.split()[1:]] for line in block.strip().splitlines()])  # noqa: E731
    return values(stress), values(slip)


def test_calculix_sticks_with_the_librarys_tangential_stiffness(scene, calculix_shear):
    stress, slip = calculix_shear
    k_t = float(jc.tangential_stiffness(scene, P_SHEAR * TABLE1["area"]).stiffness) / TABLE1["area"]
    np.testing.assert_allclose(stress[:, 1] / slip[:, 1], k_t, rtol=1e-2)


@pytest.mark.parametrize("fraction", [0.25, 0.5, 1.0])
def test_calculix_carries_the_pressure_through_the_interface(calculix, fraction):
    stress, _, _ = calculix
    np.testing.assert_allclose(stress[fraction][:, 0], fraction * P_MAX, rtol=1e-6)


@pytest.mark.parametrize("fraction", [0.25, 0.5, 1.0])
def test_calculix_closes_the_interface_by_the_librarys_closure(scene, calculix, fraction):
    _, closure, _ = calculix
    p = fraction * P_MAX
    expected = float(jc.interface_law(scene, np.array([p]), P0, in_service=False).closure[0])
    np.testing.assert_allclose(-closure[fraction][:, 0], expected, rtol=1e-2)


@pytest.mark.parametrize("fraction", [0.25, 0.5, 1.0])
def test_the_stacks_compliance_is_the_blocks_plus_the_interfaces(calculix, fraction):
    _, closure, top = calculix
    p = fraction * P_MAX
    blocks = 2 * p * HEIGHT / E_BLOCK
    np.testing.assert_allclose(-top[fraction][:, 2], blocks - closure[fraction][:, 0], rtol=1e-6)


@pytest.fixture(scope="module")
def command(tmp_path_factory):
    """`jaxcontact interface` on the embedded scene at 9 pressures: its JSON rows and its folder."""
    out = tmp_path_factory.mktemp("interface")
    argv = ["interface", "--pressures", "1e4", "1e8", "--points", "9", "--friction", "0.3", "--out", str(out)]
    argv += ["--format", "json"]
    with contextlib.redirect_stdout(io.StringIO()) as printed:
        assert main(argv) == 0
    return json.loads(printed.getvalue())["rows"], out


def test_the_command_gives_the_librarys_law(command):
    rows, _ = command
    law = jc.interface_law(jc.table1_scene(), np.geomspace(1e4, 1e8, 9))
    np.testing.assert_allclose([r["closure_m"] for r in rows], law.closure, rtol=1e-12)


def test_the_commands_fe_table_has_a_row_per_pressure_above_the_reference(command):
    lines = (command[1] / "interface.inp").read_text().split("*FRICTION")[0].splitlines()
    # provenance, keyword, the row "0., 0.", the 8 pressures above p0, the friction block's comment
    assert len(lines) == 6 + 1 + 1 + 8 + 1


def test_the_commands_stick_slope_is_k_t_at_the_highest_pressure_that_has_one(command):
    law = jc.interface_law(jc.table1_scene(), np.geomspace(1e4, 1e8, 9))
    highest = np.flatnonzero(np.asarray(law.unloading_status) == 0)[-1]
    mu, slope = (command[1] / "interface.inp").read_text().split("*FRICTION\n")[1].split(",")
    assert (float(mu), float(slope)) == pytest.approx((0.3, float(law.tangential_stiffness[highest])), rel=1e-9)


def test_the_commands_ansys_stiffnesses_are_k_n_and_k_t_at_the_stick_pressure(command):
    # FKN (real constant 3) and FKT (12), negative: ANSYS's absolute stiffnesses, Pa/m.
    law = jc.interface_law(jc.table1_scene(), np.geomspace(1e4, 1e8, 9))
    highest = np.flatnonzero(np.asarray(law.unloading_status) == 0)[-1]
    rows = [line.split("!")[0].split(",") for line in (command[1] / "interface.mac").read_text().splitlines()]
    written = {int(r[2]): -float(r[3]) for r in rows if r[0] == "RMODIF"}
    expected = {3: float(law.normal_stiffness[highest]), 12: float(law.tangential_stiffness[highest])}
    assert written == pytest.approx(expected, rel=1e-9)


def test_the_command_draws_the_law(command):
    assert (command[1] / "interface.png").stat().st_size > 10_000


def test_the_command_refuses_pressures_out_of_order(tmp_path, capsys):
    assert main(["interface", "--pressures", "5", "1", "--out", str(tmp_path)]) == 2
    assert "--pressures 5 1 must be two pressures (Pa) with 0 < low < high" in capsys.readouterr().err


def test_float32_gives_the_float64_closure_within_1e4(law):
    with x64(False):
        law32 = jc.interface_law(make_scene(**TABLE1), PRESSURES[::8].astype(np.float32), in_service=False)
        assert law32.closure.dtype == np.float32
        np.testing.assert_allclose(np.asarray(law32.closure)[1:], np.asarray(law.closure)[::8][1:], rtol=1e-4)


def test_the_dynamic_column_is_the_dynamic_stiffness_per_unit_area(scene, law):
    ok = np.asarray(law.unloading_status) == 0
    expected = np.asarray(jc.dynamic_stiffness(scene, PRESSURES * TABLE1["area"]).stiffness) / TABLE1["area"]
    np.testing.assert_allclose(np.asarray(law.dynamic_stiffness)[ok], expected[ok], rtol=1e-12)


def test_the_tangential_column_is_mindlins_ratio_times_the_dynamic_one(law):
    ok = np.asarray(law.unloading_status) == 0
    ratio = np.asarray(law.tangential_stiffness)[ok] / np.asarray(law.dynamic_stiffness)[ok]
    np.testing.assert_allclose(ratio, 2 * (1 - TABLE1["nu"]) / (2 - TABLE1["nu"]), rtol=1e-14)


def test_the_paper_readings_unloading_breakdown_is_flagged_at_the_highest_pressure(law):
    assert int(law.unloading_status[-1]) == jc.Status.INTERACTION_BREAKDOWN


def test_a_law_without_its_in_service_columns_says_so(scene):
    law = jc.interface_law(scene, PRESSURES, in_service=False)
    np.testing.assert_array_equal(law.unloading_status, jc.Status.INVALID_PARAMETERS)


def test_a_flagged_unloading_leaves_its_columns_nan(law):
    flagged = np.asarray(law.unloading_status) != 0
    assert np.all(np.isnan(np.asarray(law.tangential_stiffness)[flagged]))


@pytest.mark.parametrize(
    "mu, pressure, message",
    [
        (0.0, 1e6, r"mu = 0.0 must be a friction coefficient in \(0, inf\)"),
        (0.3, 1e8, r"pressure = 1e\+08 Pa: no tangential"),
    ],
)
def test_a_friction_block_refuses_what_it_cannot_write(scene, mu, pressure, message):
    with pytest.raises(ValueError, match=message):
        stick_friction(scene, mu, pressure)


@pytest.mark.parametrize(
    "pressures, reference, message",
    [
        ([1e4, np.nan, 1e6], None, r"pressures\[1\] = nan Pa is not a valid pressure: .* \(valid range \(0, inf\) Pa"),
        ([-1.0, 1e6], None, r"pressures\[0\] = -1.0 Pa is not a valid pressure"),
        ([1e4, 1e6], -3.0, r"reference_pressure = -3.0 Pa is not a valid pressure"),
    ],
)
def test_bad_pressures_are_refused_by_name(scene, pressures, reference, message):
    with pytest.raises(InputError, match=message):
        jc.interface_law(scene, np.array(pressures), reference)


def test_pressures_that_are_not_1d_are_refused(scene):
    with refused_type("pressures", r"pressures has shape \(1, 2\): give a 1-D array"):
        jc.interface_law(scene, np.array([[1e4, 1e6]]))
