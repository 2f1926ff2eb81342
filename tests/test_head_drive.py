"""The pan-tilt head drive that Fetch and the XLeRobot share (robots/fetch/fetch.py,
``head_drive``): the URDF's efforts and speed read as the head motors' torque-speed line,
their back-EMF the joints' own damping. Checked against numbers: the head's top speed
under a full-effort command is the URDF's 1.57 rad/s, and the XLeRobot's head pan, swung
by random absolute head targets (seed 3, the settle claim's case that failed at every
physics step: +-0.7 rad for seconds), comes to rest within the claim's 3 s hold."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action, run_random_actions
from robot_agents.tuning.claims import RANDOM_SECONDS, SETTLE_SECONDS, SETTLE_SPEED, claim_scene, settle_hold

HEAD = ("head_pan_joint", "head_tilt_joint")
#: The URDF's head efforts (N*m) and speed (rad/s), fetch_description/robots/fetch.urdf
#: (ZebraDevs/fetch_ros), which the XLeRobot's URDF carries too.
EFFORT = (0.32, 0.68)
SPEED = 1.57
#: The mode whose body action is an absolute head target (ManiSkill's).
STIFF_BODY = "pd_joint_delta_pos_stiff_body"


@pytest.mark.parametrize("uid", ["fetch", "xlerobot"])
def test_head_joints_carry_the_motors_back_emf(uid: str) -> None:
    """Each head joint's own damping is stall torque / no-load speed (0.204 and 0.433
    N*m*s/rad), and the drive keeps the rest of ManiSkill's kv = 1e2."""
    scene = ra.Scene(uid, control_modes=STIFF_BODY)
    model, agent = scene.model, scene.agents[0]
    drives = {d.joint: d for d in type(agent).check().drives}
    for joint, effort in zip(HEAD, EFFORT, strict=True):
        dof = model.jnt_dofadr[model.joint(agent.prefix + joint).id]
        assert model.dof_damping[dof] == pytest.approx(effort / SPEED, rel=1e-12)
        assert drives[joint].effort_limit == effort
        assert drives[joint].damping + model.dof_damping[dof] == pytest.approx(1e2, rel=1e-12)
    scene.close()


@pytest.mark.parametrize("uid", ["fetch", "xlerobot"])
def test_head_pan_runs_up_to_its_no_load_speed(uid: str) -> None:
    """An absolute head target 2.9 rad away (pan -1.45 -> 1.45 rad): the drive saturates at
    0.32 N*m the whole way and the back-EMF caps the pan's speed at 0.32 / b = 1.57 rad/s.
    Without the back-EMF the XLeRobot's pan reached 2.7 rad/s; with the 1.0 N*m*s/rad
    Fetch's model file gave every joint, Fetch's crawled at 0.32 rad/s (3 s at 200 Hz)."""
    scene = ra.Scene(uid, control_modes=STIFF_BODY)
    scene.reset()
    agent = scene.agents[0]
    pan = agent.joint_names.index(HEAD[0])
    state = agent.get_state()
    qpos = state["qpos"].copy()
    qpos[0, pan] = -1.45
    agent.set_state({**state, "qpos": qpos})
    agent.controller.reset(np.zeros(1, dtype=np.int64), agent.world)
    action = hold_action(agent)
    body = agent.controller.slices["body"]
    action[body.start] = 1.45
    fastest = 0.0
    for _ in range(round(3.0 * scene.control_freq)):
        agent.set_action(action)
        scene.step()
        fastest = max(fastest, abs(float(agent.qvel[0, pan])))
    assert 1.2 < fastest <= SPEED
    scene.close()


def test_xlerobot_head_pan_settles_after_random_absolute_targets() -> None:
    """The settle claim's case that failed at 200 Hz, 320 Hz and 1 kHz (seed 3 in
    ``pd_joint_delta_pos_stiff_body_arm2``, at the default 200 Hz): 10 s of random actions,
    then the targets set to the pose they left and held for 3 s. Without the back-EMF the
    head pan still swung at 0.43 rad/s at the end; every joint now below 0.05 rad/s."""
    cls = ra.get_agent("xlerobot")
    scene = claim_scene(cls, 200, 20, STIFF_BODY + "_arm2")
    scene.reset()
    agent = scene.agents[0]
    run_random_actions(scene, RANDOM_SECONDS, seed=3)
    fastest, joint = settle_hold(scene, agent, SETTLE_SECONDS)
    assert fastest < SETTLE_SPEED, joint
    scene.close()
