"""Controller semantics, checked against numbers on a small user robot and the Panda."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra


def make_scene(cls: type[ra.Agent], mode: str, num_envs: int = 1) -> tuple[ra.Scene, ra.Agent]:
    scene = ra.Scene(cls, num_envs=num_envs, control_modes=mode)
    scene.reset(keyframes="bent")
    return scene, scene.agents[0]


def run(scene: ra.Scene, agent: ra.Agent, action: object, steps: int) -> None:
    for _ in range(steps):
        agent.set_action(action)
        scene.step()


def test_pd_joint_pos_reaches_absolute_target(pendulum_cls: type[ra.Agent]) -> None:
    scene, agent = make_scene(pendulum_cls, "pd_joint_pos")
    run(scene, agent, [0.3, 0.4], 40)
    np.testing.assert_allclose(agent.qpos[0], [0.3, 0.4], atol=2e-3)
    # Un-normalized: clipped to the joint limits, the Box says so.
    np.testing.assert_allclose(agent.single_action_space.low, [-2.5, -2.5])
    run(scene, agent, [9.0, -9.0], 60)
    np.testing.assert_allclose(agent.qpos[0], [2.5, -2.5], atol=5e-3)


def test_delta_and_target_delta_accumulate_differently(pendulum_cls: type[ra.Agent]) -> None:
    # A target far beyond what one step reaches: delta-from-target keeps adding to the
    # target, delta-from-measured adds to where the joint actually is.
    scene, agent = make_scene(pendulum_cls, "pd_joint_target_delta_pos")
    start = agent.qpos[0].copy()
    run(scene, agent, [1.0, 0.0], 3)  # +0.1 rad per step on the shoulder, 3 steps
    target = agent.controller.parts["main"].get_state()["target_qpos"][0]
    np.testing.assert_allclose(target, start + np.array([0.3, 0.0]), atol=1e-12)
    obs = agent.get_proprioception()["controller"]["main"]["target_qpos"]
    np.testing.assert_allclose(obs[0], target)

    scene2, agent2 = make_scene(pendulum_cls, "pd_joint_delta_pos")
    agent2.set_action([1.0, 0.0])
    q_before = agent2.qpos[0].copy()
    target2 = agent2.controller.parts["main"].get_state()["target_qpos"][0]
    np.testing.assert_allclose(target2, q_before + np.array([0.1, 0.0]), atol=1e-12)
    scene2.step()
    q_mid = agent2.qpos[0].copy()
    agent2.set_action([1.0, 0.0])
    target3 = agent2.controller.parts["main"].get_state()["target_qpos"][0]
    np.testing.assert_allclose(target3, q_mid + np.array([0.1, 0.0]), atol=1e-12)  # measured, not previous target
    assert abs(target3[0] - (target2[0] + 0.1)) > 1e-4


def test_normalized_delta_maps_and_clips(pendulum_cls: type[ra.Agent]) -> None:
    _, agent = make_scene(pendulum_cls, "pd_joint_delta_pos")
    q = agent.qpos[0].copy()
    agent.set_action([0.5, 7.0])  # 7 clips to 1 -> +0.1 rad
    target = agent.controller.parts["main"].get_state()["target_qpos"][0]
    np.testing.assert_allclose(target, q + np.array([0.05, 0.1]), atol=1e-12)


def test_reverse_normalization_maps_minus_one_to_upper_and_inverts(pendulum_file: object) -> None:
    from tests.conftest import make_pendulum_class

    reverse = ra.PDJointPosConfig(joint_names=("shoulder",), lower=0.0, upper=0.9, reverse_normalization=True)
    plain = ra.PDJointPosConfig(joint_names=("elbow",), lower=0.0, upper=0.9)
    cls = make_pendulum_class(pendulum_file, control_modes={"m": {"a": reverse, "b": plain}})  # type: ignore[arg-type]
    scene = ra.Scene(cls)
    parts = scene.agents[0].controller.parts
    units = np.array([[-1.0], [1.0], [0.0], [7.0]])
    np.testing.assert_allclose(parts["a"].to_raw(units)[:, 0], [0.9, 0.0, 0.45, 0.0])
    np.testing.assert_allclose(parts["b"].to_raw(units)[:, 0], [0.0, 0.9, 0.45, 0.9])
    raw = np.array([[0.0], [0.2], [0.9]])
    for part in parts.values():  # from_raw inverts to_raw
        np.testing.assert_allclose(part.to_raw(part.from_raw(raw)), raw, atol=1e-15)
    np.testing.assert_allclose(parts["a"].from_raw(np.array([[-5.0]])), [[1.0]])  # clipped to lower: +1
    # the fused path of the whole mode maps the same way
    scene.agents[0].set_action([-1.0, -1.0])
    targets = [p.get_state()["target_qpos"][0, 0] for p in parts.values()]
    np.testing.assert_allclose(targets, [0.9, 0.0])
    scene.close()


def test_velocity_mode_tracks_velocity(pendulum_cls: type[ra.Agent]) -> None:
    scene, agent = make_scene(pendulum_cls, "pd_joint_vel")
    run(scene, agent, [0.5, 0.0], 10)  # normalized: 0.5 of 1 rad/s
    np.testing.assert_allclose(agent.qvel[0], [0.5, 0.0], atol=0.02)


def test_pos_vel_mode_action_layout(pendulum_cls: type[ra.Agent]) -> None:
    scene, agent = make_scene(pendulum_cls, "pd_joint_pos_vel")
    assert agent.single_action_space.shape == (4,)
    run(scene, agent, [0.2, -0.3, 0.0, 0.0], 40)
    np.testing.assert_allclose(agent.qpos[0], [0.2, -0.3], atol=2e-3)
    # A ramp at 0.5 rad/s in steps of 0.025 rad: without velocity feed-forward the PD lags
    # by kv * v / kp = 0.05 rad behind the ramp (0.0375 behind each step's target); with
    # it only the staircase of the targets remains.
    dt = scene.control_timestep
    lag = {}
    for feed_forward in (0.0, 0.5):
        agent.reset(qpos=[0.2, -0.3])
        errors = []
        for i in range(20):
            q_target = 0.2 + 0.5 * dt * (i + 1)
            agent.set_action([q_target, -0.3, feed_forward, 0.0])
            scene.step()
            errors.append(abs(agent.qpos[0, 0] - q_target))
        lag[feed_forward] = max(errors[10:])
    assert lag[0.0] > 0.03
    assert lag[0.5] < 0.015 and lag[0.5] < lag[0.0] / 2


def test_gains_applied_again_when_switching_back(pendulum_cls: type[ra.Agent]) -> None:
    scene, agent = make_scene(pendulum_cls, "pd_joint_pos")
    ids = agent.drives.actuator_ids
    np.testing.assert_allclose(scene.model.actuator_gainprm[ids, 0], 200.0)
    agent.set_control_mode("pd_joint_vel")
    np.testing.assert_allclose(scene.model.actuator_gainprm[ids, 0], 20.0)  # kv of velocity mode
    np.testing.assert_allclose(scene.model.actuator_biasprm[ids, 1], 0.0)
    scene.model.actuator_gainprm[ids, 0] = 1.0  # somebody tampers with the model
    agent.set_control_mode("pd_joint_pos")
    np.testing.assert_allclose(scene.model.actuator_gainprm[ids, 0], 200.0)
    np.testing.assert_allclose(scene.model.actuator_biasprm[ids, 1], -200.0)
    np.testing.assert_allclose(scene.model.actuator_forcerange[ids], [[-50.0, 50.0]] * 2)


def test_force_limit_is_respected(pendulum_cls: type[ra.Agent]) -> None:
    scene, agent = make_scene(pendulum_cls, "pd_joint_pos")
    agent.set_action([2.5, -2.5])  # errors of 2.0 and 1.7 rad: kp * error = 400 and 340 N*m
    data = scene.world.datas[0]
    data.ctrl[:] = scene.world.ctrl[0]
    mujoco.mj_forward(scene.model, data)
    np.testing.assert_allclose(data.actuator_force, [50.0, -50.0])
    peak = 0.0
    for _ in range(10):
        scene.step()
        peak = max(peak, float(np.max(np.abs(scene.world.datas[0].actuator_force))))
    assert peak <= 50.0 + 1e-9


def test_passive_joint_swings_under_gravity(pendulum_file: object) -> None:
    from tests.conftest import make_pendulum_class

    cls = make_pendulum_class(
        pendulum_file,  # type: ignore[arg-type]
        control_modes={
            "shoulder_only": {
                "arm": ra.PDJointPosConfig(joint_names=("shoulder",), normalize_action=False),
                "elbow": ra.PassiveConfig(joint_names=("elbow",)),
            }
        },
        gravity_compensation=False,
    )
    scene = ra.Scene(cls, control_modes="shoulder_only")
    scene.reset(keyframes="down")
    agent = scene.agents[0]
    assert agent.single_action_space.shape == (1,)
    agent.reset(qpos=[0.0, 0.6])  # elbow raised, shoulder held
    for _ in range(5):
        agent.set_action([0.0])
        scene.step()
    assert agent.qpos[0, 1] < 0.6 - 0.05  # the passive elbow falls back toward hanging
    assert abs(scene.world.datas[0].actuator_force[1]) < 1e-12


def test_interpolated_targets_move_smoothly(pendulum_file: object) -> None:
    from tests.conftest import make_pendulum_class

    config = ra.PDJointPosConfig(joint_names=("shoulder", "elbow"), normalize_action=False, interpolate=True)
    cls = make_pendulum_class(pendulum_file, control_modes={"smooth": config})  # type: ignore[arg-type]
    scene = ra.Scene(cls)
    scene.reset(keyframes="down")
    agent = scene.agents[0]
    assert agent.needs_substep
    seen: list[float] = []
    original = scene.world._step_all

    def spy(nstep: int) -> None:
        seen.append(float(scene.world.ctrl[0, 0]))
        original(nstep)

    scene.world._step_all = spy  # type: ignore[method-assign]
    agent.set_action([0.5, 0.0])
    scene.step()
    assert len(seen) == scene.substeps
    np.testing.assert_allclose(seen, 0.5 * np.arange(1, scene.substeps + 1) / scene.substeps, atol=1e-12)


def test_mimic_fingers_follow_one_action() -> None:
    scene = ra.Scene("panda", control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    fingers = [agent.joint_names.index(j) for j in agent.part_joints["gripper"]]
    hold = agent.qpos[0, :7]
    for action, expected in ((-1.0, 0.0), (0.0, 0.015), (1.0, 0.04)):
        for _ in range(20):
            agent.set_action(np.concatenate([hold, [action]]))
            scene.step()
        np.testing.assert_allclose(agent.qpos[0, fingers], [expected, expected], atol=2e-3)
        assert abs(agent.qpos[0, fingers[0]] - agent.qpos[0, fingers[1]]) < 1e-4


def test_config_validation_messages() -> None:
    with pytest.raises(ra.ConfigError, match="use_target=True needs use_delta=True"):
        ra.PDJointPosConfig(joint_names=("a",), use_target=True)
    with pytest.raises(ra.ConfigError, match="explicit lower/upper"):
        ra.PDJointPosConfig(joint_names=("a",), use_delta=True)
    with pytest.raises(ra.ConfigError, match="listed twice"):
        ra.PDJointPosConfig(joint_names=("a", "a"))
    with pytest.raises(ra.ConfigError, match="at least 2 joints"):
        ra.PDJointPosMimicConfig(joint_names=("a",))
    with pytest.raises(ra.ConfigError, match="stiffness > 0"):
        ra.PDJointPosVelConfig(joint_names=("a",), stiffness=0.0)


def test_per_joint_gain_length_checked(pendulum_file: object) -> None:
    from tests.conftest import make_pendulum_class

    cls = make_pendulum_class(
        pendulum_file,  # type: ignore[arg-type]
        control_modes={"bad": ra.PDJointPosConfig(joint_names=("shoulder", "elbow"), stiffness=(1.0, 2.0, 3.0))},
    )
    with pytest.raises(ra.ConfigError, match=r"stiffness: expected 1 or 2 values"):
        ra.Scene(cls)


def test_hold_action_commands_zero_under_asymmetric_normalized_bounds(pendulum_file: object) -> None:
    """``checks.hold_action`` asks for no motion in every mode: with asymmetric bounds a
    normalized zero is not a raw zero (it is the middle of the range), so the hold must
    map raw zero through the mode's normalization."""
    from robot_agents.checks import hold_action
    from tests.conftest import make_pendulum_class

    velocity = ra.PDJointVelConfig(joint_names=("shoulder",), lower=-0.5, upper=1.5)
    delta = ra.PDJointPosConfig(joint_names=("elbow",), lower=-0.05, upper=0.15, use_delta=True)
    cls = make_pendulum_class(pendulum_file, control_modes={"m": {"a": velocity, "b": delta}})  # type: ignore[arg-type]
    scene = ra.Scene(cls)
    scene.reset()
    agent = scene.agents[0]
    hold = hold_action(agent)
    np.testing.assert_allclose(hold, [-0.5, -0.5])  # raw 0 in [-0.5, 1.5] and in [-0.05, 0.15]
    parts = agent.controller.parts
    np.testing.assert_allclose([parts["a"].to_raw(hold[None, :1])[0, 0], parts["b"].to_raw(hold[None, 1:])[0, 0]], 0.0)
    start = agent.qpos[0].copy()
    for _ in range(20):
        agent.set_action(hold)
        scene.step()
    np.testing.assert_allclose(agent.qpos[0], start, atol=1e-3)  # held, not driven at 0.5 rad/s
    scene.close()


