"""PickCube with a one-jaw gripper's close made gentle, on a two-line robot from a model
file: an experiment harness for the Z1's misses (docs/using-a-model-file.md, "The Z1's
PickCube misses"); the library and the solver of ``examples/scripted_pick.py`` are not
changed, the harness replaces their parts for its own envs only.

The two-line robot of ``FILE`` (or a registered robot, given its uid: a subclass of
it; ``--decompose``: with ``convex_decomposition = True``) runs ``PickCube-v1`` with the generic scripted solver, seeds ``0 .. --seeds - 1`` in one
batch; printed: the successes and the seeds that succeeded. What may be replaced:

- ``--cube-share S``: the cube's edge ``S`` times the layout's measured opening (the
  layout's own ``CUBE_PER_OPENING``, 0.5, without it);
- ``--against K``: the grasp point (where the cube's centre goes) ``K`` half-edges across
  from the tool point (a one-jaw gripper's closed tips, at its fixed jaw), along the
  layout's closing axis, instead of the middle of the measured opening;
- ``--rate R``: the close as a ramp: the jaw's command moves from where it is towards
  ``closed + squeeze`` by ``R`` of the stroke per control step, and once the jaw lags its
  command by more than ``--lag`` of the stroke (stalled on the cube), the command is held
  at where the jaw then is plus ``--squeeze`` of the stroke (the solver's own close
  commands ``closed + squeeze`` at once).

``--trace SEED`` runs that seed alone and prints, per control step from the first
contact with the cube, the jaw's position (rad), the cube's centre (m) and MuJoCo's
contact forces on the cube (normal, N) with the height of each contact above the cube's
centre (mm), by the body touching it.

Usage: ``python benchmarks/jaw_close.py z1.urdf|UID [--decompose] [--cube-share 0.3]
[--against 1.0] [--rate 0.05 --lag 0.05 --squeeze 0.1] [--seeds 20 | --trace 0]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import warnings
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.envs.tasks import layout as layouts
from robot_agents.robot_source import robot_from_file

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import scripted_pick  # (the solvers live with the examples)


class GentleClose:
    """The jaw's commands of a ramped close that stops pressing where the jaw stalls
    (see the module doc), per env; ``rate``, ``lag`` and ``squeeze`` in shares of the
    stroke."""

    def __init__(self, agent: ra.Agent, num_envs: int, rate: float, lag: float, squeeze: float) -> None:
        part = agent.gripper()
        opened, shut = part.positions(len(agent.part_joints[part.name]))
        self.open, closed = float(opened[0]), float(shut[0])  # the leader's
        self.stroke = closed - self.open  # signed: towards closed
        self.end = closed + np.sign(self.stroke) * part.squeeze
        self.index = agent.index.joint(agent.part_joints[part.name][0], "jaw_close").qpos_start
        self.rate, self.lag, self.squeeze = rate, lag, squeeze
        self.agent = agent
        self.command = np.full(num_envs, self.open)
        self.held = np.zeros(num_envs, dtype=bool)

    def next(self, gripper_open: np.ndarray) -> np.ndarray:
        """The jaw's commands ``(num_envs,)`` (rad) for this step, given which envs open."""
        jaw = self.agent.qpos[:, self.index]
        closing = ~gripper_open
        self.command[gripper_open], self.held[gripper_open] = self.open, False
        stalled = closing & ~self.held & ((self.command - jaw) / self.stroke > self.lag)
        self.command[stalled] = jaw[stalled] + self.squeeze * self.stroke
        self.held |= stalled
        moving = closing & ~self.held
        low, high = sorted((self.open, self.end))
        self.command[moving] = np.clip(self.command[moving] + self.rate * self.stroke, low, high)
        return self.command.copy()


