"""What a robot declares about its model reaches the compiled MuJoCo model."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from tests.conftest import make_pendulum_class


def robot_geoms(scene: ra.Scene, agent: ra.Agent) -> list[int]:
    model = scene.model
    return [g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.startswith(agent.prefix)]


def self_contacts(scene: ra.Scene, agent: ra.Agent) -> list[tuple[str, str]]:
    """Bodies (unprefixed names) of every contact between two of the robot's own geoms."""
    model, data = scene.model, scene.world.datas[0]
    mine = set(robot_geoms(scene, agent))
    body = lambda geom: model.body(model.geom_bodyid[geom]).name[len(agent.prefix) :]  # noqa: E731
    return [(body(c.geom1), body(c.geom2)) for c in data.contact[: data.ncon] if c.geom1 in mine and c.geom2 in mine]


def test_friction_materials_per_link_and_default(pendulum_file: Path) -> None:
    cls = make_pendulum_class(
        pendulum_file,
        link_materials={"link2": ra.FrictionMaterial(sliding=1.7, torsional=0.02, rolling=0.001)},
        default_material=ra.FrictionMaterial(sliding=0.4),
    )
    scene = ra.Scene(cls)
    model = scene.model
    for g in robot_geoms(scene, scene.agents[0]):
        body = model.body(model.geom_bodyid[g]).name
        expected = [1.7, 0.02, 0.001] if body.endswith("/link2") else [0.4, 0.005, 0.0001]
        np.testing.assert_allclose(model.geom_friction[g], expected)
    panda = ra.Scene("panda")
    pads = [g for g in range(panda.model.ngeom) if panda.model.geom(g).name.endswith("finger_pad")]
    assert len(pads) == 2
    np.testing.assert_allclose(panda.model.geom_friction[pads, 0], 2.0)


def test_gravity_compensation_on_named_bodies(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, gravity_compensation=("link2",))
    scene = ra.Scene(cls)
    model = scene.model
    gravcomp = {model.body(b).name.split("/")[-1]: model.body_gravcomp[b] for b in range(1, model.nbody)}
    assert gravcomp == {"base": 0.0, "link1": 0.0, "link2": 1.0, "tip": 0.0}


def _folded_panda_pose(scene: ra.Scene) -> np.ndarray:
    """A Panda configuration in which the arm touches itself (found by search, seeded)."""
    agent = scene.agents[0]
    rng = np.random.default_rng(5)
    for _ in range(2000):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        if self_contacts(scene, agent):
            return q
    raise AssertionError("no self-colliding configuration found")


def test_self_collisions_on_by_default_and_can_be_disabled() -> None:
    scene = ra.Scene("panda", floor=False)
    q = _folded_panda_pose(scene)
    assert self_contacts(scene, scene.agents[0])

    no_self = type("PandaNoSelf", (ra.get_agent("panda"),), {"uid": "panda_no_self", "disable_self_collisions": True})
    other = ra.Scene(no_self, floor=False)
    other.agents[0].reset(qpos=q)
    assert self_contacts(other, other.agents[0]) == []


def test_self_collision_exclusions_filter_named_pairs() -> None:
    scene = ra.Scene("panda", floor=False)
    q = _folded_panda_pose(scene)
    bodies = {tuple(sorted(pair)) for pair in self_contacts(scene, scene.agents[0])}
    excluded = type(
        "PandaExcl",
        (ra.get_agent("panda"),),
        {"uid": "panda_excl", "self_collision_exclusions": tuple(tuple(p) for p in bodies)},
    )
    other = ra.Scene(excluded, floor=False)
    other.agents[0].reset(qpos=q)
    assert self_contacts(other, other.agents[0]) == []
    assert other.model.nexclude == scene.model.nexclude + len(bodies)


def colliding_bodies(scene: ra.Scene, agent: ra.Agent) -> set[str]:
    """The robot's bodies (unprefixed names) with a geom that takes part in contacts."""
    model = scene.model
    return {
        model.body(model.geom_bodyid[g]).name[len(agent.prefix) :]
        for g in robot_geoms(scene, agent)
        if model.geom_contype[g] or model.geom_conaffinity[g]
    }