def test_velocity_targets_are_met_on_joints_with_their_own_damping(tmp_path: object) -> None:
    """A joint whose model gives it damping ``b`` (``dof_damping``) under a velocity
    servo ``kv (qd* - qd)`` settles at ``kv / (kv + b)`` of the target unless the drive
    feeds ``b qd*`` forward: the shoulder here (kv 20, b 10) reached 2/3 of it."""
    from pathlib import Path

    from tests.conftest import PENDULUM_MJCF, make_pendulum_class

    path = Path(str(tmp_path)) / "damped.xml"
    path.write_text(PENDULUM_MJCF.replace('name="shoulder"', 'name="shoulder" damping="10"'))
    cls = make_pendulum_class(path, uid="test_damped_pendulum")
    scene = ra.Scene(cls, control_modes="pd_joint_vel")
    scene.reset(keyframes="down")
    agent = scene.agents[0]
    assert scene.model.dof_damping[agent.dof_adr[0]] == 10.0
    run(scene, agent, [0.5, 0.0], 10)  # 0.5 rad/s
    np.testing.assert_allclose(agent.qvel[0, 0], 0.5, rtol=0.01)
    scene.close()
    # a plain PD loop (damping_feedforward=False, Unitree's motors) settles where the real
    # one does against that damping: kv / (kv + b) = 2/3 of the target
    plain = ra.PDActuator(
        joints=("shoulder", "elbow"), stiffness=200.0, damping=20.0, effort_limit=50.0, damping_feedforward=False
    )
    scene = ra.Scene(
        make_pendulum_class(path, uid="test_plain_pd_pendulum", actuators=(plain,)), control_modes="pd_joint_vel"
    )
    scene.reset(keyframes="down")
    agent = scene.agents[0]
    run(scene, agent, [0.5, 0.0], 10)
    np.testing.assert_allclose(agent.qvel[0, 0], 0.5 * 20 / 30, rtol=0.01)
    scene.close()
    with pytest.raises(ra.ConfigError, match=r"PDActuator.damping_feedforward: expected True or False, got 1"):
        ra.PDActuator(joints="shoulder", stiffness=1.0, damping_feedforward=1)  # type: ignore[arg-type]


