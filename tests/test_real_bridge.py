"""The real-robot bridge sends the targets the simulation would apply: driven through a
simulated bus, a robot follows the simulation's trajectory bit for bit."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.errors import ActionError, ConfigError, StateError, UnknownNameError
from robot_agents.real import JointBus, RealRobot, SimulatedBus
from robot_agents.real.bridge import MOVE_TOLERANCE
from robot_agents.robots.universal_robots.ur10e import ARM_JOINTS
from robot_agents.sim.scene import Scene

FloatArray = np.ndarray


def simulated_and_bridged(
    uid: str, mode: str, steps: int, bus: JointBus | None = None
) -> tuple[FloatArray, FloatArray]:
    """Driven-joint positions per step: a scene in ``mode``, and the bridge in ``mode``
    on a simulated bus, from the same seeded random actions."""
    bus = bus if bus is not None else SimulatedBus(uid)
    real = RealRobot(uid, bus, control_mode=mode)
    scene = Scene(uid, control_modes=mode)
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    simulated, bridged = [], []
    for _ in range(steps):
        action = rng.uniform(-1.0, 1.0, real.action_space.shape)
        real.step(action)
        agent.set_action(action)
        scene.step()
        simulated.append(scene.world.qpos[0, agent.drives.qpos_adr].copy())
        order = [list(bus.joint_names).index(name) for name in agent.drives.joint_names]
        bridged.append(bus.read()[0][order])
    real.close()
    scene.close()
    return np.array(simulated), np.array(bridged)


@pytest.mark.parametrize(
    ("uid", "mode"),
    [
        ("panda", "pd_ee_delta_pose"),  # IK at the measured pose, velocity feed-forward
        ("so100", "pd_ee_target_delta_pos"),
        ("widowx250s", "pd_joint_target_delta_pos"),
        ("ur_10e", "pd_joint_vel"),  # the mode's own drive settings (a velocity drive) go to the bus
        ("allegro_hand_right", "pd_joint_delta_pos"),
    ],
)
def test_the_bridge_sends_what_the_simulation_applies(uid: str, mode: str) -> None:
    simulated, bridged = simulated_and_bridged(uid, mode, 40)
    assert np.abs(simulated[-1] - simulated[0]).max() > 0.05  # the robot moved
    np.testing.assert_array_equal(bridged, simulated)


def test_joints_the_bus_does_not_carry_keep_the_result_close() -> None:
    """The 2F-85's passive linkage joints are not on the bus: the controllers' model
    keeps them at the keyframe, which moves the result in its last bits only."""
    simulated, bridged = simulated_and_bridged("xarm6_robotiq", "pd_ee_delta_pose", 40)
    np.testing.assert_allclose(bridged, simulated, atol=1e-9)


class ReversedBus:
    """A bus that lists the joints in the opposite order."""

    def __init__(self, bus: SimulatedBus) -> None:
        self.inner = bus

    @property
    def joint_names(self) -> Sequence[str]:
        return list(self.inner.joint_names)[::-1]

    def read(self) -> tuple[FloatArray, FloatArray]:
        qpos, qvel = self.inner.read()
        return qpos[::-1].copy(), qvel[::-1].copy()

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        self.inner.write(position[::-1].copy(), velocity[::-1].copy(), effort[::-1].copy())

    def set_gains(self, stiffness: FloatArray, damping: FloatArray, effort_limit: FloatArray) -> None:
        self.inner.set_gains(stiffness[::-1].copy(), damping[::-1].copy(), effort_limit[::-1].copy())

    def close(self) -> None:
        self.inner.close()


def test_the_bus_joint_order_is_its_own() -> None:
    simulated, bridged = simulated_and_bridged("panda", "pd_joint_delta_pos", 20, ReversedBus(SimulatedBus("panda")))
    np.testing.assert_array_equal(bridged, simulated)


class RenamedBus(SimulatedBus):
    """The simulated Panda's bus, some of its joints going by other names."""

    def __init__(self, names: dict[str, str]) -> None:
        super().__init__("panda")
        self.names = names

    @property
    def joint_names(self) -> Sequence[str]:
        return [self.names.get(n, n) for n in super().joint_names]