def test_collision_links_keep_contacts_on_the_named_bodies_only(pendulum_file: Path) -> None:
    full = ra.Scene(make_pendulum_class(pendulum_file))
    assert colliding_bodies(full, full.agents[0]) == {"base", "link1", "link2"}
    kept = ra.Scene(make_pendulum_class(pendulum_file, collision_links=("link2",)))
    model, agent = kept.model, kept.agents[0]
    assert colliding_bodies(kept, agent) == {"link2"}
    # The others keep their shapes and masses (drawn only): the same model otherwise.
    np.testing.assert_array_equal(model.geom_size, full.model.geom_size)
    np.testing.assert_array_equal(model.body_mass, full.model.body_mass)
    np.testing.assert_array_equal(model.geom_rgba, full.model.geom_rgba)
    # The panda folded onto itself: with the touching bodies' contacts off, none is left.
    panda = ra.Scene("panda", floor=False)
    q = _folded_panda_pose(panda)
    touching = {b for pair in self_contacts(panda, panda.agents[0]) for b in pair}
    everything = colliding_bodies(panda, panda.agents[0])
    cls = type(
        "PandaFewer", (ra.get_agent("panda"),), {"uid": "panda_fewer", "collision_links": tuple(everything - touching)}
    )
    other = ra.Scene(cls, floor=False)
    other.agents[0].reset(qpos=q)
    assert self_contacts(other, other.agents[0]) == []
    assert colliding_bodies(other, other.agents[0]) == everything - touching


def test_collision_links_refuse_unknown_bodies_bad_types_and_pieces(pendulum_file: Path) -> None:
    with pytest.raises(ra.UnknownNameError, match=r"collision_links.*'lnk2'.*link2"):
        ra.Scene(make_pendulum_class(pendulum_file, collision_links=("lnk2",)))
    for bad in ("link2", (1,), ("",), 3):
        with pytest.raises(ra.ConfigError, match=r"collision_links: expected a tuple of body names or None"):
            make_pendulum_class(pendulum_file, collision_links=bad).validate_definition()
    with pytest.raises(ra.UnknownNameError, match=r"'collision_link'. Did you mean 'collision_links'"):  # misspelt
        make_pendulum_class(pendulum_file, collision_link=("link2",)).validate_definition()
    robot = ra.get_agent("xarm6_robotiq")
    attachment = robot.attachments[0]
    piece = type("FewerPiece", (attachment.piece,), {"collision_links": ("base",)})
    cls = type(
        "XArmFewer", (robot,), {"uid": "xarm_fewer", "attachments": (dataclasses.replace(attachment, piece=piece),)}
    )
    with pytest.raises(ra.ConfigError, match=r"piece FewerPiece declares collision_links.*robot it is mounted on"):
        ra.Scene(cls)


def test_fixed_root_is_welded_and_free_root_has_a_free_joint(pendulum_file: Path) -> None:
    fixed = ra.Scene(make_pendulum_class(pendulum_file))
    assert mujoco.mjtJoint.mjJNT_FREE not in fixed.model.jnt_type
    free = ra.Scene(make_pendulum_class(pendulum_file, fix_root_link=False))
    assert list(free.model.jnt_type).count(mujoco.mjtJoint.mjJNT_FREE) == 1


GRIPPER_URDF = """<robot name="gripper">
  <link name="palm"><inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.02 0.12 0.02"/></geometry></collision></link>
  <link name="left"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 -0.03"/><geometry><box size="0.01 0.01 0.04"/></geometry></collision></link>
  <link name="right"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 -0.03"/><geometry><box size="0.01 0.01 0.04"/></geometry></collision></link>
  <joint name="left_slide" type="prismatic"><parent link="palm"/><child link="left"/><origin xyz="0 0.01 -0.01"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="20" velocity="0.1"/></joint>
  <joint name="right_slide" type="prismatic"><parent link="palm"/><child link="right"/><origin xyz="0 -0.01 -0.01"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="20" velocity="0.1"/><mimic joint="left_slide"/></joint>
</robot>"""


