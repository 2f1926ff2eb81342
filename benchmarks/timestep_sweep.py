"""The time-step sweep for built-in robots: per robot, every physics claim at each
physics step (largest first) and the largest step at which all hold.

    python benchmarks/timestep_sweep.py                 # every registered robot
    python benchmarks/timestep_sweep.py panda so100     # just these
    python benchmarks/timestep_sweep.py --output docs/timestep-sweep.md

Writes a markdown report (summary table, then each robot's table) to ``--output``
(default: stdout). Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence

import robot_agents as ra
from robot_agents.tuning.timestep import DEFAULT_SUBSTEPS, SweepResult, sweep_timestep


def report(results: Sequence[SweepResult], seconds: Sequence[float]) -> str:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [
        "# Time-step sweep",
        "",
        f"MuJoCo physics steps tried among the divisors of the control period; load average {load:.2f}.",
        "",
        "| robot | largest passing sim_freq (Hz) | declared sim_freq | sweep time (s) |",
        "|---|---|---|---|",
    ]
    for result, took in zip(results, seconds, strict=True):
        declared = ra.get_agent(result.uid).sim_freq
        lines.append(f"| `{result.uid}` | {result.largest_passing or 'none'} | {declared or 'default'} | {took:.1f} |")
    for result in results:
        lines += ["", f"## `{result.uid}`", "", result.table()]
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("uids", nargs="*", help="robots to sweep (default: every registered robot)")
    parser.add_argument("--output", default=None, help="markdown file to write (default: stdout)")
    parser.add_argument("--substeps", default=",".join(map(str, DEFAULT_SUBSTEPS)), help="substep counts to try")
    parser.add_argument("--all-steps", action="store_true", help="try every step (default: stop after two passes)")
    args = parser.parse_args(argv)
    uids = args.uids or ra.list_agents()
    substeps = [int(n) for n in args.substeps.split(",")]
    results, seconds = [], []
    for uid in uids:
        start = time.perf_counter()
        result = sweep_timestep(uid, substeps=substeps, stop_after=None if args.all_steps else 2)
        seconds.append(time.perf_counter() - start)
        results.append(result)
        print(f"{uid}: largest passing {result.largest_passing} Hz ({seconds[-1]:.1f} s)", file=sys.stderr)
    text = report(results, seconds)
    if args.output:
        with open(args.output, "w", encoding="utf-8") as handle:
            handle.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