class RecordingBus(SimulatedBus):
    def __init__(self, robot: str | type[ra.Agent], read_nan: bool = False) -> None:
        self.writes: list[tuple[FloatArray, ...]] = []
        self.gains: list[tuple[FloatArray, ...]] = []
        self.read_nan = read_nan
        super().__init__(robot)

    def read(self) -> tuple[FloatArray, FloatArray]:
        qpos, qvel = super().read()
        if self.read_nan:
            qpos[0] = np.nan
        return qpos, qvel

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        self.writes.append((position, velocity, effort))
        super().write(position, velocity, effort)

    def set_gains(self, stiffness: FloatArray, damping: FloatArray, effort_limit: FloatArray) -> None:
        self.gains.append((stiffness, damping, effort_limit))
        super().set_gains(stiffness, damping, effort_limit)


def test_targets_far_from_the_measured_pose_are_limited() -> None:
    bus = RecordingBus("ur_10e")
    real = RealRobot("ur_10e", bus, control_mode="pd_joint_pos", max_target_step=0.05)
    measured = bus.read()[0]
    far = measured + 1.0  # 1 rad away on every joint (within the limits of the keyframe)
    sent = real.step(far)
    np.testing.assert_allclose(sent, measured + 0.05)
    np.testing.assert_array_equal(bus.writes[-1][0], sent)
    unlimited = RealRobot("ur_10e", SimulatedBus("ur_10e"), control_mode="pd_joint_pos")
    np.testing.assert_allclose(unlimited.step(far), far)
    real.close()
    unlimited.close()


def test_max_target_step_may_leave_a_joint_unbounded() -> None:
    """An entry of inf leaves that joint's targets as they are (a gripper with no rated
    speed), the others bounded: the bound of rated speed x control period."""
    bus = RecordingBus("panda")
    rated = bus.agent.drives.velocity_limit
    assert np.isinf(rated[7:]).all() and np.isfinite(rated[:7]).all()
    real = RealRobot("panda", bus, control_mode="pd_joint_pos", max_target_step=rated * 0.05)
    measured = bus.read()[0]
    far = measured + np.array([1.0] * 7 + [0.0] * 2)
    arm = real.agent.controller.slices["arm"]
    action = np.zeros(real.action_space.shape)
    action[arm] = real.agent.controller.parts["arm"].from_raw(far[None, :7])[0]
    action[-1] = -1.0  # the gripper closes: its 0.04 m go out in one target
    sent = real.step(action)
    np.testing.assert_allclose(sent[:7], measured[:7] + rated[:7] * 0.05)
    np.testing.assert_array_equal(sent[7:], real.agent.drives.targets.position[0, 7:])
    assert np.abs(sent[7:] - measured[7:]).max() > 0.03
    real.close()


def test_a_velocity_target_sent_with_a_held_back_position_target_is_scaled_with_it() -> None:
    """The Panda's end-effector feed-forward with max_target_step=0.01 rad and a
    full-scale command: each joint's velocity target goes out scaled by the fraction of
    its position step that is sent, so the pair is the IK's straight joint path shortened
    until its midpoint is on the bound (0.4 rad/s at 20 Hz) and a joint moves at most
    twice the bound a step. Unscaled (up to 13 rad/s), a joint moved 0.53 rad in one step;
    joints not held back keep their velocity targets bit for bit."""
    bus = RecordingBus("panda")
    real = RealRobot("panda", bus, control_mode="pd_ee_delta_pose", max_target_step=0.01)
    targets = real.agent.drives.targets  # the controllers' targets, in the bus's order here
    assert list(bus.joint_names) == list(real.agent.drives.joint_names)
    action = np.zeros(real.action_space.shape)
    action[[0, 2, 3]] = [1.0, -1.0, 1.0]
    for step in range(10):
        measured = bus.read()[0]
        sent = real.step(action)
        velocity = bus.writes[-1][1]
        wanted, wanted_velocity = targets.position[0], targets.velocity[0]
        held = sent != wanted
        assert held[:7].all() or step > 0  # every arm joint held back at first
        np.testing.assert_allclose(np.abs(sent - measured)[held], 0.01, rtol=1e-12)
        fraction = (sent - measured)[held] / (wanted - measured)[held]
        assert np.all((fraction > 0) & (fraction < 1))
        np.testing.assert_allclose(velocity[held], wanted_velocity[held] * fraction, rtol=1e-12)
        arm_held = held[:7]
        np.testing.assert_allclose(np.abs(velocity[:7][arm_held]), 2 * 0.01 * 20, rtol=1e-9)  # 2 s / dt
        np.testing.assert_array_equal(velocity[~held], wanted_velocity[~held])
        assert np.abs(bus.read()[0] - measured)[:7].max() <= 2 * 0.01 * 1.05
    real.close()
    # pd_joint_pos_vel: the policy's own velocities are scaled the same way
    bus = RecordingBus("panda")
    real = RealRobot("panda", bus, control_mode="pd_joint_pos_vel", max_target_step=0.05)
    measured = bus.read()[0]
    controller = real.agent.controller.parts["arm"]
    raw = np.concatenate([measured[:7] + np.array([0.2, 0.02, 0, 0, 0, 0, -0.5]), np.full(7, 0.5)])
    arm = real.agent.controller.slices["arm"]
    action = np.zeros(real.action_space.shape)
    action[arm] = controller.from_raw(raw)
    real.step(action)
    velocity = bus.writes[-1][1][:7]
    np.testing.assert_allclose(velocity, [0.5 * 0.25, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5 * 0.1], rtol=1e-9)
    real.close()


