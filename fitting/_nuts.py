"""NUTS through blackjax (the `bayes` extra): window adaptation, then several chains in one compiled scan.

Generic over the log density: `jaxcontact.fitting._posterior` gives it the model's, the tests a Gaussian's.
"""

from __future__ import annotations

import dataclasses
import time

import jax
import jax.numpy as jnp
import numpy as np

from jaxcontact.numerics import cached, optional_import, standard_promotion

from ._compiled import compiled


@dataclasses.dataclass(frozen=True)
class Chains:
    """`positions` (chains, draws, dimension), the `ess` and `rhat` of each dimension (over all chains),
    the mean acceptance, the number of divergent transitions, and the times (s): `adaptation` (with its
    compilation), the sampler's `compilation` (0 where it was kept from an earlier call), and
    `sampling` (the compiled run)."""

    positions: np.ndarray
    ess: np.ndarray
    rhat: np.ndarray
    acceptance: float
    divergences: int
    adaptation: float
    compilation: float
    sampling: float


def run_chains(logdensity, initial, *, chains: int = 4, warmup: int = 500, draws: int = 500, seed: int = 0) -> Chains:
    """Adapt NUTS's step size and diagonal mass matrix on one chain from `initial` (blackjax's window
    adaptation), then run `chains` chains of `draws` from the adapted state, each with its own key,
    `vmap`ped over chains inside one `lax.scan`. Seeded and reproducible. Both programs are kept
    (`_compiled`): a log density of the same structure and shapes (a module whose arrays differ: another
    curve) compiles nothing again.

    **Arguments:** `logdensity` (a JAX function of a position vector, or a module called so),
    `initial` (the start), `chains`, `warmup` (adaptation steps), `draws` (per chain), `seed`.
    **Returns:** `Chains`.
    """
    blackjax = optional_import("blackjax", "sampling a posterior")
    key = jax.random.PRNGKey(seed)
    adapt_key, chain_key = jax.random.split(key)
    initial = jnp.asarray(initial)
    t0 = time.perf_counter()
    with standard_promotion():
        # Compiled as one program: run eagerly, its set-up dispatches a hundred small ones.
        adapt, dynamic, _ = compiled(_adapted, logdensity, adapt_key, initial, warmup)
        state, parameters = adapt(dynamic)
        jax.block_until_ready(state.position)
        t1 = time.perf_counter()
        # Each chain starts from the adapted state; they decorrelate within a few draws (the adapted
        # step explores the posterior) and R-hat over them checks that they agree.
        states = jax.vmap(lambda _: state)(jnp.arange(chains))
        draw, dynamic, compilation = compiled(_drawn, logdensity, parameters, states, chain_key, draws)
        t2 = time.perf_counter()
        positions, acceptance, divergent = draw(dynamic)
        jax.block_until_ready(positions)
    t3 = time.perf_counter()
    positions = np.swapaxes(np.asarray(positions), 0, 1)  # (chains, draws, dimension)
    with standard_promotion():
        ess, rhat = (np.asarray(x, dtype=float) for x in _diagnostics(blackjax)(positions))
    return Chains(
        positions=positions,
        ess=ess,
        rhat=rhat,
        acceptance=float(np.mean(acceptance)),
        divergences=int(np.sum(divergent)),
        adaptation=t1 - t0,
        compilation=compilation,
        sampling=t3 - t2,
    )


def _adapted(logdensity, key, position, warmup: int):
    """NUTS's adapted state and parameters after blackjax's window adaptation from `position`."""
    blackjax = optional_import("blackjax", "sampling a posterior")
    adaptation = blackjax.window_adaptation(blackjax.nuts, logdensity)
    return adaptation.run(key, position, num_steps=warmup)[0]


def _drawn(logdensity, parameters, states, key, draws: int):
    """`draws` NUTS steps of every chain in `states` (`vmap`ped, one `lax.scan`): positions,
    acceptance rates, divergences."""
    blackjax = optional_import("blackjax", "sampling a posterior")
    kernel = blackjax.nuts(logdensity, **parameters)
    chains = jax.tree_util.tree_leaves(states)[0].shape[0]

    def one_step(states, key):
        states, info = jax.vmap(kernel.step)(jax.random.split(key, chains), states)
        return states, (states.position, info.acceptance_rate, info.is_divergent)

    return jax.lax.scan(one_step, states, jax.random.split(key, draws))[1]


@cached
def _diagnostics(blackjax):
    """`positions` (chains, draws, dimension) ↦ (ESS, R-hat) per dimension, as one compiled program."""

    def both(positions):
        d = blackjax.diagnostics
        return d.effective_sample_size(positions), d.potential_scale_reduction(positions)

    return jax.jit(jax.vmap(both, in_axes=-1))
