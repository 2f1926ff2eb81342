"""K-Scale Labs' Stompy checked against numbers: every body's pose against the URDF's joint
origins chained here (random configurations), the URDF's masses and joint ranges,
ManiSkill's joint order, standing 5 s on its feet from ManiSkill's ``standing`` (and why
the leg gains and effort limits are not the URDF's / ManiSkill's), and a cube held
between each gripper's fingers under its weight."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.actuators.config import PDActuator
from robot_agents.checks import hold_action
from robot_agents.controllers.rules import joint_control_modes
from robot_agents.envs.tasks.table_top import free_cube
from robot_agents.robots.kscale.stompy import (
    ARMATURE,
    GRIPPER_CLOSED,
    LEG_KP,
    LEG_KV,
    MANISKILL_JOINTS,
    MANISKILL_KP,
    MANISKILL_KV,
    MANISKILL_STANDING_QPOS,
    STANDING_HEIGHT,
    STOMPY_BODY,
    STOMPY_DRIVES,
    URDF_EFFORT,
    Stompy,
    joint_kind,
)
from tests.chain_check import axis_rotation, transform

UID = "stompy"
X, Y, Z = np.eye(3)

# ---------------------------------------------------------------- independent kinematics
# haosulab/ManiSkill-Stompy robot.urdf (tag v0.1.0, commit f7cd030), written out here from
# the URDF, not read from our model: per moving joint, its parent body (the previous
# moving joint's child link, or the root), its child link, its axis, its range (rad or m)
# and the URDF joint origins (xyz m, rpy rad) from the parent body's frame to the joint:
# the fixed joints in between, then the joint's own.
URDF_JOINTS: tuple[
    tuple[str, str, str, str, tuple[float, float], tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]], ...
] = (
    (
        "joint_head_1_x4_1_dof_x4",
        "link_torso_1_top_torso_1",
        "link_head_1_x4_1_inner_1",
        "0 0 1",
        (-2.5132741, 0.62831853),
        (
            ((0.016057909, 0.059323506, 0.049810865), (3.1415927, 0, 3.1415927)),
            ((0.015909902, -0.015909904, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_head_1_x4_2_dof_x4",
        "link_head_1_x4_1_inner_1",
        "link_head_1_x4_2_inner_1",
        "0 0 1",
        (-1.5707963, 0.26179939),
        (
            ((0.010505773, 0.0046774714, -0.0345), (3.1415927, 0, 0)),
            ((-0.025848084, 0.052861892, 0.071090096), (-1.5707963, 0, 0.62831853)),
            ((-0.015909904, -0.015909902, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_x8_1_dof_x8",
        "link_torso_1_top_torso_1",
        "link_right_arm_1_x8_1_inner_1",
        "0 0 1",
        (-2.0943951, 2.0943951),
        (
            ((-0.087055517, 0.066473668, -0.03013321), (-2.0071286, 0, -1.5707963)),
            ((0.033978714, -0.024686981, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_x8_2_dof_x8",
        "link_right_arm_1_x8_1_inner_1",
        "link_right_arm_1_x8_2_inner_1",
        "0 0 1",
        (0, 1.9198622),
        (
            ((0, 0.0155, -0.033), (3.1415927, 0, 0)),
            ((-0.012978714, 0.0485, 0.037055626), (-1.5707963, 0, 0)),
            ((0.012978714, -0.039944374, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_x6_1_dof_x6",
        "link_right_arm_1_x8_2_inner_1",
        "link_right_arm_1_x6_1_inner_1",
        "0 0 1",
        (-1.0471976, 3.6651914),
        (
            ((0, 0.0155, -0.033), (0, 0, 0)),
            ((-0.036, 0.017, -0.0615), (-1.5707963, -1.5707963, 0)),
            ((0, 0.036, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_x6_2_dof_x6",
        "link_right_arm_1_x6_1_inner_1",
        "link_right_arm_1_x6_2_inner_1",
        "0 0 1",
        (-1.5707963, 1.5707963),
        (
            ((0.00575, 0.0099592921, -0.0325), (0, 0, -2.0943951)),
            ((0.044, 0.018, -0.15032309), (-3.1415927, -1.5707963, 0)),
            ((-0.031176915, 0.018, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_x4_1_dof_x4",
        "link_right_arm_1_x6_2_inner_1",
        "link_right_arm_1_x4_1_inner_1",
        "0 0 1",
        (-3.1415927, 3.1415927),
        (
            ((0.0115, 0, -0.0325), (3.1415927, 0, 0)),
            ((-0.076, 0.015909901, 0.020909904), (1.5707963, 0, 1.5707963)),
            ((-0.015909904, -0.015909902, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_hand_1_x4_1_dof_x4",
        "link_right_arm_1_x4_1_inner_1",
        "link_right_arm_1_hand_1_x4_1_inner_1",
        "0 0 1",
        (-2.6179939, 0.52359878),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (0, 0, -0.10471976)),
            ((-0.0059506118, -0.03375, -0.027590099), (1.5707963, 0, 0)),
            ((0.015909902, -0.015909904, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_right_arm_1_hand_1_slider_1",
        "link_right_arm_1_hand_1_x4_1_inner_1",
        "link_right_arm_1_hand_1_slide_1",
        "0 0 1",
        (-0.034, 0),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.053383159, 0.090699991, -0.0345), (1.5707963, 0, 2.1991149)),
            ((-0.122, 0.014, 0.029), (3.1415927, 1.5707963, 0)),
        ),
    ),
    (
        "joint_right_arm_1_hand_1_slider_2",
        "link_right_arm_1_hand_1_x4_1_inner_1",
        "link_right_arm_1_hand_1_slide_2",
        "0 0 1",
        (-0.034, 0),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.053383159, 0.090699991, -0.0345), (1.5707963, 0, 2.1991149)),
            ((0.038, 0.014, 0.029), (0, 1.5707963, 0)),
        ),
    ),
    (
        "joint_right_arm_1_hand_1_x4_2_dof_x4",
        "link_right_arm_1_hand_1_x4_1_inner_1",
        "link_right_arm_1_hand_1_x4_2_inner_1",
        "0 0 1",
        (-3.1415927, 3.1415927),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.056679101, 0.021514055, -0.036409901), (-1.5707963, 0, 2.1991149)),
            ((0.015909902, -0.015909904, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_x8_1_dof_x8",
        "link_torso_1_top_torso_1",
        "link_left_arm_2_x8_1_inner_1",
        "0 0 1",
        (-1.5707963, 1.5707963),
        (
            ((0.087098832, 0.066473668, -0.030289845), (-2.0071286, 0, 1.5707963)),
            ((-0.033978714, -0.024686981, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_x8_2_dof_x8",
        "link_left_arm_2_x8_1_inner_1",
        "link_left_arm_2_x8_2_inner_1",
        "0 0 1",
        (-1.9198622, 0),
        (
            ((0, 0.0155, -0.033), (3.1415927, 0, 0)),
            ((-0.012978714, 0.0485, 0.037055626), (-1.5707963, 0, 0)),
            ((0.012978714, -0.039944374, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_x6_1_dof_x6",
        "link_left_arm_2_x8_2_inner_1",
        "link_left_arm_2_x6_1_inner_1",
        "0 0 1",
        (-3.6651914, 1.0471976),
        (
            ((0, 0.0155, -0.033), (0, 0, 0)),
            ((-0.036, 0.017, -0.0615), (-1.5707963, -1.5707963, 0)),
            ((0, 0.036, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_x6_2_dof_x6",
        "link_left_arm_2_x6_1_inner_1",
        "link_left_arm_2_x6_2_inner_1",
        "0 0 1",
        (-1.5707963, 1.5707963),
        (
            ((0.00575, -0.0099592921, -0.0325), (0, 0, 2.0943951)),
            ((0.044, 0.018, -0.15032309), (-3.1415927, -1.5707963, 0)),
            ((-0.031176915, 0.018, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_x4_1_dof_x4",
        "link_left_arm_2_x6_2_inner_1",
        "link_left_arm_2_x4_1_inner_1",
        "0 0 1",
        (-3.1415927, 3.1415927),
        (
            ((0.0115, 0, -0.0325), (3.1415927, 0, 0)),
            ((-0.076, 0.015909901, 0.020909904), (1.5707963, 0, 1.5707963)),
            ((-0.015909904, -0.015909902, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_hand_1_x4_1_dof_x4",
        "link_left_arm_2_x4_1_inner_1",
        "link_left_arm_2_hand_1_x4_1_inner_1",
        "0 0 1",
        (-2.6179939, 0.52359878),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (0, 0, -0.10471976)),
            ((-0.0059506118, -0.03375, -0.027590099), (1.5707963, 0, 0)),
            ((0.015909902, -0.015909904, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_left_arm_2_hand_1_slider_1",
        "link_left_arm_2_hand_1_x4_1_inner_1",
        "link_left_arm_2_hand_1_slide_1",
        "0 0 1",
        (-0.034, 0),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.053383159, 0.090699991, -0.0345), (1.5707963, 0, 2.1991149)),
            ((-0.122, 0.014, 0.029), (3.1415927, 1.5707963, 0)),
        ),
    ),
    (
        "joint_left_arm_2_hand_1_slider_2",
        "link_left_arm_2_hand_1_x4_1_inner_1",
        "link_left_arm_2_hand_1_slide_2",
        "0 0 1",
        (-0.034, 0),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.053383159, 0.090699991, -0.0345), (1.5707963, 0, 2.1991149)),
            ((0.038, 0.014, 0.029), (0, 1.5707963, 0)),
        ),
    ),
    (
        "joint_left_arm_2_hand_1_x4_2_dof_x4",
        "link_left_arm_2_hand_1_x4_1_inner_1",
        "link_left_arm_2_hand_1_x4_2_inner_1",
        "0 0 1",
        (-3.1415927, 3.1415927),
        (
            ((-0.0093036954, 0.0067595304, -0.0345), (3.1415927, 0, 0)),
            ((0.056679101, 0.021514055, -0.036409901), (-1.5707963, 0, 2.1991149)),
            ((0.015909902, -0.015909904, -0.0135), (3.1415927, 0, 0)),
            ((0, 0, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_torso_1_x8_1_dof_x8",
        "link_torso_1_top_torso_1",
        "link_torso_1_x8_1_inner_1",
        "0 0 1",
        (-0.78539816, 0.78539816),
        (
            ((-0.052197188, 0.05765456, -0.051789135), (3.1415927, 0, 0)),
            ((0.086161039, 0.00029979613, 0.2159), (3.1415927, 0, 0)),
            ((-0.033978714, -0.024686981, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_legs_1_x8_1_dof_x8",
        "link_torso_1_x8_1_inner_1",
        "link_legs_1_x8_1_inner_1",
        "0 0 1",
        (-0.52359878, 0.26179939),
        (
            ((0, -0.0155, -0.033), (3.1415927, 0, 0)),
            ((-0.060831348, -0.1456, 0.043863745), (-1.5707963, 0, 0)),
            ((-0.024686981, -0.033978714, 0), (3.1415927, 0, 1.5707963)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_x8_1_dof_x8",
        "link_legs_1_x8_1_inner_1",
        "link_legs_1_right_leg_1_x8_1_inner_1",
        "0 0 1",
        (-1.5707963, 0.52359878),
        (
            ((0.013423394, 0.00775, -0.033), (3.1415927, 0, 0)),
            ((-0.0018339123, -0.038176429, 0.040313019), (-1.5707963, 0, -2.0943951)),
            ((-0.033978714, -0.024686981, 0), (0, 0, 0)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_x10_2_dof_x10",
        "link_legs_1_right_leg_1_x8_1_inner_1",
        "link_legs_1_right_leg_1_x10_2_inner_1",
        "0 0 1",
        (-2.3561945, 0.78539816),
        (
            ((0.013423394, -0.00775, -0.033), (3.1415927, 0, 0)),
            ((-0.080448644, 0.01215886, 0.066594005), (1.5707963, 0, 1.0471976)),
            ((0.016377901, 0.050405995, 0), (3.1415927, 0, 1.5707963)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_x10_1_dof_x10",
        "link_legs_1_right_leg_1_x10_2_inner_1",
        "link_legs_1_right_leg_1_x10_1_inner_1",
        "0 0 1",
        (0, 1.5707963),
        (
            ((0, -0.018, -0.0405), (3.1415927, 0, 0)),
            ((0.0055400086, 0.03470966, 0.0775), (3.1415927, 0, -1.0471976)),
            ((0.042877901, 0.031152618, 0), (3.1415927, 0, 1.5707963)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_knee_revolute",
        "link_legs_1_right_leg_1_x10_2_inner_1",
        "link_legs_1_right_leg_1_51t_hdt5_15mm_belt_knee_right_1",
        "0 0 -1",
        (0, 1.5707963),
        (
            ((0, -0.018, -0.0405), (3.1415927, 0, 0)),
            ((0.090663645, -0.17503404, 0.039), (3.1415927, 0, -1.0471976)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_x6_1_dof_x6",
        "link_legs_1_right_leg_1_51t_hdt5_15mm_belt_knee_right_1",
        "link_legs_1_right_leg_1_x6_1_inner_1",
        "0 0 1",
        (-1.5707963, 1.5707963),
        (
            ((0.039323085, -0.032, 0.0535), (3.1415927, 0, 1.5707963)),
            ((-0.018, 0.031176915, 0), (3.1415927, 0, -2.6179939)),
        ),
    ),
    (
        "joint_legs_1_right_leg_1_ankle_revolute",
        "link_legs_1_right_leg_1_51t_hdt5_15mm_belt_knee_right_1",
        "link_legs_1_right_leg_1_ankle_pulley_1",
        "0 0 -1",
        (-0.78539816, 0.78539816),
        (((0.24, -0.05, 0), (0, 0, 1.5707963)),),
    ),
    (
        "joint_legs_1_right_leg_1_x4_1_dof_x4",
        "link_legs_1_right_leg_1_ankle_pulley_1",
        "link_legs_1_right_leg_1_x4_1_outer_1",
        "0 0 -1",
        (-0.78539816, 0.78539816),
        (
            ((0, -0.027053569, 0.002), (3.1415927, 0, 0)),
            ((0.064553569, 0.03925, 0.00045929214), (-1.5707963, 0, -1.5707963)),
            ((-0.0046774714, 0.010505773, 0.0345), (0, 0, -1.5707963)),
        ),
    ),
    (
        "joint_legs_1_x8_2_dof_x8",
        "link_torso_1_x8_1_inner_1",
        "link_legs_1_x8_2_inner_1",
        "0 0 1",
        (-0.26179939, 0.52359878),
        (
            ((0, -0.0155, -0.033), (3.1415927, 0, 0)),
            ((0.060831348, -0.1456, 0.11182117), (-1.5707963, 0, 0)),
            ((0.024686981, 0.033978714, 0), (3.1415927, 0, -1.5707963)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_x8_1_dof_x8",
        "link_legs_1_x8_2_inner_1",
        "link_legs_1_left_leg_1_x8_1_inner_1",
        "0 0 1",
        (-1.5707963, 0.52359878),
        (
            ((-0.013423394, 0.00775, -0.033), (3.1415927, 0, 0)),
            ((-0.032144801, 0.020676429, 0.040313019), (1.5707963, 0, 2.0943951)),
            ((-0.033978714, 0.024686981, 0), (3.1415927, 0, 0)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_x10_1_dof_x10",
        "link_legs_1_left_leg_1_x8_1_inner_1",
        "link_legs_1_left_leg_1_x10_1_inner_1",
        "0 0 1",
        (-0.78539816, 2.3561945),
        (
            ((0, -0.0155, -0.033), (3.1415927, 0, 0)),
            ((0.067132105, -0.035223783, 0.066594005), (-1.5707963, 0, 1.0471976)),
            ((-0.016377901, -0.050405995, 0), (3.1415927, 0, -1.5707963)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_x10_2_dof_x10",
        "link_legs_1_left_leg_1_x10_1_inner_1",
        "link_legs_1_left_leg_1_x10_2_inner_1",
        "0 0 1",
        (0, 1.5707963),
        (
            ((0.015588457, -0.009, -0.0405), (3.1415927, 0, 0)),
            ((-0.010048449, -0.06170966, 0.0775), (3.1415927, 0, 1.0471976)),
            ((0.042877901, -0.031152618, 0), (3.1415927, 0, -1.5707963)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_knee_revolute",
        "link_legs_1_left_leg_1_x10_1_inner_1",
        "link_legs_1_left_leg_1_51t_hdt5_15mm_belt_knee_left_1",
        "0 0 -1",
        (-1.5707963, 0),
        (
            ((0.015588457, -0.009, -0.0405), (3.1415927, 0, 0)),
            ((0.075075188, 0.14803404, 0.039), (3.1415927, 0, 1.0471976)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_ankle_revolute",
        "link_legs_1_left_leg_1_51t_hdt5_15mm_belt_knee_left_1",
        "link_legs_1_left_leg_1_ankle_pulley_1",
        "0 0 -1",
        (-0.78539816, 0.78539816),
        (((0.24, 0.05, 0), (0, 0, -1.5707963)),),
    ),
    (
        "joint_legs_1_left_leg_1_x4_1_dof_x4",
        "link_legs_1_left_leg_1_ankle_pulley_1",
        "link_legs_1_left_leg_1_x4_1_outer_1",
        "0 0 -1",
        (-0.78539816, 0.78539816),
        (
            ((0, 0.027053569, 0.021), (0, 0, 0)),
            ((0.064553569, 0.03925, 0.00045929214), (-1.5707963, 0, -1.5707963)),
            ((-0.0046774714, 0.010505773, 0.0345), (0, 0, -1.5707963)),
        ),
    ),
    (
        "joint_legs_1_left_leg_1_x6_1_dof_x6",
        "link_legs_1_left_leg_1_51t_hdt5_15mm_belt_knee_left_1",
        "link_legs_1_left_leg_1_x6_1_inner_1",
        "0 0 1",
        (-1.5707963, 1.5707963),
        (
            ((0.0705, 0.014, 0.0535), (3.1415927, 0, -1.5707963)),
            ((-0.036, 0, 0), (3.1415927, 0, 2.6179939)),
        ),
    ),
)
#: URDF root link, and the sum of the URDF's link masses (kg; the four inertials v0.1.0
#: comments out left out) and the root body's (its 15 links merged).
ROOT = "link_torso_1_top_torso_1"
TOTAL_MASS = 27.6012333686
ROOT_MASS = 7.97200855
#: The fixed joint from the head pitch joint's child link to ``link_head_1_head_1`` (the
#: camera's link): ``joint_head_1_fastened_3``.
HEAD_LINK_ORIGIN = ((-0.0093037, 0.00675953, -0.0345), (3.1415927, 0.0, 0.0))


def rpy_matrix(rpy: tuple[float, ...]) -> np.ndarray:
    """URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    roll, pitch, yaw = rpy
    return axis_rotation(Z, yaw) @ axis_rotation(Y, pitch) @ axis_rotation(X, roll)


