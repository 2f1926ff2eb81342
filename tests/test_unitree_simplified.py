"""The simplified Unitree variants (ManiSkill's ``unitree_go2_simplified_locomotion`` and
``unitree_h1_simplified``): our ``unitree_go2`` and ``unitree_h1`` with contacts on fewer
links (``collision_links``), the model, drives, keyframes and modes otherwise the same;
they stand on their legs, bit for bit as the full robots (the links that lost their
contacts touch nothing while standing), and random actions stay finite in every mode."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action

#: (variant, full robot).
VARIANTS = (("unitree_go2_simplified_locomotion", "unitree_go2"), ("unitree_h1_simplified", "unitree_h1"))
LEGS = ("FL", "FR", "RL", "RR")
#: The links with a collision shape in ManiSkill 3.0.1's
#: ``unitree_go2/urdf/go2_description_simplified_locomotion.urdf``: base, Head_upper and
#: Head_lower (fixed to the base: ours are on ``base``), the thighs and the feet.
GO2_PEER_COLLIDING = {"base", *(f"{leg}_{link}" for leg in LEGS for link in ("thigh", "foot"))}
#: The links whose collision shape in ``unitree_h1/urdf/h1_simplified.urdf`` is body-sized
#: (the torso box, pelvis sphere, thigh and shin cylinders, foot box, forearm cylinder;
#: the pelvis's is on our ``torso_link``, the capsule across the hips); the hip yaw / roll
#: and shoulder roll / yaw links have token shapes there (r 0.01-0.04 m, 1-2 cm long).
H1_KEPT = {
    "torso_link",
    *(f"{side}_{link}_link" for side in ("left", "right") for link in ("hip_pitch", "knee", "ankle", "elbow")),
}
H1_DROPPED = {
    f"{side}_{link}_link"
    for side in ("left", "right")
    for link in ("hip_yaw", "hip_roll", "shoulder_roll", "shoulder_yaw")
}
#: Fields of the compiled models that are the same in the variant and the full robot.
SAME_FIELDS = (
    "body_mass",
    "body_inertia",
    "body_pos",
    "body_quat",
    "body_ipos",
    "geom_type",
    "geom_size",
    "geom_pos",
    "geom_quat",
    "geom_friction",
    "geom_rgba",
    "jnt_range",
    "jnt_axis",
    "dof_armature",
    "dof_damping",
    "dof_frictionloss",
    "actuator_gainprm",
    "actuator_biasprm",
    "actuator_forcerange",
    "actuator_ctrlrange",
)


def colliding_bodies(scene: ra.Scene) -> set[str]:
    """The robot's bodies (unprefixed) with a geom that takes part in contacts."""
    model, prefix = scene.model, scene.agents[0].prefix
    names = (
        model.body(model.geom_bodyid[g]).name
        for g in range(model.ngeom)
        if model.geom_contype[g] or model.geom_conaffinity[g]
    )
    return {name[len(prefix) :] for name in names if name.startswith(prefix)}


def test_contacts_are_on_the_peers_links() -> None:
    go2, go2_full = ra.Scene(VARIANTS[0][0]), ra.Scene("unitree_go2")
    assert colliding_bodies(go2) == GO2_PEER_COLLIDING
    dropped = colliding_bodies(go2_full) - colliding_bodies(go2)
    assert dropped == {f"{leg}_{link}" for leg in LEGS for link in ("hip", "calf")}
    h1, h1_full = ra.Scene(VARIANTS[1][0]), ra.Scene("unitree_h1")
    assert colliding_bodies(h1) == H1_KEPT
    assert colliding_bodies(h1_full) - colliding_bodies(h1) == H1_DROPPED
    for scene in (go2, go2_full, h1, h1_full):
        scene.close()


@pytest.mark.parametrize(("uid", "full"), VARIANTS)
def test_the_model_drives_keyframes_and_modes_are_the_full_robots(uid: str, full: str) -> None:
    variant_cls, full_cls = ra.get_agent(uid), ra.get_agent(full)
    assert variant_cls.uid == uid and issubclass(variant_cls, full_cls)
    assert variant_cls.keyframes == full_cls.keyframes
    assert variant_cls.modes() == full_cls.modes()
    # The physics step is each variant's own sweep's (timestep.md): the H1's is the full
    # H1's (its drives' cycle bound), the simplified Go2's one tried step coarser.
    assert variant_cls.sim_freq is not None and full_cls.sim_freq is not None
    assert variant_cls.sim_freq <= full_cls.sim_freq
    # The whole model as drawn (the scene steps a twin without the visual-only geoms,
    # which the variant has more of).
    a, b = variant_cls.build_spec().compile(), full_cls.build_spec().compile()
    for field in SAME_FIELDS:
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), err_msg=field)
    differs = np.flatnonzero((a.geom_contype != b.geom_contype) | (a.geom_conaffinity != b.geom_conaffinity))
    assert len(differs) and np.all(a.geom_contype[differs] == 0) and np.all(a.geom_conaffinity[differs] == 0)


