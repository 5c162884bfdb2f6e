"""The BEM at scale: the Fourier-preconditioned constrained iteration against Polonsky & Keer's plain
one (the same solution to the tolerance, elastic, capped and on a free half-space, in a fraction of the
iterations), and a map split over several devices (a distributed FFT) against one device."""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import refused_type

from jaxcontact import bem

pytest.importorskip("SurfaceTopography")

L, E = 1e-3, 1e11
LOAD = 1e-4 * E * L * L  # 12-13 % contact on this surface
# (substrate, hardness, grid): the capped (12-19 % of the contact points at the cap) and free cases on
# 128² (a free solve doubles the grid).
CASES = {
    "elastic": (bem.Periodic(), None, 256),
    "capped": (bem.Periodic(), 1.5e8, 128),
    "free": (bem.Free(), None, 128),
}


@functools.cache
def _heights(grid: int):
    return jnp.asarray(bem.realisation(1.5, 1e-12, L / 32, L, grid, 0).heights())


@functools.cache
def _solved(case: str, preconditioned: bool):
    substrate, hardness, grid = CASES[case]
    loads = jnp.array([0.5, 1.0, 4.0]) * LOAD
    heights = _heights(grid)
    return bem.solve(heights, L, E, loads, hardness=hardness, substrate=substrate, preconditioned=preconditioned)


@pytest.mark.parametrize("case", CASES)
def test_the_offsets_are_the_plain_iterations_to_1e_8_of_the_rms_height(case):
    rms = float(jnp.std(_heights(CASES[case][2])))
    difference = np.asarray(_solved(case, True).offset) - np.asarray(_solved(case, False).offset)
    assert np.max(np.abs(difference)) < 1e-8 * rms


@pytest.mark.parametrize("case", CASES)
def test_the_tangent_stiffness_is_the_plain_iterations(case):
    np.testing.assert_allclose(_solved(case, True).stiffness, _solved(case, False).stiffness, rtol=1e-8)


@pytest.mark.parametrize("case", CASES)
def test_the_contact_set_is_the_plain_iterations(case):
    np.testing.assert_array_equal(_solved(case, True).contact_fraction, _solved(case, False).contact_fraction)


@pytest.mark.parametrize("case", CASES)
def test_every_load_converges(case):
    np.testing.assert_array_equal(_solved(case, True).status, [0, 0, 0])


def test_the_middle_load_is_at_12_percent_contact():
    assert 0.1 < float(_solved("elastic", True).contact_fraction[1]) < 0.15


def test_at_12_percent_contact_on_256_squared_it_takes_at_most_half_the_iterations():
    assert int(_solved("elastic", True).iterations[1]) <= int(_solved("elastic", False).iterations[1]) // 2


def test_at_46_percent_contact_on_256_squared_it_takes_at_most_a_seventh_of_the_iterations():
    """Points keep joining the contact until late: an iteration that restarts its conjugacy at each
    join (a preconditioned steepest descent) takes 40 here, the plain iteration 228."""
    assert int(_solved("elastic", True).iterations[2]) <= int(_solved("elastic", False).iterations[2]) // 7


def test_a_contact_with_93_percent_of_its_points_at_the_cap_converges():
    """D = 1.2 at H = 0.3 GPa on 128²: where the cap holds most of the contact's points, a join restarts
    the conjugacy; kept through the joins there, the iteration cycles on this contact to its limit."""
    heights = jnp.asarray(bem.realisation(1.2, 1e-12, L / 32, L, 128, 1).heights())
    solution = bem.solve(heights, L, E, jnp.array([0.1, 0.12, 0.144]) * LOAD, hardness=3e8)
    assert int(solution.status[0]) == 0


# Both subprocesses' map: self-affine (C2D ∝ q^-4, random phases), 1 µm rms, 64², as numpy `h`.
_MAP = """
L, E = 1e-3, 1e11
q = np.hypot(*np.meshgrid(np.fft.fftfreq(64), np.fft.fftfreq(64), indexing="ij"))
phases = np.exp(2j * np.pi * np.random.default_rng(0).random((64, 64)))
h = np.real(np.fft.ifft2(np.where(q > 0, q, 1.0) ** -2 * phases))
h = h * 1e-6 / h.std()
"""