def urdf_poses(root: np.ndarray, q: dict[str, float], flip: str = "") -> dict[str, np.ndarray]:
    """Every body's world pose ``(4, 4)`` chained from the root's through the URDF's
    origins and the joint rotations / slides ``q`` (``flip``: a joint whose axis is turned
    round, for the test that the check can fail)."""
    poses = {ROOT: root}
    for name, parent, child, axis, _, origins in URDF_JOINTS:
        pose = poses[parent]
        for xyz, rpy in origins:
            pose = pose @ transform(rpy_matrix(rpy), np.array(xyz))
        unit = np.array([float(v) for v in axis.split()]) * (-1.0 if name == flip else 1.0)
        if "slider" in name:
            pose = pose @ transform(np.eye(3), unit * q[name])
        else:
            pose = pose @ transform(axis_rotation(unit, q[name]), np.zeros(3))
        poses[child] = pose
    return poses


def body_pose(scene: ra.Scene, name: str) -> np.ndarray:
    body = scene.world.datas[0].body(scene.agents[0].prefix + name)
    return transform(body.xmat.reshape(3, 3).copy(), body.xpos.copy())


def test_urdf_table_covers_every_joint_in_maniskills_order() -> None:
    assert sorted(j[0] for j in URDF_JOINTS) == sorted(MANISKILL_JOINTS)
    assert len(MANISKILL_JOINTS) == len(MANISKILL_STANDING_QPOS) == 37


