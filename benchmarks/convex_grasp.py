"""A one-jaw gripper from a public model file closing on cubes, with and without
``convex_decomposition`` (docs/using-a-model-file.md, "Non-convex collision meshes").

The robot is the two-line robot of the file (its derived one-jaw gripper), plus a
third line ``convex_decomposition = True`` for the second run. From its default
keyframe the jaw is opened to ``--open`` rad; a cube (density 1000, edge from
``--edges``) is set ``--depth`` m into the mouth from the tool point towards the hand,
raised 1 mm above where it would first touch the jaws' collision geometry; the jaw's
target then ramps at 1 rad/s to the derived ``closed + squeeze`` over 2 s while the
cube is weightless (its weight balanced by an applied force), and the cube is held 2 s
under gravity. Printed per cube: the deepest contact penetration at the start (the
hull filling the mouth), the jaw's angle after closing, the cube's slip relative to
the hand over the hold, the deepest penetration during the hold, the jaw drive's torque
and the largest contact normal force on the cube at the end, and the bodies touching
the cube at the end.

The derived gripper's jaws have the built-in Panda's stiff fingertip contact
(``solref`` 0.002 s, which MuJoCo raises to two physics steps, ``solimp`` 0.95 0.99 0.001,
priority over the cube: ``robot_spec.set_pad_contact``). ``--soft`` declares MuJoCo's
default contact on them instead (``link_materials`` of :data:`SOFT`), as a file's gripper
had before 2026-11-28: MuJoCo's contacts are soft (``ra.FrictionMaterial``'s docstring),
pressed with force F a contact at rest sinks ``(1 - d) (F / m) timeconst^2`` deep, so a
light cube under a squeeze sinks into soft jaws.

Usage: ``python benchmarks/convex_grasp.py PATH/z1.urdf [--edges 0.012 0.016 0.02 0.024]
[--depth 0.015] [--open -0.9] [--soft] [--plain]`` (example-robot-data's Unitree Z1: ``pip download
--no-deps example-robot-data``; the decomposition is cached, see ``robot_agents.model.decompose``).
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.parts.declaration import Arm, Gripper

SECONDS = 2.0
RAMP = 1.0  # rad/s
#: MuJoCo's default contact (``solref`` 0.02 s, ``solimp`` 0.9 0.95 0.001), declared on the jaws.
SOFT = ra.FrictionMaterial(solref=(0.02, 1.0), solimp=(0.9, 0.95, 0.001))


def robot(path: Path, decomposed: bool, soft: bool = False) -> type[ra.Agent]:
    """The two-line robot of ``path``; ``decomposed``: with ``convex_decomposition``;
    ``soft``: the jaw's and the hand's colliding geoms get :data:`SOFT`."""
    attributes: dict[str, object] = {"uid": f"{path.stem}_{'convex' if decomposed else 'plain'}", "urdf_path": path}
    if decomposed:
        attributes["convex_decomposition"] = True
    cls = type("Convex" if decomposed else "Plain", (ra.Agent,), attributes)
    if not soft:
        return cls
    checked = cls.check()
    arm = next(p for p in checked.parts if isinstance(p, Arm))
    gripper = next(p for p in checked.parts if isinstance(p, Gripper))
    model = cls.build_spec().compile()
    jaw_body = model.body(model.jnt_bodyid[model.joint(checked.part_joints[gripper.name][0]).id]).name
    materials = {jaw_body: SOFT, arm.end_effectors[0].link: SOFT}
    return type(f"{cls.__name__}Soft", (cls,), {"uid": f"{cls.uid}_soft", "link_materials": materials})


def run(cls: type[ra.Agent], edge: float, depth: float, opened: float) -> str:
    checked = cls.check()
    arm = next(p for p in checked.parts if isinstance(p, Arm))
    gripper = next(p for p in checked.parts if isinstance(p, Gripper))
    jaw = checked.part_joints[gripper.name][0]
    spec = cls.build_spec()
    first = spec.compile()
    data = mujoco.MjData(first)
    keyframe = checked.keyframes["default"].qpos
    jaw_adr = int(first.jnt_qposadr[first.joint(jaw).id])
    hand = first.body(arm.end_effectors[0].link).id
    data.qpos[: len(keyframe)] = keyframe
    data.qpos[jaw_adr] = opened
    mujoco.mj_forward(first, data)
    rotation = data.xmat[hand].reshape(3, 3)
    tool = np.asarray(arm.end_effectors[0].pos, dtype=np.float64)
    centre = data.xpos[hand] + rotation @ (tool - np.array([depth, 0.0, 0.0]))
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, rotation.ravel())
    body = spec.worldbody.add_body(name="cube", pos=centre, quat=quat)
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[edge / 2] * 3, density=1000.0)
    model = spec.compile()
    data = mujoco.MjData(model)
    cube = model.body("cube").id
    jaw_actuator = next(a for a in range(model.nu) if model.actuator_trnid[a, 0] == model.joint(jaw).id)

    def place(lift: float) -> None:
        data.qpos[: len(keyframe)] = keyframe
        data.qpos[jaw_adr] = opened
        data.qpos[len(keyframe) : len(keyframe) + 7] = (*(centre + rotation[:, 2] * lift), *quat)
        mujoco.mj_forward(model, data)

    def deepest() -> float:
        return max(
            [
                -c.dist
                for c in data.contact[: data.ncon]
                if cube in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2])
            ]
            + [0.0]
        )

    place(0.0)
    at_start = deepest()
    lift = 0.0
    while deepest() > 0.0 and lift < 0.1:  # raise it until it clears the jaws, then 1 mm more
        lift += 0.001
        place(lift)
    place(lift + 0.001)
    for a in range(model.nu):
        data.ctrl[a] = data.qpos[model.jnt_qposadr[model.actuator_trnid[a, 0]]]
    closed = float(np.atleast_1d(gripper.closed)[0])
    target = closed + gripper.squeeze * float(np.sign(closed - opened))  # past closed by the derived squeeze
    weight = float(model.body_mass[cube]) * 9.81
    steps = round(SECONDS / model.opt.timestep)
    for i in range(steps):  # close on the weightless cube
        ramp = opened + np.sign(target - opened) * RAMP * i * model.opt.timestep
        data.ctrl[jaw_actuator] = min(ramp, target) if target > opened else max(ramp, target)
        data.xfrc_applied[cube, 2] = weight
        mujoco.mj_step(model, data)
    data.xfrc_applied[cube, 2] = 0.0
    jaw_angle = float(data.qpos[jaw_adr])

    def relative() -> np.ndarray:
        return np.asarray(data.xmat[hand].reshape(3, 3).T @ (data.xpos[cube] - data.xpos[hand]))

    start, slip, hold_depth = relative(), 0.0, 0.0
    for _ in range(steps):  # hold under gravity
        mujoco.mj_step(model, data)
        slip = max(slip, float(np.linalg.norm(relative() - start)))
        hold_depth = max(hold_depth, deepest())
    force, largest = np.zeros(6), 0.0
    for i, c in enumerate(data.contact[: data.ncon]):
        if cube in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]):
            mujoco.mj_contactForce(model, data, i, force)
            largest = max(largest, float(force[0]))
    torque = abs(float(data.actuator_force[jaw_actuator]))
    touching = sorted(
        {
            model.body(int(b)).name
            for c in data.contact[: data.ncon]
            for b in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2])
            if cube in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]) and b != cube
        }
    )
    return (
        f"| {'yes' if cls.convex_decomposition else 'no'} | {edge * 1000:.0f} | {at_start * 1000:.1f} | {jaw_angle:.3f} "
        f"| {slip * 1000:.1f} | {hold_depth * 1000:.1f} | {torque:.1f} | {largest:.1f} "
        f"| {', '.join(touching) or 'nothing (lost)'} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("path", type=Path, help="a model file whose derived gripper has one jaw (z1.urdf)")
    parser.add_argument("--edges", type=float, nargs="*", default=[0.012, 0.016, 0.02, 0.024], help="cube edges (m)")
    parser.add_argument("--depth", type=float, default=0.015, help="cube centre from the tool point into the mouth (m)")
    parser.add_argument("--open", type=float, default=-0.9, help="the jaw's angle before closing (rad)")
    parser.add_argument("--soft", action="store_true", help="the jaws get MuJoCo's default contact parameters")
    parser.add_argument("--plain", action="store_true", help="also run without the decomposition")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print(f"contact: {'MuJoCo defaults on the jaws' if args.soft else 'the derived gripper pads'}")
    print(
        "| decomposed | cube edge (mm) | penetration at start (mm) | jaw after closing (rad) | slip over 2 s hold (mm) "
        "| deepest penetration in the hold (mm) | jaw torque (N*m) | largest contact force (N) | touching at the end |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for decomposed in (False, True) if args.plain else (True,):
        cls = robot(args.path.resolve(), decomposed, args.soft)
        for edge in args.edges:
            print(run(cls, edge, args.depth, args.open), flush=True)


if __name__ == "__main__":
    main()
