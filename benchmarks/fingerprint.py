"""A fingerprint of the built-in robots' behaviour: did a change move any trajectory?

For each registered robot (or the ones named), on ``Empty-v1`` at one env and the
robot's default steps:

- ``<uid>/model``: a hash of the compiled model's physical arrays (body masses and
  inertias, joint ranges, damping, armature and friction loss, joint-limit and contact
  parameters (``solref`` / ``solimp``, geom priority and contact dimensionality),
  equality constraints' data, actuator gains, biases and force ranges, geom sizes and
  friction, the time step, integrator, friction cone, impratio and constraint
  Jacobian: since 2026-11-29 21:45 UTC, when a contact's damping ratio and a joint
  limit's time constant changed robots without moving this hash);
- ``<uid>/<mode>``: for every control mode, a hash of the observations of a reset
  (seed 3) and 8 steps of uniform random actions in [-1, 1] (seed 0).

Two runs of the same code give the same hashes (the library is deterministic), so
comparing the fingerprints taken before and after a change lists exactly the robots and
modes whose physics or control it changed (16 hex digits of SHA-256 each; ~10 s for all
robots on the CI machine). Not a test: a change may move trajectories on purpose, and
the list says which.

Usage::

    python benchmarks/fingerprint.py before.json              # every robot
    python benchmarks/fingerprint.py after.json --robots so100 panda
    python benchmarks/fingerprint.py --compare before.json after.json
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

import robot_agents as ra

#: Random-action steps per mode after the reset.
STEPS = 8


def digest(*arrays: npt.ArrayLike) -> str:
    """The first 16 hex digits of the SHA-256 of ``arrays``' bytes, in order."""
    sha = hashlib.sha256()
    for array in arrays:
        sha.update(np.ascontiguousarray(array).tobytes())
    return sha.hexdigest()[:16]


def model_digest(m: mujoco.MjModel) -> str:
    """:func:`digest` of a compiled model's physical arrays (see the module doc)."""
    return digest(
        m.body_mass,
        m.body_inertia,
        m.jnt_range,
        m.dof_damping,
        m.dof_armature,
        m.actuator_gainprm,
        m.actuator_biasprm,
        m.actuator_forcerange,
        m.geom_size,
        m.geom_friction,
        m.opt.timestep,
        m.dof_frictionloss,
        m.jnt_solref,
        m.jnt_solimp,
        m.geom_solref,
        m.geom_solimp,
        m.geom_priority,
        m.geom_condim,
        m.eq_data,
        np.array([m.opt.integrator, m.opt.cone, m.opt.jacobian, m.opt.impratio], dtype=np.float64),
    )


def fingerprint(uids: Sequence[str]) -> dict[str, str]:
    """The hashes of robots ``uids`` (see the module doc), keyed ``uid/model`` and
    ``uid/mode``."""
    out: dict[str, str] = {}
    for uid in uids:
        probe = ra.make_env("Empty-v1", robot_uids=uid, num_envs=1)
        modes = list(probe.unwrapped.agent.modes())
        probe.close()
        for mode in modes:
            env = ra.make_env("Empty-v1", robot_uids=uid, num_envs=1, control_mode=mode)
            obs, _ = env.reset(seed=3)
            if mode == modes[0]:
                out[f"{uid}/model"] = model_digest(env.unwrapped.model)
            rng = np.random.default_rng(0)
            trajectory = [obs]
            for _ in range(STEPS):
                action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
                obs, *_ = env.step(action)
                trajectory.append(obs)
            out[f"{uid}/{mode}"] = digest(*trajectory)
            env.close()
    return out


def compare(before: dict[str, str], after: dict[str, str]) -> list[str]:
    """The keys whose hashes differ or that only one fingerprint has, sorted."""
    return sorted(key for key in set(before) | set(after) if before.get(key) != after.get(key))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("output", nargs="?", help="where to write the fingerprint (JSON)")
    parser.add_argument("--robots", nargs="*", default=None, help="robot uids (default: every registered robot)")
    parser.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"), help="list what differs between two")
    args = parser.parse_args(argv)
    if args.compare:
        before, after = (json.loads(Path(path).read_text()) for path in args.compare)
        differ = compare(before, after)
        print(f"{len(before)} and {len(after)} hashes: " + ("identical" if not differ else f"{len(differ)} differ"))
        for key in differ:
            print(f"  {key}")
        return 0
    if args.output is None:
        parser.error("give an output file, or --compare BEFORE AFTER")
    uids = sorted(ra.list_agents()) if args.robots is None else args.robots
    result = fingerprint(uids)
    Path(args.output).write_text(json.dumps(result, indent=0, sort_keys=True))
    print(f"{len(result)} hashes of {len(uids)} robots written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