@pytest.mark.parametrize(("joint", "speed"), [("joint_wrist_roll", 0.3), ("joint_arm_l0", 0.05)])
def test_stretch_velocity_mode_reaches_the_commanded_speed(joint: str, speed: float) -> None:
    """Stretch's wrist joints carry damping 1 N*m*s/rad against a kv of 1-3 (the roll
    turned at half its target speed) and its telescope's three follower segments 5 N*s/m
    each on top of the leader's 5 against kv 150 (0.88 of it): the drives feed the
    joints' own damping, the followers' included, forward."""
    scene = ra.Scene("stretch", control_modes="pd_joint_vel")
    scene.reset()
    agent = scene.agents[0]
    arm, part = agent.controller.parts["arm"], agent.controller.slices["arm"]
    index = arm.binding.joint_names.index(joint)
    action = np.zeros(agent.controller.action_dim)
    action[part.start + index] = arm.from_raw(np.eye(arm.action_dim)[index] * speed)[index]
    run(scene, agent, action, 20)  # 1 s
    np.testing.assert_allclose(agent.qvel[0, arm.binding.dof_adr[index]], speed, rtol=0.02)
    scene.close()


# A turntable on a continuous (unlimited) hinge, with a limited tilt joint on it.
SPINNER_MJCF = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 0.5">
      <geom type="box" size="0.05 0.05 0.05" mass="1"/>
      <body name="rotor" pos="0 0 0.1">
        <joint name="spin" axis="0 0 1" damping="0.01"/>
        <geom type="box" size="0.1 0.02 0.02" mass="0.2"/>
        <body name="arm" pos="0.1 0 0">
          <joint name="tilt" axis="0 1 0" range="-1 1"/>
          <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01" mass="0.05"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="spin_drive" joint="spin" kp="5" kv="0.5"/>
    <position name="tilt_drive" joint="tilt" kp="5" kv="0.2" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