@pytest.mark.parametrize("pose", ["standing", "random"])
def test_every_body_follows_the_urdf_joint_origins(pose: str) -> None:
    """Every body (and the head camera's link) where the URDF's origins put it, to 5e-6 m
    and 5e-6 in rotation (the model's numbers are 6-digit roundings of the URDF's), at
    ManiSkill's ``standing`` and at 5 random configurations within the limits."""
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    for _ in range(1 if pose == "standing" else 5):
        if pose == "standing":
            scene.reset(keyframes="standing")
        else:
            q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
            agent.reset(qpos=q)
        q_by_name = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
        poses = urdf_poses(body_pose(scene, ROOT), q_by_name)
        for name, expected in poses.items():
            np.testing.assert_allclose(body_pose(scene, name), expected, atol=5e-6, err_msg=name)
        (xyz, rpy) = HEAD_LINK_ORIGIN
        head = poses["link_head_1_x4_2_inner_1"] @ transform(rpy_matrix(rpy), np.array(xyz))
        np.testing.assert_allclose(body_pose(scene, "link_head_1_head_1"), head, atol=5e-6)
    scene.close()


def test_the_chain_check_can_fail() -> None:
    """The same check with the knee's axis turned round misses the foot by centimetres."""
    scene = ra.Scene(UID)
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    q_by_name = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    knee = "joint_legs_1_right_leg_1_knee_revolute"
    poses = urdf_poses(body_pose(scene, ROOT), q_by_name, flip=knee)
    foot = "link_legs_1_right_leg_1_x4_1_outer_1"
    assert np.linalg.norm(poses[foot][:3, 3] - body_pose(scene, foot)[:3, 3]) > 0.05
    scene.close()


