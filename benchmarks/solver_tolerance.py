"""The constraint solver's tolerance per robot: what MuJoCo's relative tolerance means in
each robot's scenes, and how far the solver gets during the time-step sweep's grasp claim.

    python benchmarks/solver_tolerance.py                       # every registered robot
    python benchmarks/solver_tolerance.py fetch spot --tolerances 1e-8,1e-11
    python benchmarks/solver_tolerance.py fetch --substeps 5,4  # at these steps (default: the declared one)
    python benchmarks/solver_tolerance.py --tolerances 1e-8,1e-11 --sim-freq fetch:160 \
        --test tests/test_fetch.py::test_gripper_grasps_lifts_and_holds_a_cube   # a robot's own test

MuJoCo's Newton solver stops when the cost's improvement or its gradient, both divided
by ``meaninertia * nv`` of the whole scene, falls below ``opt.tolerance``: a heavy robot
(a large ``meaninertia * nv``) makes the same tolerance looser, in absolute terms, for a
light body it holds. Per robot: ``meaninertia * nv`` of its ``Empty-v1`` scene and of its
``PickCube-v1`` scene (``-``: no PickCube for it), then, for each tolerance and step, the
grasp claim (``robot_agents.tuning.grasp_claim``, the same code the sweep runs: the first
grasp depth that holds, else the least slip) with every physics step's solver statistics
over the 2 s hold: iterations (mean, max; the share of steps with none, and with
``opt.iterations``), the share of steps that stopped on the improvement test with the
gradient still at or above the tolerance (unconverged), and the last iteration's
improvement (median) and gradient (median, largest) as MuJoCo scales them (per step the
largest over the islands). Only ``opt.tolerance`` differs between the runs of a
robot (set on each claim scene before its reset). ``--test``: instead, run these pytest
node ids once per tolerance, each in a process of its own where every registered robot
class's ``solver_tolerance`` is that tolerance (and ``--sim-freq UID:HZ`` that robot's
``sim_freq``), and report pytest's verdict. Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
import robot_agents.sim.world as world_module
from robot_agents.errors import RobotAgentsError
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, DEFAULT_SIM_FREQ, Scene
from robot_agents.tuning import grasp_claim as claim_module
from robot_agents.tuning.claims import Penetration, scene_setup
from robot_agents.tuning.grasp_claim import GRASP_HOLD_SECONDS


@dataclass
class SolverLog:
    """Per physics step of one scene: iterations (largest over islands), the last
    iteration's scaled improvement and gradient (largest over islands)."""

    model: mujoco.MjModel
    data: mujoco.MjData
    niter: list[int] = field(default_factory=list)
    improvement: list[float] = field(default_factory=list)
    gradient: list[float] = field(default_factory=list)

    def record(self) -> None:
        data = self.data
        islands = max(1, min(int(data.nisland), mujoco.mjNISLAND))
        counts = data.solver_niter[:islands]
        niter = int(counts.max())
        if niter == 0:
            improvement = gradient = 0.0
        else:
            solved = np.flatnonzero(counts)
            last = solved * mujoco.mjNSOLVER + np.minimum(counts[solved], mujoco.mjNSOLVER) - 1
            improvement = float(data.solver.improvement[last].max())
            gradient = float(data.solver.gradient[last].max())
        self.niter.append(niter)
        self.improvement.append(improvement)
        self.gradient.append(gradient)


