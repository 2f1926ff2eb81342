"""Do a robot's physics claims hold with MuJoCo's ``discrete`` integrator (MuJoCo 3.13+:
the constraint solve and the implicit update in one metric) where they hold with the
library's ``implicitfast``? Every claim of the time-step sweep
(:func:`robot_agents.tuning.claims.measure_step`) at the given rates, under both.

    python benchmarks/integrator_claims.py panda 500 320 200
    python benchmarks/integrator_claims.py anymal_c 400 320

The library builds every scene with ``implicitfast`` and offers no integrator option;
this script swaps the integrator into the composed scene spec (the only place it is
set) for the ``discrete`` rows. What each variant costs per physics step:
``python benchmarks/sim_options.py --all --variants "as built,integrator discrete"``.
Not run in CI.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import mujoco

import robot_agents as ra
import robot_agents.sim.scene as sim_scene
from robot_agents.tuning.claims import measure_step

INTEGRATORS = {"implicitfast": None, "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE}


@contextmanager
def integrator(name: str) -> Iterator[None]:
    """Scenes composed inside use ``name`` (``implicitfast``: as the library builds them)."""
    value = INTEGRATORS[name]
    compose: Callable[..., mujoco.MjSpec] = sim_scene.compose_scene
    if value is None:
        yield
        return

    def composed(*args: Any, **kwargs: Any) -> mujoco.MjSpec:
        spec = compose(*args, **kwargs)
        spec.option.integrator = value
        return spec

    sim_scene.compose_scene = composed  # type: ignore[assignment]
    try:
        yield
    finally:
        sim_scene.compose_scene = compose  # type: ignore[assignment]


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robot")
    parser.add_argument("rates", nargs="+", type=int, help="sim_freq values (Hz)")
    args = parser.parse_args()
    cls = ra.get_agent(args.robot)
    print(f"| robot | sim_freq (Hz) | {' | '.join(INTEGRATORS)} |")
    print("|---|---|" + "---|" * len(INTEGRATORS))
    for rate in args.rates:
        cells = []
        for name in INTEGRATORS:
            with integrator(name):
                result = measure_step(cls, rate)
            failed = [f"{c.name} {c.value:.3g}" for c in result.claims if not c.passed]
            cells.append("all hold" if not failed else "fails: " + ", ".join(failed))
        print(f"| `{args.robot}` | {rate} | {' | '.join(cells)} |", flush=True)


if __name__ == "__main__":
    main()