# ---------------------------------------------------------------- the URDF's numbers
def test_masses_and_ranges_are_the_urdfs() -> None:
    scene = ra.Scene(UID)
    agent, model = scene.agents[0], scene.model
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    assert float(model.body_mass[robot].sum()) == pytest.approx(TOTAL_MASS, abs=1e-5)
    assert float(model.body(agent.prefix + ROOT).mass[0]) == pytest.approx(ROOT_MASS, abs=1e-5)
    limits = dict(zip(agent.joint_names, agent.qpos_limits, strict=True))
    assert len(limits) == 37
    for name, _, _, _, (low, high), _ in URDF_JOINTS:
        assert tuple(limits[name]) == pytest.approx((low, high), abs=1e-9), name
    scene.close()


def test_actions_follow_maniskills_joint_order_and_bounds() -> None:
    """One part, ``body``, over ManiSkill's 37 joints in ManiSkill's order: absolute
    targets within the joint limits; deltas of at most 0.1 rad or m (ManiSkill's)."""
    scene = ra.Scene(UID, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert list(agent.controller.parts) == ["body"]
    assert agent.controller.parts["body"].config.joint_names == MANISKILL_JOINTS
    limits = agent.qpos_limits[[agent.joint_names.index(j) for j in MANISKILL_JOINTS]]
    np.testing.assert_allclose(agent.single_action_space.low, limits[:, 0].astype(np.float32))
    np.testing.assert_allclose(agent.single_action_space.high, limits[:, 1].astype(np.float32))
    scene.close()
    delta = ra.Scene(UID, control_modes="pd_joint_delta_pos")
    np.testing.assert_allclose(delta.agents[0].controller.parts["body"].to_raw(np.ones((1, 37)))[0], 0.1)
    delta.close()


def test_standing_is_maniskills_but_the_head_pitch_and_height() -> None:
    """ManiSkill's joint values, the head pitch at its limit (ManiSkill's 0.5 rad lies past
    it), the torso 7 mm higher than ManiSkill's 0.965 m: the soles just clear the floor."""
    scene = ra.Scene(UID)
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    q = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    for name, value in zip(MANISKILL_JOINTS, MANISKILL_STANDING_QPOS, strict=True):
        expected = 0.26179939 if name == "joint_head_1_x4_2_dof_x4" else value
        assert q[name] == pytest.approx(expected, abs=1e-12), name
    assert agent.base_pose[0, 2] == pytest.approx(0.965 + 0.007, abs=1e-12)
    assert pytest.approx(0.972) == STANDING_HEIGHT
    scene.close()


# ---------------------------------------------------------------- standing
def tilt_deg(quat: np.ndarray) -> float:
    _, x, y, _ = quat
    return math.degrees(math.acos(float(np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0))))