def gentle_actions(rate: float, lag: float, squeeze: float) -> None:
    """Make the solver's ``Arm.action`` command the jaw as :class:`GentleClose` does."""
    plain = scripted_pick.Arm.action
    closes: dict[int, GentleClose] = {}

    def action(self: Any, arm_raw: np.ndarray, gripper_open: Any = None, base_speed: Any = None) -> np.ndarray:
        out: np.ndarray = plain(self, arm_raw, gripper_open, base_speed)
        if gripper_open is None or self.gripper is None:
            return out
        key = id(self.env)
        if key not in closes:
            closes[key] = GentleClose(self.agent, self.env.num_envs, rate, lag, squeeze)
        command = closes[key].next(np.asarray(gripper_open, dtype=bool))
        out[:, self.controller.slices[self.gripper]] = self.controller.parts[self.gripper].from_raw(command[:, None])
        return out

    scripted_pick.Arm.action = action  # type: ignore[method-assign]


def set_layout(cls: type[ra.Agent], cube_share: float | None, against: float | None) -> None:
    """Replace the cube's edge and the grasp point in ``cls``'s table-top layout."""
    layout = layouts.table_top_layout(cls)
    gripper = layout.gripper
    half = layout.cube_half_size if cube_share is None else 0.5 * cube_share * gripper.opening
    if against is not None:
        grasp = -np.asarray(gripper.closing_axis) * against * half
        gripper = dataclasses.replace(gripper, grasp_point=tuple(float(x) for x in grasp))
    layouts._LAYOUTS[cls] = dataclasses.replace(layout, cube_half_size=half, gripper=gripper)


def trace(env: Any) -> None:
    """Make ``env.step`` print the jaw, the cube and the contacts on it (module doc)."""
    model = env.model
    cube = model.body("cube").id
    part = env.agent.gripper()
    jaw = env.agent.index.joint(env.agent.part_joints[part.name][0], "trace").qpos_start
    plain, steps, touched = env.step, [0], [False]
    force = np.zeros(6)

    def step(action: np.ndarray) -> Any:
        out = plain(action)
        steps[0] += 1
        data = env.data
        centre = data.xpos[cube]
        cells = []
        for i in range(data.ncon):
            contact = data.contact[i]
            bodies = model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]
            if cube in bodies:
                other = bodies[1] if bodies[0] == cube else bodies[0]
                mujoco.mj_contactForce(model, data, i, force)
                name = model.body(other).name.rsplit("/", 1)[-1]
                cells.append(f"{name} {force[0]:.0f} N at {1000 * (contact.pos[2] - centre[2]):+.0f} mm")
        touched[0] |= any(not c.startswith("table") for c in cells)
        if touched[0]:
            jaw_at = float(env.agent.qpos[0, jaw])
            print(f"{steps[0]:3d} jaw {jaw_at:+.3f} cube {np.round(centre, 4)} | " + " | ".join(cells))
        return out

    env.step = step


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robot", help="a model file (its two-line robot) or a registered robot's uid")
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--trace", type=int, help="this seed alone, traced")
    parser.add_argument("--decompose", action="store_true", help="convex_decomposition = True")
    parser.add_argument("--cube-share", type=float, help="the cube's edge over the measured opening")
    parser.add_argument("--against", type=float, help="the grasp point this many half-edges from the tool point")
    parser.add_argument("--rate", type=float, help="the jaw's command ramp, strokes per control step")
    parser.add_argument("--lag", type=float, default=0.05, help="the lag (strokes) taken for a stall")
    parser.add_argument("--squeeze", type=float, default=0.1, help="past the stalled jaw (strokes)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    attrs: dict[str, object] = {"uid": "jaw_close"}
    if args.decompose:
        attrs["convex_decomposition"] = True
    registered = args.robot in ra.list_agents()
    base = ra.get_agent(args.robot) if registered else robot_from_file(Path(args.robot).resolve())
    cls = type("JawClose", (base,), attrs)
    ra.register_agent(cls, override=True)
    set_layout(cls, args.cube_share, args.against)
    if args.rate is not None:
        gentle_actions(args.rate, args.lag, args.squeeze)
    num_envs = 1 if args.trace is not None else args.seeds
    env = ra.make_env("PickCube-v1", robot_uids="jaw_close", num_envs=num_envs).unwrapped
    try:
        if args.trace is not None:
            trace(env)
        success = scripted_pick.solve_pick(env, args.trace or 0)
    finally:
        env.close()
    print(f"{int(success.sum())}/{num_envs}: seeds {(np.flatnonzero(success) + (args.trace or 0)).tolist()}")


if __name__ == "__main__":
    main()