def test_a_velocity_mode_is_not_slowed_by_max_target_step() -> None:
    """pd_joint_vel's drives have no position stiffness: the position targets it leaves
    (the pose held when the mode started) are clipped on the way out and pull on
    nothing, and the velocity targets go as commanded after the joint has turned past
    the bound."""
    bus = RecordingBus("ur_10e")
    real = RealRobot("ur_10e", bus, control_mode="pd_joint_vel", max_target_step=0.05)
    start = bus.read()[0]
    action = np.zeros(real.action_space.shape)
    action[0] = 0.5
    for _ in range(20):
        real.step(action)
        np.testing.assert_array_equal(bus.writes[-1][1], real.agent.drives.targets.velocity[0])
    speed = real.agent.controller.parts[next(iter(real.agent.controller.parts))].to_raw(action[None])[0, 0]
    assert abs(bus.read()[0][0] - start[0]) > 10 * 0.05
    assert bus.read()[1][0] == pytest.approx(speed, rel=0.02)
    real.close()


def effort_ur() -> type[ra.Agent]:
    """The UR10e with an effort mode on top of its declared PD drives (stiffness kept)."""

    class EffortUR(ra.get_agent("ur_10e")):  # type: ignore[misc]
        default_control_mode = "pd_joint_pos"
        control_modes = {
            "pd_joint_pos": ra.PDJointPosConfig(joint_names=ARM_JOINTS),
            "joint_effort": ra.JointEffortConfig(joint_names=ARM_JOINTS, normalize_action=False),
        }

    return EffortUR


def test_an_effort_sent_with_a_held_back_position_target_is_scaled_with_it() -> None:
    """An effort of 40 N*m on the UR10e's wrist 3 against its hold spring (3200 N*m/rad)
    rests 12.5 mrad from the held pose in simulation. With max_target_step=0.005 rad the
    spring's pull is cut to the bound; the effort, sent as it was, ran the joint away
    (0.46 rad in 60 steps, without end). Scaled by the fraction of the position step
    that is sent, the joint rests where the simulation's does: the whole command is
    shrunk, kp f (p - q) + f tau, which is zero where kp (p - q) + tau is."""
    cls = effort_ur()
    tau = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 40.0])
    scene = Scene(cls, control_modes="joint_effort")
    scene.reset()
    agent = scene.agents[0]
    start = scene.world.qpos[0, agent.drives.qpos_adr].copy()
    for _ in range(60):
        agent.set_action(tau)
        scene.step()
    simulated = scene.world.qpos[0, agent.drives.qpos_adr] - start
    scene.close()
    assert simulated[5] == pytest.approx(40.0 / 3200.0, rel=1e-6)
    bus = RecordingBus(cls)
    real = RealRobot(cls, bus, control_mode="joint_effort", max_target_step=0.005)
    start = bus.read()[0]
    held_back = 0
    for _ in range(60):
        measured = bus.read()[0]
        sent = real.step(tau)
        wanted = real.agent.drives.targets.position[0]
        effort = bus.writes[-1][2]
        if sent[5] != wanted[5]:
            held_back += 1
            fraction = (sent[5] - measured[5]) / (wanted[5] - measured[5])
            assert 0.0 < fraction < 1.0 and effort[5] == pytest.approx(40.0 * fraction, rel=1e-12)
        else:
            assert effort[5] == 40.0
        np.testing.assert_array_equal(effort[:5], 0.0)
    assert held_back > 0
    np.testing.assert_allclose(bus.read()[0] - start, simulated, atol=1e-9)
    real.close()


