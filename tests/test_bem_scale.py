"""The BEM at scale: the Fourier-preconditioned constrained iteration against Polonsky & Keer's plain
one (the same solution to the tolerance, elastic, capped and on a free half-space, in a fraction of the
iterations), and a map sharded over several devices against one device."""

import functools

import jax.numpy as jnp
import numpy as np
import pytest

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


_SHARDED = """
import os
os.environ["XLA_FLAGS"] = "--xla_force_host_platform_device_count=4"
import json, jax, jax.numpy as jnp, numpy as np
jax.config.update("jax_enable_x64", True)
from jax.sharding import Mesh, NamedSharding, PartitionSpec
from jaxcontact import bem
h = np.random.default_rng(0).normal(size=(64, 64)) * 1e-6
loads = jnp.array([2e-3, 8e-3]) * 1e11 * 1e-6
alone = bem.solve(jnp.asarray(h), 1e-3, 1e11, loads)
mesh = Mesh(np.array(jax.devices()), ("rows",))
sharded = bem.solve(jax.device_put(h, NamedSharding(mesh, PartitionSpec("rows", None))), 1e-3, 1e11, loads)
print(json.dumps([np.asarray(x).tolist() for x in (alone.offset, sharded.offset, alone.stiffness, sharded.stiffness)]))
"""


@pytest.fixture(scope="module")
def sharded_and_alone():
    """A 64² map's solve with the heights sharded by rows over 4 (host) devices, and alone: in a process
    of its own, since the device count is fixed when JAX starts."""
    import json
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _SHARDED], capture_output=True, text=True, check=True).stdout
    return [np.asarray(x) for x in json.loads(out.strip().splitlines()[-1])]


def test_a_solve_of_sharded_heights_gives_the_offsets_of_one_device(sharded_and_alone):
    alone, sharded, _, _ = sharded_and_alone
    np.testing.assert_allclose(sharded, alone, rtol=1e-10)


def test_a_solve_of_sharded_heights_gives_the_stiffness_of_one_device(sharded_and_alone):
    _, _, alone, sharded = sharded_and_alone
    np.testing.assert_allclose(sharded, alone, rtol=1e-10)
