"""The Inspire RH56DFX hand's model, written once for both sides: the right hand's
numbers (ManiSkill's ``inspire_hand_right.urdf``, read as data; see
:mod:`robot_agents.robots.inspire.inspire_hand`) and the mirror that makes the left
hand of them. :func:`hand_mjcf` writes the MJCF text of one side; the files
``assets/inspire_hand_{right,left}.xml`` are its output, regenerated with
``python -m robot_agents.robots.inspire.model`` (tests/test_inspire_hand.py checks that
they are).

The mirror: the left hand is the right one reflected through a plane. Each link has a
mirror axis in its own frame, the normal of that plane (``wrist_base_link``: x; every
other link: z). A link origin ``(p, R)`` in its parent's frame becomes
``(M_parent p, M_parent R M_child)`` and a link's centre of mass and inertia ``M c`` and
``M I M`` (``M``: the reflection of the link's axis). Every joint turns about its
link's z axis, which the reflection ``M_z`` leaves as it is, so the left hand's joint
angles, ranges, couplings and keyframes are the right hand's. The upstream left URDF
(``inspire_hand_left.urdf``) is this mirror of the right one to its printed digits
(joint frames within 3e-7: it prints the thumb MCP's yaw -0.003172 where the right one
prints -0.0031723; masses and inertias within 0.1 %: two exports of one CAD model).

Inertials are the URDF's, except that most of its products of inertia under 1e-10
kg*m^2 and centre-of-mass offsets under 1e-7 m are written as 0, and that the four
finger proximals take the middle, ring and pinky's 7.4556 g (the index's is 7.4557 g).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

ASSETS = Path(__file__).parent / "assets"
SIDES = ("right", "left")

Vec3 = tuple[float, float, float]
HALF_PI = 1.5707963267948966


@dataclass(frozen=True)
class Inertial:
    """A link's mass (kg), centre of mass (m) and inertia about it (kg*m^2: ixx, iyy,
    izz, ixy, ixz, iyz), in the link frame."""

    mass: float
    com: Vec3
    inertia: tuple[float, float, float, float, float, float]


@dataclass(frozen=True)
class Shape:
    """A primitive collision and visual shape: ``kind`` box (``size``: half extents),
    cylinder (radius, half length, along z) or capsule (``fromto`` and radius), in the
    link frame (m)."""

    kind: str
    pos: Vec3 = (0.0, 0.0, 0.0)
    size: tuple[float, ...] = ()
    fromto: tuple[float, float, float, float, float, float] | None = None
    euler: Vec3 = (0.0, 0.0, 0.0)
    collides: bool = True


@dataclass(frozen=True)
class Link:
    """One link of the right hand: its origin in the parent frame (URDF xyz, rpy), its
    joint (about the link's z axis; ``None``: fixed), range (rad), coupling (``leader,
    multiplier, offset``: ``q = offset + multiplier * q_leader``) and shapes."""

    name: str
    parent: str | None
    xyz: Vec3
    rpy: Vec3
    joint: str | None = None
    joint_range: tuple[float, float] | None = None
    mimic: tuple[str, float, float] | None = None
    inertial: Inertial | None = None
    shapes: tuple[Shape, ...] = ()
    mirror_axis: int = 2
    pad: bool = False


# ------------------------------------------------------------------ the right hand's numbers
# Origins, ranges, couplings and inertials: ManiSkill's inspire_hand_right.urdf (names
# without the ``right_hand_`` prefix). Shapes: boxes, cylinders and capsules fitted to
# the extents of the URDF's visual meshes (measured with trimesh; see the robot module).
FINGER_PROXIMAL = Inertial(
    0.0074556, (0.013292, -0.0019853, 0.0), (3.0932e-07, 8.2022e-07, 9.1249e-07, 1.1169e-07, 0.0, 0.0)
)
PROXIMAL_BOX = Shape("box", (0.0129, -0.0015, 0.0), (0.0225, 0.0124, 0.0072))
#: Each finger: (name, MCP origin xyz, MCP yaw (rad), PIP yaw (rad), middle-link inertial,
#: middle-link capsule end (x, y), tip origin (x, y)).
FINGERS: tuple[tuple[str, Vec3, float, float, Inertial, tuple[float, float], tuple[float, float]], ...] = (
    (
        "index",
        (0.027071, 0.10464, -0.0020953),
        1.5359,
        0.0016248,
        Inertial(0.0044472, (0.018926, -0.0015379, 0.0), (1.4776e-07, 6.6739e-07, 7.4626e-07, 2.0201e-07, 0.0, 0.0)),
        (0.0377, -0.0078),
        (0.043944, -0.009147),
    ),
    (
        "middle",
        (0.00775, 0.105, -0.0020953),
        HALF_PI,
        -0.019795,
        Inertial(0.0048916, (0.020219, -0.0014517, 0.0), (1.6257e-07, 8.8194e-07, 9.6869e-07, 2.4464e-07, 0.0, 0.0)),
        (0.0415, -0.0078),
        (0.047746, -0.009066),
    ),
    (
        "ring",
        (-0.011479, 0.1045, -0.0020953),
        1.6232,
        0.0016262,
        Inertial(0.0044472, (0.018926, -0.0015379, 0.0), (1.4776e-07, 6.6738e-07, 7.4626e-07, 2.0201e-07, 0.0, 0.0)),
        (0.0377, -0.0078),
        (0.043944, -0.009147),
    ),
    (
        "pinky",
        (-0.030655, 0.10299, -0.0020953),
        1.6755,
        0.090322,
        Inertial(
            0.00358,
            (0.015705, -0.001732, -3.0224e-05),
            (1.1688e-07, 3.6707e-07, 4.2838e-07, 1.3011e-07, 5.7801e-10, -3.7876e-10),
        ),
        (0.0297, -0.0080),
        (0.035855, -0.009619),
    ),
)
#: The URDF's MCP range and its PIP coupling (``PIP = -0.167348 + 1.06399 MCP``, range).
MCP_RANGE = (-1.34, 0.0)
PIP_RANGE = (-1.5930946, 0.04545)
PIP_MIMIC = (1.06399, -0.167348)
#: The thumb's bend couplings, Inspire's own (the URDF's commented-out tags; ManiSkill
#: chains the IP joint to the MCP instead, the same relation): both follow the CMC pitch.
THUMB_MCP_MIMIC = (1.3333333333333335, -0.08144869842640205)
THUMB_IP_MIMIC = (0.6666666666666667, -0.040724349213201026)


def _finger_links(
    name: str,
    xyz: Vec3,
    yaw: float,
    pip_yaw: float,
    middle: Inertial,
    end: tuple[float, float],
    tip: tuple[float, float],
) -> list[Link]:
    mcp = f"{name}_MCP_joint"
    return [
        Link(
            f"{name}_proximal",
            "hand_base_link",
            xyz,
            (-HALF_PI, 0.12457, yaw),
            mcp,
            MCP_RANGE,
            None,
            FINGER_PROXIMAL,
            (PROXIMAL_BOX,),
        ),
        Link(
            f"{name}_middle",
            f"{name}_proximal",
            (0.030445, -0.010275, 0.0),
            (0.0, 0.0, pip_yaw),
            f"{name}_PIP_joint",
            PIP_RANGE,
            (mcp, *PIP_MIMIC),
            middle,
            (Shape("capsule", size=(0.0063,), fromto=(0.0, 0.002, 0.0, end[0], end[1], 0.0)),),
            pad=True,
        ),
        Link(f"{name}_tip", f"{name}_middle", (tip[0], tip[1], 0.0), (0.0, 0.0, 0.0)),
    ]


LINKS: tuple[Link, ...] = (
    Link(
        "wrist_base_link",
        None,
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        inertial=Inertial(
            0.065373,
            (2.5182e-06, 0.0014729, 0.032787),
            (4.1551e-05, 4.1183e-05, 2.7992e-05, 7.0443e-11, -6.0666e-09, 8.3238e-09),
        ),
        shapes=(Shape("cylinder", (0.0, 0.0, 0.0392), (0.03, 0.0392)),),
        mirror_axis=0,
    ),
    Link(
        "wrist_link",
        "wrist_base_link",
        (0.0, 0.0, 0.0785),
        (HALF_PI, 0.0, HALF_PI),
        "wrist_pitch_joint",
        (-0.39549160850191506, 0.3860668305411457),
        inertial=Inertial(
            0.00056124, (0.0, -7.0516e-06, -7.9885e-05), (2.9483e-08, 2.9284e-08, 2.2194e-09, 0.0, 0.0, 3.1625e-13)
        ),
        shapes=(Shape("cylinder", (0.0, 0.0, 0.0), (0.003, 0.014), collides=False),),
    ),
    Link(
        "hand_base_link",
        "wrist_link",
        (0.0, 0.0, 0.0),
        (0.0, HALF_PI, 0.0),
        "wrist_yaw_joint",
        (-0.445058959258554, 0.445058959258554),
        inertial=Inertial(
            0.19286,
            (-0.001139, 0.05204, -0.0013473),
            (9.3622e-05, 9.545e-05, 0.00016048, -1.7899e-06, 6.7062e-07, 2.7767e-06),
        ),
        shapes=(
            # the palm below the finger bases, the thenar pad beside the thumb, the wrist end
            Shape("box", (-0.001, 0.06, -0.0035), (0.040, 0.04, 0.0155)),
            Shape("box", (0.0, 0.03, 0.0175), (0.038, 0.02, 0.0055)),
            Shape("cylinder", (0.0, -0.005, 0.0), (0.027, 0.015), euler=(HALF_PI, 0.0, 0.0)),
        ),
        pad=True,
    ),
    Link(
        "thumb_metacarpal_base",
        "hand_base_link",
        (0.02125, 0.0285, 0.01515),
        (-HALF_PI, -0.2617993877991494, 0.0),
        "thumb_CMC_yaw_joint",
        (-1.3089969389957472, 0.0),
        inertial=Inertial(
            0.0015178,
            (0.003828, 0.0005479, 2.5426e-05),
            (3.6056e-08, 6.0741e-08, 5.6162e-08, 5.7714e-09, 1.9601e-09, -2.0748e-10),
        ),
        shapes=(Shape("box", (0.0036, 0.001, 0.0), (0.0106, 0.0068, 0.0058)),),
    ),
    Link(
        "thumb_metacarpal",
        "thumb_metacarpal_base",
        (0.0115, 0.0, -0.00075),
        (-HALF_PI, -0.6831165238198015, 0.0),
        "thumb_CMC_pitch_joint",
        (-0.4799655442984406, 0.0),
        inertial=Inertial(
            0.026112, (0.025599, 0.0011669, 0.0), (2.4138e-06, 6.7222e-06, 7.9398e-06, 1.4258e-07, 0.0, 0.0)
        ),
        shapes=(Shape("box", (0.0292, 0.0007, 0.0), (0.0339, 0.0163, 0.0097)),),
        pad=True,
    ),
    Link(
        "thumb_proximal",
        "thumb_metacarpal",
        (0.055852, -0.0040666, 0.0),
        (0.0, 0.0, -0.0031723),
        "thumb_MCP_joint",
        (-0.8, 0.0),
        ("thumb_CMC_pitch_joint", *THUMB_MCP_MIMIC),
        Inertial(0.0076245, (0.0096374, 0.0056519, 0.0), (3.7134e-07, 7.908e-07, 8.6329e-07, 9.4961e-08, 0.0, 0.0)),
        (Shape("box", (0.0057, 0.0053, 0.0), (0.0224, 0.0118, 0.0081)),),
        pad=True,
    ),
    Link(
        "thumb_distal",
        "thumb_proximal",
        (0.022558, 0.0020717, 0.0),
        (0.0, 0.0, 0.011853),
        "thumb_IP_joint",
        (-0.4, 0.0),
        ("thumb_CMC_pitch_joint", *THUMB_IP_MIMIC),
        Inertial(0.0032026, (0.01088, 0.00050953, 0.0), (8.1419e-08, 1.751e-07, 1.8651e-07, 2.1824e-08, 0.0, 0.0)),
        (Shape("box", (0.0098, 0.0017, 0.0), (0.0152, 0.0085, 0.0073)),),
        pad=True,
    ),
    Link("thumb_tip", "thumb_distal", (0.024859, -0.000031, 0.0), (0.0, 0.0, 0.0)),
    *(link for finger in FINGERS for link in _finger_links(*finger)),
)


# ------------------------------------------------------------------ rotations and the mirror
def rpy_matrix(rpy: Sequence[float]) -> npt.NDArray[np.float64]:
    """URDF roll-pitch-yaw (rad) as a rotation matrix ``(3, 3)``: Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_quat(rotation: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """A rotation matrix ``(3, 3)`` as a unit quaternion ``(w, x, y, z)`` with w >= 0."""
    import mujoco

    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, dtype=np.float64).reshape(9))
    return quat if quat[0] >= 0.0 else -quat