def test_a_mode_switch_sends_the_modes_drive_settings() -> None:
    bus = RecordingBus("ur_10e")
    real = RealRobot("ur_10e", bus, control_mode="pd_joint_pos")
    stiffness, damping, _ = bus.gains[-1]
    assert np.all(stiffness > 0)
    real.set_control_mode("pd_joint_vel")
    stiffness, damping, _ = bus.gains[-1]
    assert real.control_mode == "pd_joint_vel" and np.all(stiffness == 0) and np.all(damping > 0)
    real.close()


def test_a_rejected_action_sends_nothing_and_changes_nothing() -> None:
    bus = RecordingBus("panda")
    real = RealRobot("panda", bus, control_mode="pd_joint_target_delta_pos")
    real.step(np.full(real.action_space.shape, 0.5))
    writes, before = len(bus.writes), real.agent.controller.get_state()
    for bad in (np.zeros(3), np.full(real.action_space.shape, np.nan), "up"):
        with pytest.raises(ActionError):
            real.step(bad)
    assert len(bus.writes) == writes
    after = real.agent.controller.get_state()
    for part in before:
        for key in before[part]:
            np.testing.assert_array_equal(after[part][key], before[part][key])
    real.close()
    with pytest.raises(StateError, match="closed"):
        real.step(np.zeros(real.action_space.shape))


def test_an_unknown_mode_changes_nothing() -> None:
    """A misspelt mode is refused before the bus is read: the observation and the mode
    stay as they were (the bus was read first, and the controllers' model moved to the
    robot's new pose on a call that failed)."""
    bus = SimulatedBus("panda")
    robot = RealRobot("panda", bus, control_mode="pd_joint_delta_pos")
    before = robot.get_obs().copy()
    bus.write(bus.read()[0] + 0.2, np.zeros(9), np.zeros(9))  # the robot moves meanwhile
    with pytest.raises(UnknownNameError, match=r"RealRobot.set_control_mode.*Did you mean 'pd_joint_pos'"):
        robot.set_control_mode("pd_joint_poz")
    np.testing.assert_array_equal(robot.get_obs(), before)
    assert robot.control_mode == "pd_joint_delta_pos"
    robot.close()


class FlakyBus(RecordingBus):
    """A bus whose ``write`` fails the first ``failures`` times (a lost connection)."""

    def __init__(self, robot: str, failures: int) -> None:
        super().__init__(robot)
        self.failures = failures

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        if self.failures:
            self.failures -= 1
            raise OSError("the motors did not answer")
        super().write(position, velocity, effort)


@pytest.mark.parametrize("mode", ["pd_joint_target_delta_pos", "pd_ee_target_delta_pose"])
def test_a_failed_write_leaves_the_controllers_as_they_were(mode: str) -> None:
    """A bus write that raises leaves the controllers and targets as before the call:
    retried, the command is the one a bus that took it first time was sent (a target
    delta added once; it was added again on each retry)."""
    flaky, steady = FlakyBus("widowx250s", failures=2), RecordingBus("widowx250s")
    robots = [RealRobot("widowx250s", bus, control_mode=mode) for bus in (flaky, steady)]
    action = np.full(robots[0].action_space.shape, 0.5)
    before = robots[0].agent.controller.get_state()
    for _ in range(2):
        with pytest.raises(OSError, match="did not answer"):
            robots[0].step(action)
    after = robots[0].agent.controller.get_state()
    for part, arrays in before.items():
        for key, value in arrays.items():
            np.testing.assert_array_equal(after[part][key], value)
    for _ in range(3):
        sent = [robot.step(action) for robot in robots]
        np.testing.assert_array_equal(sent[0], sent[1])
    np.testing.assert_array_equal(flaky.writes[-1][1], steady.writes[-1][1])
    for robot in robots:
        robot.close()