def spun_spinner(tmp_path: object) -> tuple[ra.Scene, ra.Agent]:
    """The two-line spinner robot, its hinge turned to 7.5 rad (past one turn) at 1 rad/s
    in ``pd_joint_vel`` and stopped there."""
    from pathlib import Path

    from robot_agents.robot_source import robot_from_file

    path = Path(str(tmp_path)) / "spinner.xml"
    path.write_text(SPINNER_MJCF)
    scene = ra.Scene(robot_from_file(path), control_modes="pd_joint_vel")
    scene.reset()
    agent = scene.agents[0]
    velocity = agent.controller.parts["main"]
    run(scene, agent, velocity.from_raw(np.array([1.0, 0.0])), 150)  # 7.5 s at 20 Hz
    run(scene, agent, velocity.from_raw(np.zeros(2)), 40)
    assert agent.qpos[0, 0] == pytest.approx(7.5, abs=1e-3)
    return scene, agent


@pytest.mark.parametrize("mode", ["pd_joint_pos", "pd_joint_pos_vel"])
def test_an_unlimited_hinge_holds_past_a_turn_and_takes_absolute_targets_the_short_way(
    tmp_path: object, mode: str
) -> None:
    """A continuous hinge at 7.5 rad (after turning in velocity mode): the absolute mode's
    hold keeps it there (clipped to the +-2 pi action bound it swung back 1.22 rad to
    2 pi), and a target of pi - 0.1 is taken modulo 2 pi to 3 pi - 0.1, the angle nearest
    the measured one (it went down 4.4 rad to pi - 0.1 instead of up 1.8 rad). The
    limited tilt joint takes its targets as given, bit for bit."""
    from robot_agents.checks import hold_action

    scene, agent = spun_spinner(tmp_path)
    agent.set_control_mode(mode)
    controller = agent.controller.parts["main"]
    np.testing.assert_allclose(controller.raw_low[:2], [-2 * np.pi, -1.0])  # bounds unchanged
    start = agent.qpos[0].copy()
    hold = hold_action(agent)
    assert -2 * np.pi <= controller.to_raw(hold[None])[0, 0] <= 2 * np.pi
    run(scene, agent, hold, 20)
    np.testing.assert_allclose(agent.qpos[0], start, atol=1e-6)
    np.testing.assert_allclose(controller.get_state()["target_qpos"][0, 0], start[0], rtol=0, atol=1e-12)

    action = controller.from_raw(np.array([np.pi - 0.1, 0.3] + [0.0, 0.0] * (mode == "pd_joint_pos_vel")))
    path = []
    for _ in range(40):
        agent.set_action(action)
        scene.step()
        path.append(agent.qpos[0, 0])
    target = controller.get_state()["target_qpos"][0]
    assert target[0] == pytest.approx(3 * np.pi - 0.1, abs=1e-12)
    assert target[1] == controller.to_raw(action[None])[0, 1]  # the limited joint: as given
    assert np.all(np.diff(path) > -1e-3)  # up the short way, never back down
    np.testing.assert_allclose(agent.qpos[0, :2], [3 * np.pi - 0.1, 0.3], atol=5e-3)
    scene.close()