def stand(cls: type[ra.Agent] | str, seconds: float = 5.0) -> dict[str, float | bool | set[str]]:
    """Reset to ``standing`` and repeat the default mode's hold action; the base's
    movement over the last 4 s, the largest tilt, the bodies touching the floor, and
    whether it ends standing (``is_standing``, not ``is_fallen``)."""
    scene = ra.Scene(cls)
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    model, data = scene.model, scene.world.datas[0]
    hold = hold_action(agent)
    positions, tilt, touching = [], 0.0, set()
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(hold)
        scene.step()
        pose = agent.base_pose[0]
        positions.append(pose[:3].copy())
        tilt = max(tilt, tilt_deg(pose[3:]))
        for contact in data.contact[: data.ncon]:
            bodies = {int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])}
            if 0 in bodies:
                touching |= {model.body(b).name.removeprefix(agent.prefix) for b in bodies - {0}}
    standing = bool(agent.is_standing()[0]) and not bool(agent.is_fallen()[0])
    scene.close()
    late = np.array(positions[round(scene.control_freq) :])
    return {
        "standing": standing,
        "moved": float(np.max(np.linalg.norm(late - late[0], axis=1))),
        "height": float(positions[-1][2]),
        "tilt": tilt,
        "touching": touching,
    }


def test_stands_on_its_feet_for_5_s_from_standing() -> None:
    """ManiSkill's ``standing`` (its soles rolled 4.3 deg: it lands on their edges), the
    hold action: the torso moves under 2 mm over the last 4 s, tilts at most 4.5 deg, the
    feet alone on the floor."""
    result = stand(UID)
    assert result["standing"]
    assert result["moved"] < 0.002
    assert result["tilt"] < 4.5
    assert result["touching"] == {"link_legs_1_right_leg_1_x4_1_outer_1", "link_legs_1_left_leg_1_x4_1_outer_1"}