_SHARDED = (
    """
import os
# The suite's compiler flags (conftest.py), with 4 host devices.
os.environ["XLA_FLAGS"] = os.environ.get("XLA_FLAGS", "") + " --xla_force_host_platform_device_count=4"
import json, jax, jax.numpy as jnp, numpy as np
jax.config.update("jax_enable_x64", True)
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from jaxcontact import bem
"""
    + _MAP
    + """
h = jnp.asarray(h)
mesh = Mesh(np.array(jax.devices()), ("rows",))
fft = bem.DistributedFFT(mesh, "rows")
loads = jnp.array([0.5, 4.0]) * 1e-4 * E * L * L
out = {}
# The capped periodic case (elastic and plastic points), its offsets with their gradient with respect
# to the heights, and the free case (the padded grid) with its tangents.
def capped(fft):
    def solved(heights):
        solution = bem.solve(heights, L, E, loads, hardness=1.5e8, fft=fft)
        return solution.offset, solution.plastic_fraction
    return solved
for name, fft_ in (("alone", bem.LocalFFT()), ("split", fft)):
    offset, pullback, plastic = jax.vjp(capped(fft_), h, has_aux=True)
    (gradient,) = pullback(jnp.ones_like(offset))
    out["capped " + name] = [np.asarray(offset).tolist(), np.asarray(gradient).tolist()]
out["capped plastic"] = float(plastic[-1])
out["gradient sharding"] = gradient.sharding.spec[0]
# Each device computes its columns of Love's kernel, which differ from the host's in the last bits: the
# two solves then agree to their tolerance, 1e-12 here.
free = lambda fft: bem.solve(h, L, E, loads, substrate=bem.Free(), tolerance=1e-12, fft=fft)
alone, split = free(bem.LocalFFT()), free(fft)
out["free"] = [np.asarray(x).tolist() for x in (alone.offset, split.offset, alone.stiffness, split.stiffness)]
# Heights sharded by the user with the FFTs left to XLA's partitioner: the same solve.
user = bem.solve(jax.device_put(h, NamedSharding(mesh, PartitionSpec("rows", None))), L, E, loads)
out["partitioner"] = [np.asarray(x).tolist() for x in (bem.solve(h, L, E, loads).offset, user.offset)]
# Float32: the map and loads in single precision (tolerance 1e-5 of the rms height).
single = lambda fft: bem.solve(h.astype(jnp.float32), L, E, loads.astype(jnp.float32), fft=fft)
solved = (single(bem.LocalFFT()), single(fft))
out["float32"] = [[str(s.stiffness.dtype), np.asarray(s.stiffness, float).tolist()] for s in solved]
# The BEM model's realisations split so: the secant of each, to the solves' tolerance (1e-9).
import jaxcontact as jc
model = lambda fft: jc.BEM(grid=32, realisations=1, fft=fft)
side = 4e-4  # l_min = side/6 on 32²
scene = jc.Scene(jc.Surface(D=1.5, G=1e-12, l_min=side / 6), jc.Material(E=E, nu=0.3, H=1e9), side**2, model(fft))
model_loads = np.array([1e-4, 3e-4]) * E * side**2
stiffness = lambda f: np.asarray(jc.solve(scene.with_model(model(f)), model_loads).stiffness).tolist()
out["model"] = [stiffness(bem.LocalFFT()), stiffness(fft)]
try:
    bem.solve(h[:62, :62], L, E, loads, fft=fft)
except ValueError as error:
    out["refused"] = str(error)
print(json.dumps(out))
"""
)


@pytest.fixture(scope="module")
def sharded():
    """A 64² map solved with its rows split over 4 (host) devices by `bem.DistributedFFT`, and on one:
    in a process of its own, since the device count is fixed when JAX starts."""
    import json
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _SHARDED], capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_the_distributed_solve_reaches_the_cap(sharded):
    assert sharded["capped plastic"] > 0.01


def test_a_distributed_fft_gives_the_capped_offsets_of_one_device(sharded):
    np.testing.assert_allclose(sharded["capped split"][0], sharded["capped alone"][0], rtol=1e-10)


def test_a_distributed_fft_gives_the_free_offsets_of_one_device(sharded):
    alone, split, _, _ = sharded["free"]
    np.testing.assert_allclose(split, alone, rtol=1e-10)


def test_a_distributed_fft_gives_the_free_tangents_of_one_device(sharded):
    _, _, alone, split = sharded["free"]
    np.testing.assert_allclose(split, alone, rtol=1e-10)


