"""The time-step sweep for built-in robots: per robot, every physics claim at each
physics step (largest first) and the largest step at which all hold.

    python benchmarks/timestep_sweep.py                 # every registered robot, every step
    python benchmarks/timestep_sweep.py panda so100     # just these
    python benchmarks/timestep_sweep.py --quick panda   # finest step, then stop after two passes
    python benchmarks/timestep_sweep.py --seeds 0 so100 # one random-action sequence (default: 0,1,2)
    python benchmarks/timestep_sweep.py --output docs/timestep-sweep.md
    python benchmarks/timestep_sweep.py --jobs 2       # robots swept in 2 processes
    python benchmarks/timestep_sweep.py --solver-tolerance 1e-11 spot  # every claim scene's opt.tolerance

Writes a markdown report (summary table, then each robot's table) to ``--output``
(default: stdout). Not run in CI.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor

import robot_agents as ra
from robot_agents.sim.scene import Scene
from robot_agents.tuning.claims import RANDOM_SEEDS, scene_setup
from robot_agents.tuning.cycles import DriveCycleBound, drive_cycle_bounds
from robot_agents.tuning.timestep import DEFAULT_SUBSTEPS, SweepResult, sweep_timestep


def cycle_cells(uid: str, declared: int | None) -> tuple[str, str]:
    """The drive whose torque-limit cycle reaches the highest rate (with that rate), and
    the cycles possible at the declared step (``robot_agents.tuning.cycles``)."""
    bounds = drive_cycle_bounds(uid)
    if not bounds:
        return "-", "-"
    top = bounds[0]
    highest = f"{top.cycle_free_above:.0f} (`{top.joint}`{'' if top.reachable else ', not reachable'})"
    rate = declared or 500
    possible: list[DriveCycleBound] = [b for b in bounds if b.amplitude(rate) > 0]
    at_default = (
        ", ".join(
            f"`{b.joint}` {b.amplitude(rate):.2g}{'' if b.reachable else ' (not reachable)'}" for b in possible[:3]
        )
        + (" ..." if len(possible) > 3 else "")
        if possible
        else "none"
    )
    return highest, at_default


def report(results: Sequence[SweepResult], seconds: Sequence[float], seeds: Sequence[int]) -> str:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [
        "# Time-step sweep",
        "",
        "MuJoCo physics steps tried among the divisors of the control period; random actions with seeds "
        f"{', '.join(map(str, seeds))} (each must pass); load average {load:.2f}. The cycle columns are "
        "the analysis of `robot_agents.tuning.cycles` (no simulation): below that rate a force-limited drive can "
        "flip between its limits every step, at the speed given; not reachable: its rated speed is below the "
        "speed that enters the cycle.",
        "",
        "| robot | largest passing sim_freq (Hz) | claims failing at every step | largest passing, other claims (Hz) "
        "| declared sim_freq | torque-limit cycle possible below (Hz) | cycles possible at the declared step "
        "(rad/s or m/s) | sweep time (s) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for result, took in zip(results, seconds, strict=True):
        declared = ra.get_agent(result.uid).sim_freq
        everywhere = ", ".join(result.failing_everywhere) or "-"
        others = result.largest_passing_other_claims if result.failing_everywhere else result.largest_passing
        highest, at_default = cycle_cells(result.uid, declared)
        lines.append(
            f"| `{result.uid}` | {result.largest_passing or 'none'} | {everywhere} | {others or 'none'} "
            f"| {declared or 'default'} | {highest} | {at_default} | {took:.1f} |"
        )
    for result in results:
        lines += ["", f"## `{result.uid}`", "", result.table()]
    return "\n".join(lines) + "\n"


def timed_sweep(
    uid: str, substeps: Sequence[int], seeds: Sequence[int], quick: bool, tolerance: float | None = None
) -> tuple[SweepResult, float]:
    """One robot's sweep and its wall-clock seconds (reported on stderr as it ends);
    ``tolerance``: every claim scene's constraint-solver tolerance (``None``: as built)."""

    def set_tolerance(scene: Scene) -> None:
        if tolerance is not None:
            scene.model.opt.tolerance = tolerance

    start = time.perf_counter()
    with scene_setup(set_tolerance):
        result = sweep_timestep(uid, substeps=substeps, seeds=seeds, stop_after=2 if quick else None)
    took = time.perf_counter() - start
    print(f"{uid}: largest passing {result.largest_passing} Hz ({took:.1f} s)", file=sys.stderr, flush=True)
    return result, took


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("uids", nargs="*", help="robots to sweep (default: every registered robot)")
    parser.add_argument("--output", default=None, help="markdown file to write (default: stdout)")
    parser.add_argument("--substeps", default=",".join(map(str, DEFAULT_SUBSTEPS)), help="substep counts to try")
    parser.add_argument(
        "--seeds", default=",".join(map(str, RANDOM_SEEDS)), help="seeds of the random-action claim (each must pass)"
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="measure the finest step, then stop after two coarser passes (default: every step; a robot near "
        "a torque-limit cycle can pass at a coarse step and fail at a finer one)",
    )
    parser.add_argument(
        "--jobs",
        type=int,
        default=1,
        help="robots swept at once, each in its own process (the sweep times then share the machine's cores)",
    )
    parser.add_argument(
        "--solver-tolerance",
        type=float,
        default=None,
        help="the constraint solver's tolerance of every claim scene (default: the scene as built, a robot's "
        "declared solver_tolerance or MuJoCo's 1e-8)",
    )
    args = parser.parse_args(argv)
    uids = args.uids or ra.list_agents()
    substeps = [int(n) for n in args.substeps.split(",")]
    seeds = [int(n) for n in args.seeds.split(",")]
    sweep = functools.partial(
        timed_sweep, substeps=substeps, seeds=seeds, quick=args.quick, tolerance=args.solver_tolerance
    )
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            timed = list(pool.map(sweep, uids))
    else:
        timed = [sweep(uid) for uid in uids]
    text = report([result for result, _ in timed], [took for _, took in timed], seeds)
    if args.output:
        with open(args.output, "w", encoding="utf-8") as handle:
            handle.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