def test_urdf_mimic_joint_becomes_a_coupling(tmp_path: Path) -> None:
    path = tmp_path / "gripper.urdf"
    path.write_text(GRIPPER_URDF)

    class Gripper(ra.Agent):
        uid = "urdf_gripper"
        urdf_path = path
        keyframes = {"open": ra.Keyframe(qpos=(0.04, 0.04))}
        # Only the leading joint is actuated; the URDF <mimic> drags the other along.
        control_modes = {"grip": ra.PDJointPosConfig(joint_names=("left_slide",), stiffness=200.0, damping=5.0)}

    scene = ra.Scene(Gripper, floor=False)
    assert scene.model.neq == 1  # the <mimic> became a joint equality
    scene.reset()
    agent = scene.agents[0]
    for _ in range(20):
        agent.set_action([0.0])  # normalized 0 -> 0.02 m
        scene.step()
    np.testing.assert_allclose(agent.qpos[0], [0.02, 0.02], atol=1e-3)


def test_contact_softness_of_a_material_reaches_links_and_props(pendulum_file: Path) -> None:
    stiff = ra.FrictionMaterial(sliding=1.2, solref=(0.004, 1.0), solimp=(0.95, 0.99, 0.001))
    cls = make_pendulum_class(pendulum_file, link_materials={"link2": stiff})
    ball = ra.Prop("ball", "sphere", (0.01,), pos=(1.0, 0.0, 0.01), mass=0.008, friction=stiff)
    scene = ra.Scene(cls, props=[ball])
    model = scene.model
    for g in robot_geoms(scene, scene.agents[0]):
        on_pad = model.body(model.geom_bodyid[g]).name.endswith("/link2")
        np.testing.assert_array_equal(model.geom_solref[g], [0.004, 1.0] if on_pad else [0.02, 1.0])
        np.testing.assert_array_equal(
            model.geom_solimp[g], [0.95, 0.99, 0.001, 0.5, 2.0] if on_pad else [0.9, 0.95, 0.001, 0.5, 2.0]
        )
        assert model.geom_priority[g] == (1 if on_pad else 0)
        assert model.geom_friction[g, 0] == (1.2 if on_pad else 1.0)
    prop = model.geom("ball").id
    np.testing.assert_array_equal(model.geom_solref[prop], [0.004, 1.0])
    assert model.geom_priority[prop] == 1
    # friction only (every built-in robot's materials): no priority, the file's softness
    plain = ra.Scene(make_pendulum_class(pendulum_file, link_materials={"link2": ra.FrictionMaterial(sliding=2.0)}))
    assert not plain.model.geom_priority.any()


@pytest.mark.parametrize(("timeconst", "impedance"), [(0.02, 0.95), (0.004, 0.99)])
def test_a_pressed_light_ball_sinks_as_the_soft_contact_predicts(
    pendulum_file: Path, timeconst: float, impedance: float
) -> None:
    """The materials' docstring: at rest a contact pressed with F sinks
    (1 - d) * (F / m) * timeconst^2 (dampratio 1): an 8 g ball pressed onto the floor
    with 2 N, MuJoCo's default softness and the Panda's fingertip pads."""
    mass, radius, push = 0.008, 0.01, 2.0
    material = ra.FrictionMaterial(solref=(timeconst, 1.0), solimp=(impedance, impedance, 0.001))
    ball = ra.Prop("ball", "sphere", (radius,), pos=(1.0, 0.0, radius), mass=mass, friction=material)
    scene = ra.Scene(make_pendulum_class(pendulum_file), props=[ball], sim_freq=500)
    model, data = scene.model, scene.world.datas[0]
    body = model.body("ball").id
    for _ in range(1000):  # 2 s: settled
        data.xfrc_applied[body, 2] = -push
        mujoco.mj_step(model, data)
    depth = radius - data.xpos[body, 2]
    predicted = (1 - impedance) * (push + mass * 9.81) / mass * timeconst**2
    np.testing.assert_allclose(depth, predicted, rtol=1e-3)
    assert abs(data.qvel[model.body_dofadr[body] : model.body_dofadr[body] + 6]).max() < 1e-6