@pytest.mark.parametrize(("uid", "full"), VARIANTS)
def test_every_keyframe_stands_as_the_full_robot_bit_for_bit(uid: str, full: str) -> None:
    """Standing, only the feet touch anything, so dropping the other links' contacts
    changes nothing: 3 s of each keyframe's hold give the full robot's trajectory (both
    at the variant's physics step)."""
    scenes = {name: ra.Scene(name, sim_freq=ra.get_agent(uid).sim_freq) for name in (uid, full)}
    for key in ra.get_agent(full).keyframes:
        paths = {}
        for name, scene in scenes.items():
            agent = scene.agents[0]
            scene.reset(keyframes=key)
            hold = hold_action(agent)
            path = []
            for _ in range(3 * scene.control_freq):
                agent.set_action(hold)
                scene.step()
                path.append(np.concatenate([agent.base_pose[0], agent.qpos[0], agent.qvel[0]]))
            paths[name] = np.array(path)
            assert np.all(agent.is_standing()) and not np.any(agent.is_fallen()), (name, key)
            assert np.all(agent.is_static()), (name, key)
            start = agent.keyframes[key].base_pos[2] if agent.keyframes[key].base_pos else None
            assert start is not None and abs(float(agent.base_pose[0, 2]) - start) < 0.05, (name, key)
        np.testing.assert_array_equal(paths[uid], paths[full], err_msg=key)
    for scene in scenes.values():
        scene.close()


@pytest.mark.parametrize(("uid", "mode"), [(uid, mode) for uid, _ in VARIANTS for mode in ra.get_agent(uid).modes()])
def test_random_actions_for_10_s_stay_finite_in_every_mode(uid: str, mode: str) -> None:
    scene = ra.Scene(uid, control_modes=mode)
    agent = scene.agents[0]
    scene.reset()
    rng = np.random.default_rng(1)
    space = agent.single_action_space
    for _ in range(10 * scene.control_freq):
        agent.set_action(rng.uniform(space.low, space.high))
        scene.step()
        assert np.all(np.isfinite(agent.qpos)) and np.all(np.isfinite(agent.base_pose))
        assert np.max(np.abs(agent.qvel)) < 200.0  # rad/s: no blow-up
        assert abs(agent.base_pose[0, 2]) < 2.0 and np.max(np.abs(agent.base_pose[0, :2])) < 3.0
    assert not np.any(scene.world.instability_counts())
    scene.close()


def floor_touching(scene: ra.Scene, qpos: np.ndarray) -> set[str]:
    """The robot's bodies (unprefixed) touching the floor at ``qpos`` (the scene model's)."""
    model, prefix = scene.model, scene.agents[0].prefix
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    floor = model.geom("floor").id
    bodies = set()
    for c in data.contact[: data.ncon]:
        if floor in (c.geom1, c.geom2):
            other = c.geom2 if c.geom1 == floor else c.geom1
            bodies.add(model.body(model.geom_bodyid[other]).name[len(prefix) :])
    return bodies


def test_a_dropped_link_passes_through_what_the_full_robots_hits() -> None:
    """The standing Go2 lowered until its calves' upper cylinders reach 6 mm into the
    floor: the full robot's calves touch the floor, the simplified robot's do not; its
    feet touch alike."""
    full, simplified = ra.Scene("unitree_go2"), ra.Scene(VARIANTS[0][0])
    model, prefix = full.model, full.agents[0].prefix
    data = mujoco.MjData(model)
    root = model.joint(prefix + "root_free_joint").qposadr[0]
    data.qpos[root : root + 7] = (0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0)
    for leg in LEGS:
        for joint, angle in zip(("hip", "thigh", "calf"), (0.0, 0.9, -1.8), strict=True):
            data.qpos[model.joint(f"{prefix}{leg}_{joint}_joint").qposadr[0]] = angle
    mujoco.mj_forward(model, data)
    calf = model.body(prefix + "FL_calf").id
    upper = min(
        (g for g in range(model.ngeom) if model.geom_bodyid[g] == calf and model.geom_contype[g]),
        key=lambda g: -data.geom_xpos[g, 2],
    )
    radius = model.geom_size[upper, 0]
    data.qpos[root + 2] -= data.geom_xpos[upper, 2] - (radius - 0.006)  # its side 6 mm into the floor
    touching = {uid: floor_touching(scene, data.qpos) for uid, scene in (("full", full), ("simplified", simplified))}
    calves = {f"{leg}_calf" for leg in LEGS}
    feet = {f"{leg}_foot" for leg in LEGS}
    assert touching["full"] == calves | feet, touching
    assert touching["simplified"] == feet, touching
    full.close()
    simplified.close()