def test_delta_from_target_turns_an_unlimited_hinge_past_a_turn(tmp_path: object) -> None:
    """Delta-from-target adds to the current target with no bound on a continuous hinge
    (no clip at +-2 pi, no wrap): ten steps of +0.1 rad from 7.5 rad reach 8.5 rad."""
    scene, agent = spun_spinner(tmp_path)
    agent.set_control_mode("pd_joint_target_delta_pos")
    controller = agent.controller.parts["main"]
    start = controller.get_state()["target_qpos"][0, 0]
    run(scene, agent, controller.from_raw(np.array([0.1, 0.0])), 10)
    assert controller.get_state()["target_qpos"][0, 0] == pytest.approx(start + 1.0, abs=1e-12)
    run(scene, agent, controller.from_raw(np.zeros(2)), 40)
    assert agent.qpos[0, 0] == pytest.approx(start + 1.0, abs=5e-3)
    scene.close()


# A continuous (unlimited) hinge leading a limited flap through a URDF-style mimic
# equality, flap = 0.5 spin: the flap's limits (+-1 rad) bound the spin to +-2 rad.
MIMIC_MJCF = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 0.5">
      <geom type="box" size="0.05 0.05 0.05" mass="1"/>
      <body name="rotor" pos="0 0 0.1">
        <joint name="spin" axis="0 0 1" damping="0.01"/>
        <geom type="box" size="0.1 0.02 0.02" mass="0.2"/>
      </body>
      <body name="flap" pos="0 0.1 0">
        <joint name="flap" axis="1 0 0" range="-1 1" damping="0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0.1 0" size="0.01" mass="0.05"/>
      </body>
    </body>
  </worldbody>
  <equality>
    <joint joint1="flap" joint2="spin" polycoef="0 0.5 0 0 0"/>
  </equality>
  <actuator>
    <position name="spin_drive" joint="spin" kp="5" kv="0.5"/>
  </actuator>