def test_the_distributed_gradient_is_one_devices(sharded):
    alone, split = np.asarray(sharded["capped alone"][1]), np.asarray(sharded["capped split"][1])
    np.testing.assert_allclose(split, alone, rtol=1e-10, atol=1e-12 * np.max(np.abs(alone)))


def test_the_distributed_gradient_stays_split_by_rows(sharded):
    assert sharded["gradient sharding"] == "rows"


def test_heights_sharded_by_the_user_give_the_offsets_of_one_device(sharded):
    alone, user = sharded["partitioner"]
    np.testing.assert_allclose(user, alone, rtol=1e-10)


_PROCESS = (
    """
import os, sys, json
process, port = int(sys.argv[1]), sys.argv[2]
os.environ["XLA_FLAGS"] = os.environ.get("XLA_FLAGS", "") + " --xla_force_host_platform_device_count=2"
import jax
jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_collectives_implementation", "gloo")
jax.distributed.initialize(f"localhost:{port}", num_processes=2, process_id=process)
import jax.numpy as jnp, numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec
from jaxcontact import bem
"""
    + _MAP
    + """
# Each process holds its own rows of the map only.
mesh = Mesh(np.array(jax.devices()), ("rows",))
heights = jax.make_array_from_callback(h.shape, NamedSharding(mesh, PartitionSpec("rows", None)), lambda i: h[i])
loads = jnp.array([0.5, 4.0]) * 1e-4 * E * L * L
solution = bem.solve(heights, L, E, loads, fft=bem.DistributedFFT(mesh))
print(json.dumps({"devices": len(jax.devices()), "offset": np.asarray(solution.offset).tolist()}))
"""
)


@pytest.fixture(scope="module")
def two_processes():
    """The elastic solve on two processes of two (host) devices each, as on two hosts
    (`jax.distributed`, gloo's collectives): each process's output."""
    import json
    import socket
    import subprocess
    import sys

    with socket.socket() as free:
        free.bind(("localhost", 0))
        port = str(free.getsockname()[1])
    runs = [
        subprocess.Popen([sys.executable, "-c", _PROCESS, str(i), port], stdout=subprocess.PIPE, text=True)
        for i in range(2)
    ]
    outputs = [run.communicate(timeout=300)[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0]
    return [json.loads(out.strip().splitlines()[-1]) for out in outputs]


def test_two_processes_see_four_devices(two_processes):
    assert [out["devices"] for out in two_processes] == [4, 4]


@pytest.mark.parametrize("process", [0, 1])
def test_two_processes_give_the_offsets_of_one_device(sharded, two_processes, process):
    np.testing.assert_allclose(two_processes[process]["offset"], sharded["partitioner"][0], rtol=1e-10)


def test_a_distributed_float32_solve_stays_in_float32(sharded):
    assert [dtype for dtype, _ in sharded["float32"]] == ["float32", "float32"]


def test_a_distributed_float32_solve_gives_one_devices_stiffness_to_its_tolerance(sharded):
    (_, alone), (_, split) = sharded["float32"]
    np.testing.assert_allclose(split, alone, rtol=1e-4)


def test_the_bem_model_split_over_devices_gives_one_devices_stiffness(sharded):
    alone, split = sharded["model"]
    np.testing.assert_allclose(split, alone, rtol=1e-8)


def test_a_side_that_does_not_split_over_the_devices_is_refused_with_the_count(sharded):
    assert "n = 62 is not a multiple of the 4 devices" in sharded["refused"]


def test_a_distributed_fft_needs_a_mesh():
    with refused_type("mesh", "mesh = 'rows' is not a jax.sharding.Mesh"):
        bem.DistributedFFT("rows")


def test_a_distributed_fft_names_the_meshs_axes():
    from jax.sharding import Mesh

    with pytest.raises(ValueError, match=r"axis = 'rows' is not an axis of the mesh: valid are \('x',\)"):
        bem.DistributedFFT(Mesh(np.array(jax.devices()[:1]), ("x",)), "rows")


def test_the_fft_is_an_object():
    with refused_type("fft", "fft = 'distributed' must be bem.LocalFFT"):
        bem.solve(jnp.ones((8, 8)), L, E, jnp.array([1.0]), fft="distributed")
