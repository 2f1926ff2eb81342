"""The time-step sweep: the largest physics step at which all of a robot's physics
claims hold.

For a robot, :func:`sweep_timestep` tries physics steps from large to small among the
divisors of the control period (``1 / control_freq`` split into ``n`` substeps) and
measures, at each step, every claim the robot makes (:mod:`.claims`, which lists
them and their bounds).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from robot_agents.agent import Agent
from robot_agents.errors import ConfigError
from robot_agents.registry import agent_class
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ
from robot_agents.tuning.claims import CLAIMS, RANDOM_SEEDS, StepResult, checked_seeds, measure_step

#: Substeps per control step tried by default (control period / n), large steps first.
DEFAULT_SUBSTEPS = (2, 4, 5, 8, 10, 16, 20, 25, 32, 40, 50)
#: A claim failing at every step counts as failing the same way at a step where its
#: value is at most this many times its value at the finest step.
SAME_FAILURE = 2.0


@dataclass(frozen=True)
class SweepResult:
    """A robot's sweep: per step (largest first) its claims, and the largest step at
    which all held (``None``: none did)."""

    uid: str
    control_freq: int
    steps: tuple[StepResult, ...] = field(default_factory=tuple)

    @property
    def largest_passing(self) -> int | None:
        """The lowest ``sim_freq`` (largest step) at which every claim held, provided
        every smaller step tried also passed (a pass below a failure is not trusted)."""
        return self._largest_passing(())

    @property
    def failing_everywhere(self) -> tuple[str, ...]:
        """Claims that failed at every step tried (at least two): they do not depend on
        the step, so they do not limit it; they are the robot's to fix."""
        if len(self.steps) < 2:
            return ()
        failing = [
            name for name in CLAIMS if all((c := s.claim(name)) is not None and not c.passed for s in self.steps)
        ]
        return tuple(failing)

    @property
    def largest_passing_other_claims(self) -> int | None:
        """:attr:`largest_passing` judged without :attr:`failing_everywhere`, provided
        those fail no worse than :data:`SAME_FAILURE` times their value at the finest
        step tried (a failure that grows as the step grows does depend on the step)."""
        return self._largest_passing(self.failing_everywhere)

    def _largest_passing(self, ignored: Sequence[str]) -> int | None:
        ordered = sorted(self.steps, key=lambda s: -s.sim_freq)  # small steps first
        allowed = {}
        for name in ignored:
            claim = ordered[0].claim(name)
            if claim is not None:
                allowed[name] = max(SAME_FAILURE * claim.value, claim.bound)
        best = None
        for step in ordered:
            if not all(c.passed or c.value <= allowed.get(c.name, -np.inf) for c in step.claims):
                break
            best = step.sim_freq
        return best

    def table(self) -> str:
        """A markdown table: one row per step, one column per claim (value, pass)."""
        header = "| sim_freq (Hz) | step (ms) | " + " | ".join(CLAIMS) + " | all | random-action press (m) |"
        rows = [header, "|" + "---|" * (len(CLAIMS) + 4)]
        for step in self.steps:
            cells = []
            for name in CLAIMS:
                claim = step.claim(name)
                if claim is None:
                    cells.append("n/a")
                else:
                    cells.append(f"{claim.value:.3g}{'' if claim.passed else ' FAIL'}")
            ok = "yes" if step.passed else "no"
            rows.append(
                f"| {step.sim_freq} | {1000 / step.sim_freq:.3g} | "
                + " | ".join(cells)
                + f" | {ok} | {step.random_press_depth:.3g} |"
            )
        return "\n".join(rows)


def sweep_timestep(
    robot: str | type[Agent],
    control_freq: int = DEFAULT_CONTROL_FREQ,
    substeps: Sequence[int] = DEFAULT_SUBSTEPS,
    seeds: Sequence[int] = RANDOM_SEEDS,
    stop_after: int | None = 2,
    progress: Callable[[StepResult], None] | None = None,
) -> SweepResult:
    """Measure every claim of ``robot`` at ``sim_freq = control_freq * n`` for each
    ``n`` in ``substeps``, largest step first.

    ``stop_after``: measure the finest step first (a claim failing there may not
    depend on the step, see :attr:`SweepResult.largest_passing_other_claims`), then
    stop once this many coarser steps in a row have passed every other claim and failed
    those no worse than :data:`SAME_FAILURE` times their value there (the answer is then
    settled: smaller steps are not expected to fail); ``None`` tries them all, largest
    step first.
    ``seeds``: the random claim's action sequences at every step (each must pass).
    ``progress`` is called with each step's result as it is measured.
    """
    cls = agent_class(robot, "sweep_timestep")
    counts = sorted({int(n) for n in substeps})
    if not counts or counts[0] < 1:
        raise ConfigError(f"sweep_timestep: expected positive substep counts, got {list(substeps)!r}.")
    seeds = checked_seeds(seeds, "sweep_timestep")
    results: list[StepResult] = []
    allowed: dict[str, float] = {}
    if stop_after is not None and len(counts) > 1:
        # The finest step first: a claim that fails even there may not depend on the
        # step (the robot's to fix); coarser steps may fail it no worse than there.
        finest = measure_step(cls, control_freq * counts[-1], control_freq, seeds)
        results.append(finest)
        if progress is not None:
            progress(finest)
        allowed = {c.name: max(SAME_FAILURE * c.value, c.bound) for c in finest.claims if not c.passed}
        counts = counts[:-1]
    passes = 0
    for n in counts:
        step = measure_step(cls, control_freq * n, control_freq, seeds)
        results.append(step)
        if progress is not None:
            progress(step)
        passes = passes + 1 if all(c.passed or c.value <= allowed.get(c.name, -np.inf) for c in step.claims) else 0
        if stop_after is not None and passes >= stop_after:
            break
    results.sort(key=lambda s: s.sim_freq)
    return SweepResult(cls.uid or cls.__name__, control_freq, tuple(results))