</mujoco>
"""


def mimic_robot(tmp_path: object, equality: bool = True, follower: str = 'range="-1 1"') -> type[ra.Agent]:
    """The two-line mimic robot of :data:`MIMIC_MJCF`; without the ``equality`` both
    joints are driven and only a mimic mode couples them; ``follower``: the flap's
    range attribute (empty: an unlimited hinge too)."""
    import re
    from pathlib import Path

    from robot_agents.robot_source import robot_from_file

    text = MIMIC_MJCF.replace('range="-1 1"', follower)
    if not equality:
        text = re.sub(r"<equality>.*?</equality>\n", "", text, flags=re.S)
        text = text.replace(
            "</actuator>", '  <position name="flap_drive" joint="flap" kp="5" kv="0.2"/>\n  </actuator>'
        )
    path = Path(str(tmp_path)) / f"mimic{equality}{len(follower)}.xml"
    path.write_text(text)
    return robot_from_file(path)


@pytest.mark.parametrize("mode", ["pd_joint_pos", "pd_joint_pos_vel"])
def test_an_unlimited_hinge_tied_to_a_limited_mimic_is_limited_by_it(tmp_path: object, mode: str) -> None:
    """A continuous hinge whose mimic follower (flap = 0.5 spin, an equality) is limited
    to +-1 rad can turn +-2 rad only: it is no longer periodic. From 1.9 rad a target of
    -1.5 rad goes there; taken modulo a turn to the angle nearest the measured one, it was
    4.78 rad, which the flap's limit blocked: the hinge stalled at 4.32 and the soft
    equality dragged the flap 0.51 rad past its limit. Its action is bounded to +-2 rad."""
    scene = ra.Scene(mimic_robot(tmp_path), control_modes=mode)
    scene.reset()
    agent = scene.agents[0]
    controller = agent.controller.parts["main"]
    assert not controller.binding.periodic[0]
    np.testing.assert_array_equal(controller.raw_low[:1], [-2.0])
    np.testing.assert_array_equal(controller.raw_high[:1], [2.0])
    speeds = [0.0] * (mode == "pd_joint_pos_vel")
    run(scene, agent, controller.from_raw(np.array([1.9, *speeds])), 60)
    np.testing.assert_allclose(agent.qpos[0], [1.9, 0.95], atol=1e-3)
    run(scene, agent, controller.from_raw(np.array([-1.5, *speeds])), 60)
    assert controller.get_state()["target_qpos"][0, 0] == -1.5
    np.testing.assert_allclose(agent.qpos[0], [-1.5, -0.75], atol=1e-3)
    scene.close()


def test_a_mimic_mode_with_an_unlimited_leader_moves_its_followers_with_it(tmp_path: object) -> None:
    """Both joints driven, coupled only by a mimic mode (flap = 0.5 spin). A limited
    follower bounds the leader (to +-2 rad): the leader's target is no longer taken
    modulo a turn (from 1.9 rad, -1.5 rad went to 4.78 rad while the flap went to -0.75),
    and target deltas stop at the pair's limits together (the leader ran on to 11 rad
    with the flap at its limit). An unlimited follower turning twice as fast keeps the
    leader periodic, and the leader's turns reach the follower: from (7.5, 15) rad a
    target of pi - 0.1 sends (3 pi - 0.1, 6 pi - 0.2); each taken to its own nearest
    turn, the follower's was 4 pi - 0.2, a turn away from its leader's."""
    mimic = ra.PDJointPosMimicConfig
    joints, ratio = ("spin", "flap"), (1.0, 0.5)

    def modes(base: type[ra.Agent], ratio: tuple[float, float]) -> type[ra.Agent]:
        configs = {
            "abs": mimic(joint_names=joints, normalize_action=False, multipliers=ratio),
            "tdelta": mimic(
                joint_names=joints, lower=-0.1, upper=0.1, use_delta=True, use_target=True, multipliers=ratio
            ),
        }
        return type("Mimic", (base,), {"default_control_mode": "abs", "control_modes": configs})

    scene = ra.Scene(modes(mimic_robot(tmp_path, equality=False), ratio))
    scene.reset()
    agent = scene.agents[0]
    controller = agent.controller.parts["main"]
    np.testing.assert_array_equal([controller.raw_low[0], controller.raw_high[0]], [-2.0, 2.0])
    run(scene, agent, np.array([1.9]), 60)
    run(scene, agent, np.array([-1.5]), 60)
    np.testing.assert_array_equal(controller.get_state()["target_qpos"][0], [-1.5, -0.75])
    np.testing.assert_allclose(agent.qpos[0], [-1.5, -0.75], atol=1e-3)
    agent.set_control_mode("tdelta")
    run(scene, agent, np.array([1.0]), 60)
    np.testing.assert_array_equal(agent.controller.parts["main"].get_state()["target_qpos"][0], [2.0, 1.0])
    scene.close()

    scene = ra.Scene(modes(mimic_robot(tmp_path, equality=False, follower=""), (1.0, 2.0)))
    scene.reset()
    agent = scene.agents[0]
    controller = agent.controller.parts["main"]
    assert controller.raw_low[0] == -2 * np.pi
    agent.reset(qpos=np.array([7.5, 15.0]))
    agent.set_control_mode("abs")  # holds the measured pose
    run(scene, agent, controller.from_raw(np.array([np.pi - 0.1])), 1)
    np.testing.assert_allclose(controller.get_state()["target_qpos"][0], [3 * np.pi - 0.1, 6 * np.pi - 0.2], rtol=1e-15)
    scene.close()


def test_a_mimic_delta_from_the_measured_pose_keeps_the_followers_on_the_leaders_relation(tmp_path: object) -> None:
    """Both joints driven, coupled only by a mimic mode (flap = 0.5 spin + 0.1), the
    delta added to the measured pose. Each joint added its share to its own measured
    position, so the followers drifted from the relation by what each drive lagged:
    after 15 steps of +0.05 rad the flap was 0.12 rad off it and stayed there when held
    (0.1188 measured with the offset 0). The followers' targets come from the leader's
    measured position through the relation, as in the absolute mode: exact in every
    target, and the pose settles on it."""
    cls = mimic_robot(tmp_path, equality=False)
    delta = ra.PDJointPosMimicConfig(
        joint_names=("spin", "flap"),
        lower=-0.1,
        upper=0.1,
        use_delta=True,
        normalize_action=False,
        multipliers=(1.0, 0.5),
        offsets=(0.0, 0.1),
    )
    modes = {"delta": delta}
    scene = ra.Scene(type("MimicDelta", (cls,), {"default_control_mode": "delta", "control_modes": modes}))
    scene.reset()
    agent = scene.agents[0]
    controller = agent.controller.parts["main"]
    for _ in range(15):
        spin = agent.qpos[0, 0]
        run(scene, agent, np.array([0.05]), 1)
        target = controller.get_state()["target_qpos"][0]
        np.testing.assert_array_equal(target, [spin + 0.05, 0.5 * (spin + 0.05) + 0.1])
    assert 0.25 < agent.qpos[0, 0] < 0.35  # it moved (0.293)
    run(scene, agent, np.array([0.0]), 40)
    assert agent.qpos[0, 1] == pytest.approx(0.5 * agent.qpos[0, 0] + 0.1, abs=1e-9)
    scene.close()
    # the leader's position in action units needs its multiplier
    with pytest.raises(ra.ConfigError, match=r"nonzero multipliers\[0\].*\(0\.0, 1\.0\)"):
        ra.PDJointPosMimicConfig(joint_names=("a", "b"), lower=-0.1, upper=0.1, use_delta=True, multipliers=(0.0, 1.0))


def test_a_mimic_target_delta_starts_the_followers_on_the_leaders_relation(tmp_path: object) -> None:
    """Both joints driven, coupled only by a mimic mode adding its deltas to the targets
    (flap = 0.5 spin + 0.1). Reset off the relation (spin 0.2, flap 0.5: 0.3 rad off),
    each joint's target was its own measured position, so every later target kept the
    flap 0.3 rad off and the pose stayed there. Now a reset and the mode's activation put
    the flap's target on the relation to the spin's measured position, the spin's target
    is its measured position exactly, and the pose settles on the relation."""
    cls = mimic_robot(tmp_path, equality=False)
    tdelta = ra.PDJointPosMimicConfig(
        joint_names=("spin", "flap"),
        lower=-0.1,
        upper=0.1,
        use_delta=True,
        use_target=True,
        normalize_action=False,
        multipliers=(1.0, 0.5),
        offsets=(0.0, 0.1),
    )
    absolute = ra.PDJointPosMimicConfig(joint_names=("spin", "flap"), normalize_action=False, multipliers=(1.0, 0.5))
    modes = {"tdelta": tdelta, "abs": absolute}
    scene = ra.Scene(type("MimicTarget", (cls,), {"default_control_mode": "tdelta", "control_modes": modes}))
    scene.reset()
    agent = scene.agents[0]
    agent.reset(qpos=np.array([0.2, 0.5]))
    controller = agent.controller.parts["main"]
    np.testing.assert_array_equal(controller.get_state()["target_qpos"][0], [0.2, 0.5 * 0.2 + 0.1])
    run(scene, agent, np.array([0.05]), 1)
    np.testing.assert_array_equal(controller.get_state()["target_qpos"][0], [0.25, 0.5 * 0.2 + 0.1 + 0.5 * 0.05])
    run(scene, agent, np.array([0.0]), 60)
    np.testing.assert_allclose(agent.qpos[0], [0.25, 0.225], atol=1e-3)
    # activation holds the measured pose: off the relation again (by the absolute mode's
    # offset 0), the target-delta mode starts its followers back on it
    agent.set_control_mode("abs")
    run(scene, agent, np.array([0.4]), 60)
    np.testing.assert_allclose(agent.qpos[0], [0.4, 0.2], atol=1e-3)
    agent.set_control_mode("tdelta")
    spin = agent.qpos[0, 0]
    target = agent.controller.parts["main"].get_state()["target_qpos"][0]
    assert target[0] == spin and target[1] == 0.5 * spin + 0.1
    scene.close()


def test_a_velocity_target_on_a_joint_with_dry_friction_settles_short_by_friction_over_damping(
    tmp_path: object,
) -> None:
    """docs/control-modes.md, why ``frictionloss`` is not fed forward: a Go2-like joint
    (kv 5, damping b 2 fed forward, frictionloss f 0.2 N*m, armature 0.01) settles
    ``f / (kv + b)`` = 0.029 rad/s short of 0.5 rad/s; below MuJoCo's friction
    constraint's soft zone (0.01 rad/s) it resists in proportion to speed, not with ``f``."""
    from pathlib import Path

    path = Path(str(tmp_path)) / "dry.xml"
    path.write_text(SPINNER_MJCF.replace('damping="0.01"', 'damping="2" armature="0.01" frictionloss="0.2"'))
    drive = ra.PDActuator(joints=("spin", "tilt"), stiffness=60.0, damping=5.0, effort_limit=20.0)
    attributes = {"uid": "dry", "mjcf_path": path, "actuators": (drive,), "replace_file_actuators": True}
    cls = type("DrySpinner", (ra.Agent,), attributes)
    scene = ra.Scene(cls, control_modes="pd_joint_vel")
    scene.reset()
    agent = scene.agents[0]
    velocity = agent.controller.parts["main"]
    run(scene, agent, velocity.from_raw(np.array([0.5, 0.0])), 40)
    assert agent.qvel[0, 0] == pytest.approx(0.5 - 0.2 / 7, abs=1e-6)
    run(scene, agent, velocity.from_raw(np.array([0.01, 0.0])), 40)
    assert 0.0 < agent.qvel[0, 0] < 0.01  # the soft zone: slowed, not stopped 0.019 short
    scene.close()
    # a plain PD loop (damping_feedforward=False, the Go2's): short by (b qd* + f) / (kd + b)
    plain = ra.PDActuator(
        joints=("spin", "tilt"), stiffness=60.0, damping=5.0, effort_limit=20.0, damping_feedforward=False
    )
    scene = ra.Scene(
        type("PlainDrySpinner", (ra.Agent,), {**attributes, "actuators": (plain,)}), control_modes="pd_joint_vel"
    )
    scene.reset()
    agent = scene.agents[0]
    run(scene, agent, agent.controller.parts["main"].from_raw(np.array([0.5, 0.0])), 40)
    assert agent.qvel[0, 0] == pytest.approx(0.5 - (2 * 0.5 + 0.2) / 7, abs=1e-6)
    scene.close()