class ManiSkillGainsStompy(Stompy):
    """ManiSkill's gains (100 N*m/rad, 10 N*m*s/rad) on the legs too."""

    actuators: ClassVar = (
        dataclasses.replace(STOMPY_DRIVES[0], stiffness=MANISKILL_KP, damping=MANISKILL_KV),
        *STOMPY_DRIVES[1:],
    )


class UrdfEffortStompy(Stompy):
    """Our gains, each drive limited to the URDF's effort."""

    actuators: ClassVar = tuple(
        PDActuator(
            joints=name,
            stiffness=LEG_KP if name.startswith("joint_legs") else MANISKILL_KP,
            damping=LEG_KV if name.startswith("joint_legs") else MANISKILL_KV,
            effort_limit=URDF_EFFORT[joint_kind(name)],
            armature=ARMATURE,
        )
        for name in MANISKILL_JOINTS
    )


@pytest.mark.parametrize("cls", [ManiSkillGainsStompy, UrdfEffortStompy], ids=["maniskill_gains", "urdf_effort"])
def test_why_the_leg_drives_are_ours(cls: type[ra.Agent]) -> None:
    """With ManiSkill's 100 N*m/rad on the legs, or with each drive limited to the URDF's
    effort (the standing load needs 13 N*m at the 6 N*m hip roll drives), the robot falls."""
    assert not stand(cls, seconds=3.0)["standing"]