def test_a_failed_write_leaves_the_step_info_as_it_was() -> None:
    """An end-effector mode's step info (``ik_success`` and the residual errors) is the
    controller state's: after a bus write that raises it is the last command's that
    went, whether the failed call's IK failed (a pose out of reach) or succeeded."""
    bus = FlakyBus("widowx250s", failures=0)
    robot = RealRobot("widowx250s", bus, control_mode="pd_ee_pose")
    controller = robot.agent.controller.parts["arm"]
    out_of_reach = np.r_[0.7, 0.7, 0.8, 0.0, 0.0, 0.0, 1.0]  # 1.2 m from the shoulder: IK fails
    reachable = np.r_[controller.hold_raw(robot.agent.world)[0], 1.0]
    for went, failed_call in ((reachable, out_of_reach), (out_of_reach, reachable)):
        robot.step(went)
        info = robot.agent.step_info()
        assert bool(info["ik_success"][0]) == (went is reachable)
        bus.failures = 1
        with pytest.raises(OSError, match="did not answer"):
            robot.step(failed_call)
        after = robot.agent.step_info()
        assert set(after) == set(info)
        for key, value in info.items():
            np.testing.assert_array_equal(after[key], value)
    robot.close()


def test_a_closed_robot_and_bus_refuse_every_call() -> None:
    bus = SimulatedBus("so100")
    real = RealRobot("so100", bus)
    real.close()
    for name, call in (
        ("set_control_mode", lambda: real.set_control_mode("pd_joint_pos")),
        ("get_proprioception", real.get_proprioception),
        ("get_obs", real.get_obs),
        ("camera_params", real.camera_params),
        ("move_to", lambda: real.move_to("rest")),
    ):
        with pytest.raises(StateError, match=rf"^RealRobot\.{name}: this RealRobot is closed"):
            call()
    zeros = np.zeros(len(bus.joint_names))
    with pytest.raises(StateError, match=r"^SimulatedBus\.set_gains: this bus is closed"):
        bus.set_gains(zeros, zeros, zeros)


def test_touch_entries_come_from_the_model_at_the_measured_pose() -> None:
    """docs/real-robots.md: the pads read only the robot's own contacts in the controllers' model."""
    bus = SimulatedBus("panda_touch")
    real = RealRobot("panda_touch", bus, control_mode="pd_joint_pos")
    arm = bus.read()[0][:7]
    real.step(np.r_[arm, 1.0])
    np.testing.assert_array_equal(real.get_proprioception()["touch"], 0.0)  # open: nothing to touch
    for _ in range(10):
        real.step(np.r_[arm, -1.0])
    real.sync()
    assert np.all(real.get_proprioception()["touch"] > 1.0)  # closed on each other
    real.close()


def test_the_scene_is_closed_when_the_bus_fails_to_close() -> None:
    class FailingBus(SimulatedBus):
        def close(self) -> None:
            super().close()
            raise OSError("the port is gone")

    real = RealRobot("so100", FailingBus("so100"))
    with pytest.raises(OSError, match="the port is gone"):
        real.close()
    assert real.scene.world.closed  # its stepping threads stopped (left running before)