def test_a_sign_friction_feedforward_overdrives_slow_targets() -> None:
    """The feed-forward docs/control-modes.md turns down, ``sign(qd*) f`` on top of the
    same joint's velocity servo (MuJoCo alone): exact above the soft zone (0.1 rad/s),
    but below it the constraint resists with less than ``f``, so the joint runs
    faster than asked (0.0149 rad/s for 0.01, 0.0118 for 0.002), the more so the lighter
    the joint (armature 0.001: 0.028 for 0.01)."""
    kv, b, f = 5.0, 2.0, 0.2

    def joint(armature: float) -> tuple[mujoco.MjModel, mujoco.MjData]:
        model = mujoco.MjModel.from_xml_string(
            '<mujoco><option timestep="0.0025" integrator="implicitfast" gravity="0 0 0"/><worldbody><body>'
            f'<joint name="j" axis="0 0 1" damping="{b}" frictionloss="{f}" armature="{armature}"/>'
            '<geom type="box" size="0.1 0.02 0.02" mass="0.5"/></body></worldbody>'
            f'<actuator><velocity joint="j" kv="{kv}"/></actuator></mujoco>'
        )
        return model, mujoco.MjData(model)

    def command(model: mujoco.MjModel, data: mujoco.MjData, target: float, feedforward: bool, steps: int) -> None:
        data.ctrl[0] = target * (kv + b) / kv  # the library's damping feed-forward
        data.qfrc_applied[0] = f * np.sign(target) if feedforward else 0.0  # the friction feed-forward
        for _ in range(steps):
            mujoco.mj_step(model, data)

    def settle(target: float, armature: float) -> float:
        model, data = joint(armature)
        command(model, data, target, True, 1200)  # 3 s
        return float(data.qvel[0])

    assert settle(0.1, 0.01) == pytest.approx(0.1, abs=1e-6)
    assert settle(0.01, 0.01) == pytest.approx(0.0149, abs=2e-4)
    assert settle(0.002, 0.01) == pytest.approx(0.0118, abs=2e-4)
    assert settle(0.01, 0.001) == pytest.approx(0.0282, abs=5e-4)
    # a command jittering about zero: +-0.005 rad/s alternating at 20 Hz for 2 s
    spread = {}
    for feedforward in (False, True):
        model, data = joint(0.01)
        angles = []
        for step in range(40):
            command(model, data, 0.005 * (-1) ** step, feedforward, 20)
            angles.append(data.qpos[0])
        spread[feedforward] = float(np.ptp(angles))
    assert spread[False] == pytest.approx(4.7e-5, rel=0.05)
    assert spread[True] == pytest.approx(4.4e-4, rel=0.05)