# ---------------------------------------------------------------- grasp
CUBE_HALF = 0.02


@pytest.mark.parametrize("side", ["right_arm_1", "left_arm_2"])
def test_each_gripper_holds_a_cube_under_its_weight(side: str) -> None:
    """A 4 cm cube, weightless, between the open fingers of the standing robot; the
    gripper closes (slider targets at ``closed``) for 1 s, then the cube gets its weight:
    over 2 s it moves under 2 mm relative to the fingers, both fingers press on it
    (``is_grasping``), and the contact forces on it sum to its weight (5%)."""
    cube = free_cube("cube", CUBE_HALF, (0.8, 0.2, 0.2, 1.0), pos=(1.0, 1.0, CUBE_HALF))
    scene = ra.Scene(UID, props=[cube])
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    model, data = scene.model, scene.world.datas[0]
    hold = hold_action(agent)
    for _ in range(scene.control_freq):  # settle on the feet
        agent.set_action(hold)
        scene.step()
    finger_a = data.geom(agent.prefix + f"{side}_hand_1_gripper_1")
    finger_b = data.geom(agent.prefix + f"{side}_hand_1_gripper_2")

    def grip_frame() -> tuple[np.ndarray, np.ndarray]:
        closing = finger_b.xpos - finger_a.xpos
        closing /= np.linalg.norm(closing)
        along = finger_a.xmat.reshape(3, 3)[:, 2]
        along = along - (along @ closing) * closing
        along /= np.linalg.norm(along)
        return (finger_a.xpos + finger_b.xpos) / 2.0, np.stack([closing, along, np.cross(closing, along)], axis=1)

    centre, axes = grip_frame()
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, axes.reshape(-1))
    body = model.body("cube")
    joint = int(body.jntadr[0])
    qpos_adr = np.arange(7) + int(model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(model.jnt_dofadr[joint])
    scene.world.write_joint_state([0], qpos_adr, np.concatenate([centre, quat])[None], dof_adr, np.zeros((1, 6)))
    mass = float(model.body_mass[body.id])
    weight = -mass * model.opt.gravity
    data.xfrc_applied[body.id, :3] = weight
    close = hold.copy()
    for name in (f"joint_{side}_hand_1_slider_1", f"joint_{side}_hand_1_slider_2"):
        close[MANISKILL_JOINTS.index(name)] = GRIPPER_CLOSED
    for _ in range(scene.control_freq):  # close on the weightless cube
        agent.set_action(close)
        scene.step()
    data.xfrc_applied[body.id, :3] = 0.0

    def in_grip() -> np.ndarray:
        centre, axes = grip_frame()
        return axes.T @ (data.xpos[body.id] - centre)

    start, slip = in_grip(), 0.0
    for _ in range(2 * scene.control_freq):
        agent.set_action(close)
        scene.step()
        slip = max(slip, float(np.linalg.norm(in_grip() - start)))
    assert slip < 0.002
    assert bool(agent.is_grasping("cube", gripper=side.split("_")[0] + "_gripper")[0])
    force = np.zeros(3)
    fingers = {model.body(agent.prefix + f"link_{side}_hand_1_slide_{i}").id for i in (1, 2)}
    touching = set()
    for i, contact in enumerate(data.contact[: data.ncon]):
        bodies = (int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2]))
        if body.id not in bodies:
            continue
        other = bodies[0] if bodies[1] == body.id else bodies[1]
        touching.add(other)
        local = np.zeros(6)
        mujoco.mj_contactForce(model, data, i, local)
        world = contact.frame.reshape(3, 3).T @ local[:3]  # force on geom1, world axes
        force += world if bodies[0] == body.id else -world
    assert touching == fingers
    np.testing.assert_allclose(force, -weight, atol=0.05 * np.linalg.norm(weight))
    scene.close()


