"""Sharded sweeps: results on two (forced) host devices equal unsharded ones."""

import json
import os
import subprocess
import sys

import numpy as np
from helpers import ROOT, TABLE1

import jaxcontact as jc
from jaxcontact.applications import solve_sweep

SCRIPT = r"""
import jax, json, numpy as np
jax.config.update("jax_enable_x64", True)
import jaxcontact as jc
from jaxcontact.applications import sweep
assert len(jax.devices()) == 2, jax.devices()
scene = jc.Scene(jc.Surface(1.4058, 2.2826e-10), jc.Material(220e9, 0.25, 100e9), 1e-4)
D, G = np.linspace(1.3, 1.7, 5), np.geomspace(1e-11, 1e-9, 3)
loads = np.geomspace(1e-7, 1e-3, 7) * 2.2e7
sharded = sweep(scene, D, G, loads, block=4)
direct = [[jc.solve(jc.Scene(jc.Surface(d, g), scene.material, 1e-4), loads) for g in G] for d in D]
K = np.array([[np.asarray(s.stiffness) for s in row] for row in direct])
status = np.array([[np.asarray(s.status) for s in row] for row in direct])
print(json.dumps({"devices": sharded.devices,
                  "status_equal": bool(np.array_equal(sharded.status, status)),
                  "flagged": int((sharded.status != 0).sum()),
                  "max_diff_direct": float(np.nanmax(np.abs(sharded.stiffness / K - 1))),
                  "nan_match": bool(np.array_equal(np.isnan(sharded.stiffness), np.isnan(K)))}))
"""


def test_two_devices_equal_unsharded():
    # The suite's own XLA flags (conftest) kept: the child compiles as the tests do.
    flags = f"{os.environ.get('XLA_FLAGS', '')} --xla_force_host_platform_device_count=2".strip()
    env = {**os.environ, "XLA_FLAGS": flags, "JAX_PLATFORMS": "cpu"}
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, cwd=ROOT, check=True)
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["devices"] == 2
    assert result["status_equal"]
    assert result["nan_match"]
    assert result["flagged"] > 0  # the grid reaches breakdown loads: flagged points travel too
    assert result["max_diff_direct"] < 1e-13


def test_sweep_command_writes_csv(tmp_path, capsys):
    from jaxcontact.cli import main

    assert (
        main(
            [
                "sweep",
                "--D",
                "1.4:1.6:2",
                "--G",
                "1e-10:1e-9:2",
                "--out",
                str(tmp_path),
                "--format",
                "json",
                "--no-progress",
            ]
        )
        == 0
    )
    payload = json.loads(capsys.readouterr().out)
    assert payload["points"] == 2 * 2 * 41
    assert len(payload["rows"]) == payload["points"]
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    assert lines[0].startswith("D,G_m,F_N")
    assert len(lines) == 1 + payload["points"]
    assert main(["sweep", "--D", "1.4:1.6", "--out", str(tmp_path)]) == 2
    assert "LOW:HIGH:COUNT" in capsys.readouterr().err
    assert main(["sweep", "--D", "1.4:2.5:3", "--out", str(tmp_path)]) == 2
    assert "--D 2.5 (fractal dimension) is outside its valid range (1, 2)" in capsys.readouterr().err
    np.testing.assert_allclose(payload["rows"][0]["D"], 1.4)


def test_a_chunked_solve_equals_one_solve(table1_scene):
    """Loads in several chunks (the last padded): the same as one call, per-call fields included."""
    loads = np.geomspace(1e-7, 1e-4, 10) * TABLE1["E"] * TABLE1["area"]
    chunked = solve_sweep(table1_scene, loads, chunk=4)
    whole = jc.solve(table1_scene, loads)
    np.testing.assert_allclose(chunked.stiffness, np.asarray(whole.stiffness), rtol=1e-13)
    np.testing.assert_allclose(chunked.load_star, np.asarray(whole.load_star), rtol=1e-15)
    np.testing.assert_array_equal(chunked.modulus, np.asarray(whole.modulus))


def test_a_sweep_shorter_than_a_chunk_is_padded_on_the_host_with_no_program_to_cut_it(table1_scene):
    from jaxcontact.programs import _programs as programs

    loads = np.geomspace(1e-7, 1e-4, 10) * TABLE1["E"] * TABLE1["area"]
    programs._unpad.cache_clear()
    swept = solve_sweep(table1_scene, loads)
    assert programs._unpad.cache_info().currsize == 0
    np.testing.assert_array_equal(swept.stiffness, np.asarray(jc.solve(table1_scene, loads).stiffness))
