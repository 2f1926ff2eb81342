"""What building a Scene costs for a robot class not checked yet (its check, then its
build), and how many times the model files are parsed for it: a composed built-in (a
fresh subclass of ``xarm6_robotiq``), the two-line robot of ``examples/my_arm.urdf``
and that file with the Robotiq 2F-85 mounted (``robot_from_file(..., gripper=...)``,
whose parts are inferred beside the piece's). Medians of ``--rounds`` builds, CPU time
of this process (``time.process_time``: the machine's other load counts less than in
wall time), after one build of each to warm imports and the pieces' own checks.

    python benchmarks/load_time.py --rounds 21

Columns: CPU ms per Scene; model-file parses per Scene (``load_model_spec`` calls);
CPU ms spent in them. Not run in CI.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import robot_agents as ra
from robot_agents.model import loading
from robot_agents.registry import get_agent
from robot_agents.robot_source import robot_from_file

ARM = Path(__file__).resolve().parents[1] / "examples" / "my_arm.urdf"


class Parses:
    """Counts and times ``load_model_spec`` wherever the library calls it from."""

    def __init__(self) -> None:
        self.count, self.seconds = 0, 0.0
        parse = loading.load_model_spec

        def counted(*args: Any, **kwargs: Any) -> Any:
            self.count += 1
            began = time.process_time()
            try:
                return parse(*args, **kwargs)
            finally:
                self.seconds += time.process_time() - began

        # the module that parses for a check: load_scope (an older tree: declaration)
        for name in ("robot_agents.model.load_scope", "robot_agents.agent.declaration"):
            module = sys.modules.get(name)
            if module is not None and hasattr(module, "load_model_spec"):
                module.load_model_spec = counted  # type: ignore[attr-defined]


def robots() -> dict[str, Callable[[], type[ra.Agent]]]:
    composed = get_agent("xarm6_robotiq")
    return {
        "xarm6_robotiq (a fresh subclass)": lambda: type("Fresh", (composed,), {}),
        "examples/my_arm.urdf (robot_from_file)": lambda: robot_from_file(ARM),
        "examples/my_arm.urdf + robotiq_2f85 at flange": lambda: robot_from_file(
            ARM, gripper="robotiq_2f85", at="flange"
        ),
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=21, help="Scenes built per robot (the median is shown)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", RuntimeWarning)  # the derived robots' notes
    parses = Parses()
    print("| robot | CPU ms per Scene | file parses | CPU ms parsing |")
    print("|---|---|---|---|")
    for label, make in robots().items():
        ra.Scene(make()).close()
        times, spent = [], []
        for _ in range(args.rounds):
            parses.count, parses.seconds = 0, 0.0
            began = time.process_time()
            ra.Scene(make()).close()
            times.append(time.process_time() - began)
            spent.append(parses.seconds)
        print(
            f"| {label} | {statistics.median(times) * 1000:.0f} | {parses.count} | {statistics.median(spent) * 1000:.1f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