def reflection(axis: int) -> npt.NDArray[np.float64]:
    """The reflection ``(3, 3)`` that negates coordinate ``axis`` (0: x, 1: y, 2: z)."""
    m = np.eye(3)
    m[axis, axis] = -1.0
    return m


def _fmt(values: Sequence[float] | npt.NDArray[np.float64]) -> str:
    return " ".join(f"{float(v) + 0.0:.9g}" for v in values)


def _inertia_matrix(values: tuple[float, float, float, float, float, float]) -> npt.NDArray[np.float64]:
    ixx, iyy, izz, ixy, ixz, iyz = values
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _shape_xml(shape: Shape, m: npt.NDArray[np.float64], cls: str) -> str:
    if shape.fromto is not None:
        a, b = m @ np.array(shape.fromto[:3]), m @ np.array(shape.fromto[3:])
        where = f'fromto="{_fmt([*a, *b])}"'
    else:
        rotation = m @ rpy_matrix(shape.euler) @ m
        where = f'pos="{_fmt(m @ np.array(shape.pos))}"'
        if shape.euler != (0.0, 0.0, 0.0):
            where += f' quat="{_fmt(matrix_quat(rotation))}"'
    return f'<geom class="{cls}" type="{shape.kind}" {where} size="{_fmt(shape.size)}"/>'


