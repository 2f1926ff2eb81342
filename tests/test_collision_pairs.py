"""The never-touching self-collision check (robot_agents.tuning.collisions) on small
hand-written models whose closest approach is known in closed form."""

from __future__ import annotations

import math

import mujoco
import pytest

from robot_agents.tuning import collision_profile, collisions

#: A post (sphere, r 5 cm) 0.3 m above a hinge about y, and a ball (r 5 cm) on a 0.3 m
#: arm swinging about it: the ball's centre is at (0.3 cos q, 0, -0.3 sin q), so it
#: meets the post at q = -pi/2. The arm body has no geoms (the pair is post-ball, one
#: joint on its path).
SWING = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <geom name="post" type="sphere" size="0.05" pos="0 0 0.3"/>
      <body name="arm">
        <joint name="swing" type="{kind}" axis="0 1 0" {limits}/>
        <inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
        <body name="ball" pos="0.3 0 0">
          <geom name="ball" type="sphere" size="0.05"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

#: The same post, and a ball at the end of three 0.1 m links hinged about y (three
#: joints on the pair's path: random sampling).
CHAIN = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <geom name="post" type="sphere" size="0.05" pos="0 0 0.3"/>
      <body name="l1">
        <joint name="j1" axis="0 1 0" range="{r1}"/><inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
        <body name="l2" pos="0.1 0 0">
          <joint name="j2" axis="0 1 0" range="{r}"/><inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
          <body name="l3" pos="0.1 0 0">
            <joint name="j3" axis="0 1 0" range="{r}"/><inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
            <body name="ball" pos="0.1 0 0">
              <geom name="ball" type="sphere" size="0.05"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def swing(low: float, high: float) -> collisions.PairDistance:
    model = mujoco.MjModel.from_xml_string(SWING.format(kind="hinge", limits=f'range="{low} {high}"'))
    return collisions.pair_distance(model, model.body("base").id, model.body("ball").id)


def closest_gap(low: float) -> float:
    """Gap (m) between post and ball when the arm stops at ``low`` (rad, > -pi/2)."""
    return 2 * 0.3 * math.sin((math.pi / 2 + low) / 2) - 0.1


def test_a_pair_that_cannot_touch_is_found_with_its_gap() -> None:
    result = swing(-0.9, 0.9)
    expected = closest_gap(-0.9 - collisions.HINGE_OVERSHOOT)  # 25.3 mm
    assert result.method == "grid" and result.joints == ("swing",)
    assert result.min_distance == pytest.approx(expected, abs=1e-6)  # the grid holds the limit itself
    assert 0 < result.allowance < 1e-3
    assert result.never_touching


def test_a_pair_that_can_touch_is_not_excluded() -> None:
    result = swing(-1.6, 1.6)
    assert result.min_distance < -0.099  # the ball passes through the post
    assert not result.never_touching


def test_a_gap_under_the_margin_counts_as_touching() -> None:
    # stops (with the overshoot) 5 mm short of the post: clear, but closer than the margin
    low = -math.pi / 2 + 2 * math.asin(0.105 / 0.6) + collisions.HINGE_OVERSHOOT
    result = swing(low, -low)
    assert result.min_distance == pytest.approx(0.005, abs=1e-6)
    assert not result.never_touching


def test_the_joint_limit_overshoot_is_sampled() -> None:
    # the range alone stops 16 mm short; its soft-limit overshoot reaches the post
    low = -math.pi / 2 + 2 * math.asin(0.116 / 0.6)
    assert closest_gap(low) == pytest.approx(0.016)
    assert not swing(low, -low).never_touching


def test_an_unlimited_slide_on_the_path_counts_as_touching() -> None:
    model = mujoco.MjModel.from_xml_string(SWING.format(kind="slide", limits='limited="false"'))
    result = collisions.pair_distance(model, model.body("base").id, model.body("ball").id)
    assert result.method == "unbounded"
    assert not result.never_touching


def chain(first: str, others: str) -> collisions.PairDistance:
    model = mujoco.MjModel.from_xml_string(CHAIN.format(r1=first, r=others))
    return collisions.pair_distance(model, model.body("base").id, model.body("ball").id)


def test_random_sampling_finds_the_fold_that_touches() -> None:
    # only q1 near -pi/2 with q2, q3 near 0 brings the ball into the post
    result = chain("-1.8 1.8", "-1.5 1.5")
    assert result.method == "random" and len(result.joints) == 3
    assert result.min_distance < -0.05
    assert not result.never_touching


def test_random_sampling_keeps_a_pair_that_cannot_reach() -> None:
    # every joint in [0, 0.5] (+-0.25 overshoot): the ball stays below z = 0.14 m,
    # the post's underside is at 0.25 m
    result = chain("0 0.5", "0 0.5")
    assert result.method == "random"
    assert result.min_distance > 0.1
    assert result.never_touching


def test_candidate_pairs_skip_parents_welds_and_exclusions() -> None:
    model = mujoco.MjModel.from_xml_string(CHAIN.format(r1="-1 1", r="-1 1"))
    # only base and ball have geoms; base is welded to the world, so MuJoCo checks them
    assert collisions.candidate_pairs(model) == [(model.body("base").id, model.body("ball").id)]
    excluded = CHAIN.replace("</worldbody>", '</worldbody><contact><exclude body1="base" body2="ball"/></contact>')
    assert collisions.candidate_pairs(mujoco.MjModel.from_xml_string(excluded.format(r1="-1 1", r="-1 1"))) == []


def test_a_real_robot_pair_of_each_kind() -> None:
    # the Panda's base and second link (two joints apart: grid) stay 9 cm apart; its
    # base and hand (seven joints: random) can meet
    from robot_agents.registry import get_agent

    apart, meeting = collisions.pair_distances(
        get_agent("panda"), [("panda_link0", "panda_link2"), ("panda_link0", "panda_hand")]
    )
    assert apart.method == "grid" and apart.never_touching and apart.bound > 0.05
    assert meeting.method == "random" and meeting.min_distance < 0 and not meeting.never_touching


def test_collision_profile_counts_the_floor_pair_of_a_resting_ball() -> None:
    import numpy as np

    model = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><geom type="plane" size="1 1 0.1"/>'
        '<body name="ball" pos="0 0 0.2"><freejoint/><geom type="sphere" size="0.05"/></body>'
        "</worldbody></mujoco>"
    )
    # 1 s at 2 ms: the ball falls 0.15 m in 0.17 s and rests; the bounding-sphere test
    # lets the pair through from 5 cm above the floor (its radius) on
    profile = collision_profile.collision_profile(model, model.qpos0.copy(), np.zeros((10, 0)), 50)
    share = profile.narrow_pairs[("world", "ball")]
    assert 0.8 < share <= 1.0
    assert 0.8 < profile.contacts <= 1.0
    assert 0.0 < profile.shares["collision"] < 1.0
    assert profile.shares["broad"] + profile.shares["narrow"] <= profile.shares["collision"] + 1e-9