class AllJointModesStompy(Stompy):
    """Stompy with the library's six joint modes (ours declares ManiSkill's two)."""

    control_modes: ClassVar = {mode: {"body": config} for mode, config in joint_control_modes(STOMPY_BODY).items()}


def test_why_the_velocity_modes_are_left_out() -> None:
    """With unlimited drives (ManiSkill's), 2 s of random velocity targets spin a beltless
    rotor (kv x up to 31.4 rad/s) more than 1 rad through its joint limit; ManiSkill's two
    modes stay within 0.25 rad of the stops (the sweep's bound)."""

    def overshoot(cls: type[ra.Agent], mode: str) -> float:
        scene = ra.Scene(cls, control_modes=mode)
        scene.reset()
        agent = scene.agents[0]
        space, limits = agent.single_action_space, agent.qpos_limits
        rng = np.random.default_rng(0)
        worst = 0.0
        for _ in range(2 * scene.control_freq):
            agent.set_action(rng.uniform(space.low, space.high))
            scene.step()
            q = agent.qpos[0]
            worst = max(worst, float(np.max(np.maximum(q - limits[:, 1], limits[:, 0] - q))))
        scene.close()
        return worst

    assert overshoot(AllJointModesStompy, "pd_joint_vel") > 1.0
    for mode in Stompy.modes():
        assert overshoot(Stompy, mode) < 0.25, mode