class _SteppingMujoco:
    """The ``mujoco`` module as ``robot_agents.sim.world`` sees it while a claim runs:
    ``mj_step(m, d, nstep)`` as ``nstep`` single steps (the same arithmetic) with the
    solver's statistics recorded after each."""

    def __init__(self, logs: dict[int, SolverLog]) -> None:
        self._logs = logs

    def __getattr__(self, name: str) -> Any:
        return getattr(mujoco, name)

    def mj_step(self, model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
        log = self._logs.get(id(data))
        for _ in range(nstep):
            mujoco.mj_step(model, data)
            if log is not None:
                log.record()


@contextmanager
def solver_logged(tolerance: float | None) -> Iterator[list[SolverLog]]:
    """Within the block, every claim scene gets ``opt.tolerance = tolerance`` (``None``:
    as built) and a :class:`SolverLog` of its first env, in the order made."""
    logs: list[SolverLog] = []
    by_data: dict[int, SolverLog] = {}

    def setup(scene: Scene) -> None:
        if tolerance is not None:
            scene.model.opt.tolerance = tolerance
        log = SolverLog(scene.model, scene.world.datas[0])
        logs.append(log)
        by_data[id(log.data)] = log

    saved = world_module.mujoco
    world_module.mujoco = _SteppingMujoco(by_data)  # type: ignore[assignment]
    try:
        with scene_setup(setup):
            yield logs
    finally:
        world_module.mujoco = saved


def scale(uid: str, task: str) -> float | None:
    """``meaninertia * max(1, nv)`` of ``task``'s scene with this robot (``None``: the task
    does not take it)."""
    try:
        env = ra.make_env(task, robot_uids=uid)
    except RobotAgentsError:
        return None
    try:
        model = env.unwrapped.model
        return float(model.stat.meaninertia) * max(1, int(model.nv))
    finally:
        env.close()


@dataclass
class GraspRun:
    tolerance: float
    sim_freq: int
    slip_mm: float
    detail: str
    scale: float
    niter_mean: float
    niter_max: int
    capped: float
    improvement_median: float
    gradient_median: float
    gradient_max: float
    kept: float
    stopped_short: float


def grasp_run(uid: str, sim_freq: int, tolerance: float | None, control_freq: int) -> GraspRun | None:
    """The grasp claim of ``uid`` at ``sim_freq`` with ``tolerance`` and the solver's
    statistics over its hold (the attempt the claim reports: the first that holds, else
    the one with the least slip)."""
    cls = ra.get_agent(uid)
    slips: list[float] = []  # each two-finger attempt's slip, in the order tried (one log each)
    grasp_at = claim_module._grasp_at

    def recorded(*args: Any) -> tuple[float, str]:
        out = grasp_at(*args)
        slips.append(out[0])
        return out

    claim_module._grasp_at = recorded  # type: ignore[assignment]
    try:
        with solver_logged(tolerance) as logs:
            result = claim_module.grasp_claim(cls, sim_freq, control_freq, Penetration())
    finally:
        claim_module._grasp_at = grasp_at  # type: ignore[assignment]
    if result is None or not logs:
        return None
    # the attempt the claim reports: the least slip (the first that holds is the last tried)
    log = logs[int(np.argmin(slips))] if len(slips) == len(logs) else logs[-1]
    hold = round(GRASP_HOLD_SECONDS * control_freq) * (sim_freq // control_freq)
    niter = np.array(log.niter[-hold:])
    improvement = np.array(log.improvement[-hold:])
    gradient = np.array(log.gradient[-hold:])
    model = log.model
    solved = (niter > 0) & (niter < model.opt.iterations)
    return GraspRun(
        tolerance=float(model.opt.tolerance),
        sim_freq=sim_freq,
        slip_mm=1000.0 * float(result.value),
        detail=result.detail,
        scale=float(model.stat.meaninertia) * max(1, int(model.nv)),
        niter_mean=float(niter.mean()),
        niter_max=int(niter.max()),
        capped=float(np.mean(niter >= model.opt.iterations)),
        improvement_median=float(np.median(improvement[niter > 0])) if (niter > 0).any() else 0.0,
        gradient_median=float(np.median(gradient[niter > 0])) if (niter > 0).any() else 0.0,
        gradient_max=float(gradient.max()),
        kept=float(np.mean(niter == 0)),
        stopped_short=float(np.mean(solved & (gradient >= model.opt.tolerance))),
    )


ROOT = Path(__file__).resolve().parents[1]


def patch_classes(tolerance: str, sim_freq: str) -> None:
    """Every registered robot class's ``solver_tolerance`` (``none``: MuJoCo's 1e-8), and
    ``UID:HZ``'s ``sim_freq`` (subclasses that do not set their own follow it)."""
    for uid in ra.list_agents():
        ra.get_agent(uid).solver_tolerance = None if tolerance == "none" else float(tolerance)
    if sim_freq:
        uid, rate = sim_freq.split(":")
        ra.get_agent(uid).sim_freq = int(rate)


def run_tests(tests: Sequence[str], tolerances: Sequence[str], sim_freq: str) -> list[str]:
    """Each pytest node id at each tolerance, each run in a child process: table rows."""
    rows = ["| test | sim_freq | tolerance | pytest |", "|---|---|---|---|"]
    for test in tests:
        for tolerance in tolerances:
            child = [sys.executable, __file__, "--child", tolerance, "--sim-freq", sim_freq, test]
            run = subprocess.run(child, cwd=ROOT, capture_output=True, text=True, check=False)
            lines = run.stdout.strip().splitlines()
            verdict = lines[-1] if lines else f"exit {run.returncode}: {run.stderr.strip()[-200:]}"
            failure = next((line.strip() for line in lines if line.startswith("E  ")), "")
            print(f"{test} {sim_freq or 'declared'} {tolerance}: {verdict}", file=sys.stderr, flush=True)
            rows.append(
                f"| `{test}` | {sim_freq or 'declared'} | {tolerance} | {verdict}"
                + (f" (`{failure[:160]}`)" if failure else "")
                + " |"
            )
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("uids", nargs="*", help="robots (default: every registered robot)")
    parser.add_argument(
        "--tolerances", default="", help="tolerances to run the grasp claim with (default: the scene as built)"
    )
    parser.add_argument(
        "--substeps", default="", help="substeps per 20 Hz control step to run it at (default: the declared step)"
    )
    parser.add_argument("--no-scales", action="store_true", help="skip the Empty-v1 / PickCube-v1 scales")
    parser.add_argument("--test", action="append", default=[], help="a pytest node id to run at each tolerance")
    parser.add_argument("--sim-freq", default="", help="UID:HZ, that robot's sim_freq in the --test runs")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)  # a --test run's own process
    args, rest = parser.parse_known_args(argv)
    if args.child is not None:
        import pytest

        patch_classes(args.child, args.sim_freq)
        return int(pytest.main(["-q", "-p", "no:cacheprovider", *args.uids, *rest]))
    if rest:
        parser.error(f"unrecognized arguments: {' '.join(rest)}")
    if args.test:
        print("\n".join(run_tests(args.test, [t for t in args.tolerances.split(",") if t] or ["none"], args.sim_freq)))
        return 0
    uids = args.uids or ra.list_agents()
    tolerances: list[float | None] = [float(t) for t in args.tolerances.split(",") if t] or [None]
    control_freq = DEFAULT_CONTROL_FREQ
    print(f"load average {os.getloadavg()[0]:.2f}; control at {control_freq} Hz", file=sys.stderr)
    scale_rows = [
        "| robot | declared sim_freq | declared tolerance | meaninertia * nv, Empty-v1 | PickCube-v1 |",
        "|---|---|---|---|---|",
    ]
    rows = [
        "| robot | sim_freq (Hz) | tolerance | meaninertia * nv (claim scene) | slip (mm) | iterations mean / max "
        "| no iteration | at the cap | unconverged (stopped on the improvement test) | last improvement, median | last gradient, "
        "median / max | claim |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for uid in uids:
        cls = ra.get_agent(uid)
        declared = int(cls.sim_freq or DEFAULT_SIM_FREQ)
        if not args.no_scales:
            empty, pick = scale(uid, "Empty-v1"), scale(uid, "PickCube-v1")
            scale_rows.append(
                f"| `{uid}` | {declared} | {cls.solver_tolerance or '-'} | {empty:.3g} | "
                + (f"{pick:.3g} |" if pick is not None else "- |")
            )
        rates = [control_freq * int(n) for n in args.substeps.split(",") if n] or [declared]
        for rate in rates:
            for tolerance in tolerances:
                start = time.perf_counter()
                run = grasp_run(uid, rate, tolerance, control_freq)
                took = time.perf_counter() - start
                if run is None:
                    print(f"{uid}: no grasp claim", file=sys.stderr, flush=True)
                    break
                print(
                    f"{uid} {rate} Hz tol {run.tolerance:g}: slip {run.slip_mm:.3f} mm ({took:.1f} s)",
                    file=sys.stderr,
                    flush=True,
                )
                rows.append(
                    f"| `{uid}` | {rate} | {run.tolerance:g} | {run.scale:.3g} | {run.slip_mm:.3f} "
                    f"| {run.niter_mean:.2f} / {run.niter_max} | {100 * run.kept:.1f} % | {100 * run.capped:.1f} % "
                    f"| {100 * run.stopped_short:.1f} % | {run.improvement_median:.1e} "
                    f"| {run.gradient_median:.1e} / {run.gradient_max:.1e} | {run.detail} |"
                )
    if not args.no_scales:
        print("\n".join(scale_rows) + "\n")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