def test_bad_setups_are_clean_errors() -> None:
    with pytest.raises(ConfigError, match="free root"):
        RealRobot("anymal_c", SimulatedBus("panda"))
    with pytest.raises(ConfigError, match="mobile base"):
        RealRobot("fetch", SimulatedBus("fetch"))
    renamed = RenamedBus({"panda_finger_joint2": "panda_finger_jiont2"})
    with pytest.raises(ConfigError, match=r"missing \['panda_finger_joint2'\].*did you mean 'panda_finger_joint2'"):
        RealRobot("panda", renamed)
    with pytest.raises(ConfigError, match="max_target_step > 0"):
        RealRobot("panda", SimulatedBus("panda"), max_target_step=-1.0)
    for not_a_distance in (True, "0.1", [0.1, None], np.inf, [np.nan] * 9):
        with pytest.raises(ConfigError, match="max_target_step > 0"):
            RealRobot("panda", SimulatedBus("panda"), max_target_step=not_a_distance)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="expected a JointBus"):
        RealRobot("panda", object())  # type: ignore[arg-type]
    with pytest.raises(UnknownNameError, match="keyframe"):
        SimulatedBus("panda", keyframe="rset")
    with pytest.raises(StateError, match="expected finite"):
        RealRobot("panda", RecordingBus("panda", read_nan=True))
    for reading in ((np.zeros(9),) * 3, None, ("a", "b")):  # ValueError / TypeError from the unpacking before
        bad = RecordingBus("panda")
        bad.read = lambda reading=reading: reading  # type: ignore[method-assign]
        with pytest.raises(StateError, match=r"RealRobot.sync: expected .*\(9,\)"):
            RealRobot("panda", bad)
        bad.close()
    bus = SimulatedBus("panda")
    with pytest.raises(ActionError, match="finite targets"):
        bus.write(np.zeros(2), np.zeros(2), np.zeros(2))
    with pytest.raises(ConfigError, match="values >= 0"):
        bus.set_gains(-np.ones(9), np.ones(9), np.ones(9))
    for gains in ((np.full(9, np.inf), np.ones(9)), (np.ones(9), np.full(9, np.inf))):
        with pytest.raises(ConfigError, match="stiffness and damping finite"):
            bus.set_gains(*gains, np.ones(9))  # NaN physics on the next write before
    bus.set_gains(np.ones(9), np.ones(9), np.full(9, np.inf))  # no effort limit
    bus.close()


def test_the_docs_example_runs() -> None:
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "real-robots.md").read_text()
    (block,) = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    namespace: dict[str, object] = {}
    exec(compile(block, "docs/real-robots.md", "exec"), namespace)
    start = SimulatedBus("so100")
    moved = np.asarray(namespace["sent"]) - start.read()[0]
    start.close()
    assert isinstance(namespace["robot"], RealRobot) and np.abs(moved).max() > 0.1  # rad: the arm went


def test_move_to_ramps_to_a_keyframe() -> None:
    bus = RecordingBus("widowx250s")
    robot = RealRobot("widowx250s", bus, control_mode="pd_joint_delta_pos", max_target_step=0.3)
    local = {int(adr): i for i, adr in enumerate(robot.agent.index.qpos_adr)}
    order = [local[int(adr)] for adr in robot.agent.drives.qpos_adr]
    target = robot.agent.keyframe_qpos("sleep")[order]
    start = bus.read()[0]
    assert np.abs(start - target).max() > 1.0  # from home to sleep: over a radian on some joint
    before = len(bus.writes)
    left = robot.move_to("sleep", steps=40)
    sent = np.array([w[0] for w in bus.writes[before:]])
    assert 40 <= len(sent) <= 80  # the ramp, then the keyframe until the lagging arm is there
    np.testing.assert_allclose(sent[39:], np.broadcast_to(target, sent[39:].shape), atol=1e-12)
    assert left == pytest.approx(np.abs(bus.read()[0] - target).max(), abs=1e-12)
    assert left <= MOVE_TOLERANCE
    assert robot.control_mode == "pd_joint_delta_pos"
    with pytest.raises(UnknownNameError, match="Did you mean 'sleep'"):
        robot.move_to("slep")
    with pytest.raises(UnknownNameError, match="unknown keyframe"):
        robot.move_to(["sleep"])  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="steps"):
        robot.move_to("sleep", steps=0)
    robot.close()


