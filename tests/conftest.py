"""Shared fixtures. The tests run in float64 (the library itself never switches x64 on)."""

import os

os.environ.setdefault("JAX_PLATFORMS", "cpu")

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)

import pathlib  # noqa: E402

import pytest  # noqa: E402

import jaxcontact as jc  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
CHECKPOINTS = ROOT.parent / "shared" / "checkpoints.csv"

# MODEL.md §7: Table 1 grinding surface with the paper's material values.
TABLE1 = dict(D=1.4058, G=2.2826e-10, E=220e9, nu=0.25, H=100e9, area=1e-4, l_min=1e-9)
# Sec. 5.1 material (Figs. 3–6).
SEC51 = dict(E=210e9, nu=0.3, H=120e9, area=1e-4, l_min=1e-9)


def make_scene(D, G, E, nu, H, area, l_min, **kw):
    return jc.Scene(jc.Surface(D=D, G=G, l_min=l_min), jc.Material(E=E, nu=nu, H=H), area, **kw)


@pytest.fixture(scope="session")
def table1_scene():
    return make_scene(**TABLE1)