def hand_mjcf(side: str) -> str:
    """The MJCF text of the ``side`` (``"right"`` or ``"left"``) hand: bodies, joints and
    equalities named with the upstream ``{side}_hand_`` prefix."""
    if side not in SIDES:
        from robot_agents.errors import UnknownNameError

        raise UnknownNameError("hand_mjcf", "side", side, SIDES)
    prefix = f"{side}_hand_"
    mirrors = {link.name: reflection(link.mirror_axis) if side == "left" else np.eye(3) for link in LINKS}
    children: dict[str | None, list[Link]] = {}
    for link in LINKS:
        children.setdefault(link.parent, []).append(link)
    lines: list[str] = []

    def body(link: Link, depth: int) -> None:
        pad = "  " * depth
        m = mirrors[link.name]
        mp = mirrors[link.parent] if link.parent is not None else np.eye(3)
        pos = mp @ np.array(link.xyz)
        quat = matrix_quat(mp @ rpy_matrix(link.rpy) @ m)
        cls = ' childclass="inspire"' if link.parent is None else ""
        lines.append(f'{pad}<body name="{prefix}{link.name}" pos="{_fmt(pos)}" quat="{_fmt(quat)}"{cls}>')
        if link.inertial is not None:
            inertia = m @ _inertia_matrix(link.inertial.inertia) @ m
            full = (inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2])
            lines.append(
                f'{pad}  <inertial pos="{_fmt(m @ np.array(link.inertial.com))}" mass="{link.inertial.mass:.9g}" '
                f'fullinertia="{_fmt(full)}"/>'
            )
        if link.joint is not None and link.joint_range is not None:
            kind = "inspire_follower" if link.mimic is not None else "inspire_driven"
            lines.append(f'{pad}  <joint name="{prefix}{link.joint}" class="{kind}" range="{_fmt(link.joint_range)}"/>')
        for shape in link.shapes:
            visual = "inspire_pad_visual" if link.pad else "inspire_visual"
            lines.append(f"{pad}  {_shape_xml(shape, m, visual)}")
            if shape.collides:
                lines.append(f"{pad}  {_shape_xml(shape, m, 'inspire_collision')}")
        for child in children.get(link.name, []):
            body(child, depth + 1)
        lines.append(f"{pad}</body>")

    for root in children[None]:
        body(root, 2)
    equalities = [
        f'    <joint name="{prefix}{link.joint}_mimic" joint1="{prefix}{link.joint}" joint2="{prefix}{link.mimic[0]}" '
        f'polycoef="{_fmt((link.mimic[2], link.mimic[1], 0.0, 0.0, 0.0))}"/>'
        for link in LINKS
        if link.mimic is not None and link.joint is not None
    ]
    return TEMPLATE.format(side=side, bodies="\n".join(lines), equalities="\n".join(equalities))