def test_move_to_reaches_the_keyframe_in_a_velocity_mode_and_within_max_target_step() -> None:
    """The ramp runs under the declared drives' position gains (a velocity mode's
    stiffness is 0: the arm did not move), and the mode's settings are sent again after
    it; with max_target_step the ramp is lengthened to what the bound allows and the
    keyframe commanded until the arm is there (it stopped 1.5 rad short before)."""
    bus = SimulatedBus("panda", keyframe="rest")
    robot = RealRobot("panda", bus, control_mode="pd_joint_vel")
    target = robot.agent.keyframe_qpos("ready")[:7]
    assert robot.move_to("ready", steps=40) <= MOVE_TOLERANCE
    assert np.abs(bus.read()[0][:7] - target).max() <= MOVE_TOLERANCE
    assert np.all(bus.agent.drives.stiffness[:7] == 0.0)  # pd_joint_vel's drive settings again
    robot.close()
    bus = SimulatedBus("so100", keyframe="rest")
    robot = RealRobot("so100", bus, control_mode="pd_joint_delta_pos", max_target_step=0.02)
    target = robot.agent.keyframe_qpos("zero")[:5]
    assert robot.move_to("zero", steps=5) <= MOVE_TOLERANCE
    assert np.abs(bus.read()[0][:5] - target).max() <= MOVE_TOLERANCE
    robot.close()
    closed = SimulatedBus("so100")
    closed.close()
    with pytest.raises(StateError, match="closed"):
        closed.read()


def _obs_difference(uid: str, mode: str, steps: int = 20) -> tuple[float, float]:
    """Largest difference between a simulated ``Empty-v1``'s state observation and the
    bridge's ``get_obs`` on a simulated bus started from the env's reset state: at the
    reset and over ``steps`` steps of the same random actions."""
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, obs_mode="state").unwrapped
    first, _ = env.reset(seed=0)
    bus = SimulatedBus(uid)
    bus.agent.reset(qpos=env.agent.qpos[0], qvel=env.agent.qvel[0])
    robot = RealRobot(uid, bus, control_mode=mode)
    at_reset = float(np.abs(robot.get_obs() - first).max())
    assert robot.get_obs().shape == first.shape and robot.get_obs().dtype == np.float32
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(steps):
        action = rng.uniform(-1.0, 1.0, env.action_space.shape)
        obs = env.step(action)[0]
        robot.step(action)
        robot.sync()
        worst = max(worst, float(np.abs(robot.get_obs() - obs).max()))
    env.close()
    robot.close()
    return at_reset, worst


@pytest.mark.parametrize(
    ("uid", "mode"),
    [("panda", "pd_ee_delta_pose"), ("so100", "pd_joint_delta_pos"), ("widowx250s", "pd_joint_target_delta_pos")],
)
def test_get_obs_is_the_simulated_state_observation(uid: str, mode: str) -> None:
    assert _obs_difference(uid, mode) == (0.0, 0.0)


def test_a_mimic_follower_is_set_from_its_leader() -> None:
    """The WidowX AI's right carriage follows the left through a joint equality and is
    not on the bus: the bridge sets it from its leader (exactly), the simulation holds
    it there within the equality's softness."""
    robot = RealRobot("widowxai", SimulatedBus("widowxai"))
    assert len(robot.bus.joint_names) == robot.agent.nq - 1 and len(robot._followers.leader) == 1
    robot.close()
    at_reset, worst = _obs_difference("widowxai", "pd_ee_delta_pose")
    assert at_reset == 0.0 and worst < 2e-3


def test_camera_params_follow_the_measured_joints() -> None:
    """The Panda's wrist camera seen through the bridge: the same intrinsics and pose
    as the simulated env's ``sensor_param`` after the same end-effector moves."""
    uid, mode = "panda_wristcam", "pd_ee_delta_pose"
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, obs_mode="rgb").unwrapped
    env.reset(seed=0)
    bus = SimulatedBus(uid)
    bus.agent.reset(qpos=env.agent.qpos[0], qvel=env.agent.qvel[0])
    robot = RealRobot(uid, bus, control_mode=mode)
    start = robot.camera_params()["hand_camera"]["cam2world_gl"].copy()
    rng = np.random.default_rng(0)
    for _ in range(5):
        action = rng.uniform(-1.0, 1.0, env.action_space.shape)
        obs = env.step(action)[0]
        robot.step(action)
    robot.sync()
    params = robot.camera_params()
    assert list(params) == ["hand_camera"]  # the robot's own; the task's base camera is not the robot's
    for key, value in params["hand_camera"].items():
        np.testing.assert_array_equal(value.astype(np.float32), obs["sensor_param"]["hand_camera"][key])
    assert np.abs(params["hand_camera"]["cam2world_gl"][0, :3, 3] - start[0, :3, 3]).max() > 0.01  # it moved
    env.close()
    robot.close()