NAN = float("nan")


@pytest.mark.parametrize(
    ("make", "match"),
    [
        # an effort mode's bounds were not checked: NaN went on to NaN effort targets
        (lambda: ra.JointEffortConfig(joint_names=("a", "b"), lower=NAN, normalize_action=False), r"lower: expected"),
        (lambda: ra.JointEffortConfig(joint_names=("a", "b"), lower=(1.0, 2.0, 3.0)), r"lower: expected .* 2"),
        (lambda: ra.JointEffortConfig(joint_names=("a",), lower=5.0, upper=-5.0), r"lower <= upper"),
        # a bound after a None one was not looked at
        (lambda: ra.PDJointPosConfig(joint_names=("a",), upper=NAN), r"upper: expected"),
        (lambda: ra.JointEffortConfig(joint_names=("a",), upper=NAN), r"upper: expected"),
        # a base's bounds were not checked (NaN bounds of raw actions: NaN velocity targets)
        (lambda: ra.PDBaseVelConfig(joint_names=("x", "y", "yaw"), lower=NAN, normalize_action=False), r"lower"),
        (lambda: ra.PDBaseVelConfig(joint_names=("x", "y", "yaw"), holonomic=False, upper=(1.0, 1.0, 1.0)), r"2"),
        # end-effector bounds (NaN: pd_ee_pose's targets silently stayed where they were)
        (lambda: ra.PDEEPosConfig(joint_names=("a",), pos_lower=NAN), r"pos_lower: expected .* axis"),
        (lambda: ra.PDEEPoseConfig(joint_names=("a",), rot_upper=(0.1, NAN, 0.1)), r"rot_upper"),
        (lambda: ra.PDEEPoseConfig(joint_names=("a",), pos_lower=0.2, pos_upper=0.1), r"pos_lower <= pos_upper"),
    ],
)
def test_bad_action_bounds_are_refused_when_the_config_is_made(make: object, match: str) -> None:
    with pytest.raises(ra.ConfigError, match=match):
        make()  # type: ignore[operator]