TEMPLATE = """<!--
  Inspire RH56DFX hand, {side} side: a model of its own, primitive shapes only, GENERATED
  by robot_agents/robots/inspire/model.py (python -m robot_agents.robots.inspire.model);
  edit the numbers there, not here. The numbers and their sources are listed in
  robot_agents/robots/inspire/inspire_hand.py.

  Frames, joint and link names: ManiSkill's RH56DFX-2LR URDF (inspire_hand_{side}.urdf,
  read as data). The root `{side}_hand_wrist_base_link` is the wrist's base (z up the
  forearm axis), then the wrist's pitch and yaw joints, then the palm
  `{side}_hand_hand_base_link` (y along the fingers). Every joint turns about its link's
  z axis. The distal joints follow their proximal ones, and the thumb's MCP and IP joints
  its CMC pitch, through joint equalities (the URDF's mimic tags).

  Geoms: collision shapes (group 3, massless: every link has the URDF's inertial) and
  visual copies (group 2): boxes, cylinders and capsules fitted to the URDF meshes'
  extents. The collision geoms are the hand's pads: near-rigid contact with priority.
-->
<mujoco model="inspire_hand_{side}">
  <compiler angle="radian" autolimits="true"/>

  <default>
    <default class="inspire">
      <joint axis="0 0 1" solreflimit="0.005 1" solimplimit="0.95 0.99 0.001"/>
      <default class="inspire_driven"/>
      <default class="inspire_follower">
        <joint armature="0.0001" damping="0.001"/>
      </default>
      <default class="inspire_visual">
        <geom group="2" contype="0" conaffinity="0" density="0" rgba="0.75 0.75 0.78 1"/>
        <default class="inspire_pad_visual">
          <geom rgba="0.15 0.15 0.15 1"/>
        </default>
      </default>
      <!-- near-rigid contact, winning parameter mixing (the library's pads: Menagerie's
           trs_so_arm100 pad values): with MuJoCo's default contact a finger's saturated
           drive pressed 17.5 mm into the grasp claim's 64 g cube -->
      <default class="inspire_collision">
        <geom group="3" density="0" rgba="0.55 0.65 0.8 0.5" priority="1" solref="0.01 1"
              solimp="0.9999 0.9999 0.01"/>
      </default>
    </default>
  </default>

  <worldbody>
{bodies}
  </worldbody>

  <equality>
{equalities}
  </equality>
</mujoco>
"""


def write_assets(directory: Path = ASSETS) -> list[Path]:
    """Write both sides' MJCF files into ``directory``; returns their paths."""
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for side in SIDES:
        path = directory / f"inspire_hand_{side}.xml"
        path.write_text(hand_mjcf(side))
        paths.append(path)
    return paths


def main(argv: Sequence[str] | None = None) -> None:
    """Regenerate both asset files from the numbers above."""
    parser = argparse.ArgumentParser(description="Write assets/inspire_hand_{right,left}.xml from the numbers.")
    parser.parse_args(argv)
    write_assets()


if __name__ == "__main__":
    main()
