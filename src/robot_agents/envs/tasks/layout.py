"""Where the table-top scene puts a robot, its table and its workspace, measured from
the robot's own definition (no per-robot numbers anywhere).

The layout (:func:`table_top_layout`, computed once per robot class on a probe scene):

- **Reach** ``R``: how far the first end effector gets from the anchor of the arm's
  first joint (its *shoulder*), the largest distance over the default keyframe and
  1024 configurations drawn (with a fixed seed) uniformly within the arm joints'
  limits: 0.95 m for the Panda, 1.36 m for the UR10e, 0.51 m for the SO-100.
- **Facing**: the robot is turned about the vertical so that its default keyframe's
  tool lies straight ahead of its shoulder, along world +x (a robot whose tool is
  above its shoulder keeps its heading).
- **Placement**: the robot stands on the table top, at its own ``mount_pose`` above
  it, moved so that its default keyframe's tool is above the world origin: the
  *workspace centre*, where cubes and goals are drawn around. An arm that turns on a
  hinge and whose default keyframe holds the tool up (within :data:`UPRIGHT_SHARE`
  ``R`` of its shoulder, horizontally: the pose every joint at zero gives most model
  files) or stretched out (farther than :data:`STRETCHED_SHARE` ``R``: the Koch's file)
  has the centre :data:`UPRIGHT_AHEAD` ``R`` ahead of the shoulder instead (the built-in
  arms rest their tools 0.25-0.65 R ahead), or, when it has a gripper, in the middle of
  the distances at which its tool reaches pointing down at the heights of cubes and
  goals, where that is nearer (:func:`_pointing_down_points`: configurations in which
  the robot touches itself or the table top are left out). A robot that declares no
  keyframe (its default is its file's pose) gets its centre there whatever its rest
  pose, with or without a gripper (a bare tool pointing its z down). The table top is at
  ``z = 0.75 R`` above the floor and spans from ``0.35 R`` behind the robot's root to
  ``0.55 R`` ahead of the workspace centre, ``1.2 R`` wide.
- **A robot on a pedestal of its own** (its file's: gymnasium-robotics' Franka
  kitchen), whose tool gets no lower over the floor it stands on than the goals' heights
  over the cubes, stands on the floor instead; the table top rises to where the heights
  of cubes and goals centre on the median height at which its tool points down
  (:func:`_centred_band`), below what of the robot moves as it rests (an arm hung from
  above), and the table starts :data:`TABLE_CLEARANCE` ``R`` clear of the robot's fixed
  geoms lower than its top (the pedestal), the centre moved ahead where a cube drawn
  nearest the robot would lie off it.
- **A tall arm** (gymnasium-robotics' Fetch: its shoulder 0.80 m over the base it
  stands on), with a gripper and its centre where its tool points down (above), whose
  tool points down at the heights of cubes and goals over its mount floor only over a
  band of distances from its shoulder narrower than :data:`NARROW_BAND` ``R``, stands
  on the floor too, where a table top risen as for a pedestal (the median height at
  which it points down; not capped under its moving parts, but below its shoulder's
  first joint, so that the arm stands over its table) widens that band; the
  centre goes to the middle of the risen band, and the table starts
  :data:`TABLE_CLEARANCE` ``R`` clear of every part of the robot lower than its top as
  it rests (``lowered``).
- **Mobile robots** (a ``Base`` part) stand on the floor at their ``mount_pose``
  instead, next to the table, facing it as above. The table top is ``0.15 R`` below
  the default keyframe's tool (0.18 R for the Panda on its table). The table's near
  edge clears, by ``0.02 R``, the circle that the robot's geoms lower than the table
  top (plus 1 cm) sweep when the base turns in place about its yaw axis, so the robot
  can turn at the table. The workspace centre lies under the rest tool, or further
  ahead when a cube drawn near the centre's robot side could overhang that edge.
  ``robot_pose`` is this stance (where a mobile task docks the base).
- **Cube**: its edge is half the opening of the gripper (the distances from the tool
  point, or the gripper's ``grasp_frame``, to each finger's colliding geoms, gripper
  open, summed), 4 cm for the Panda;
  for a robot without a gripper, ``0.04 R``. Density 1000 kg/m^3 (water).
- **Randomization scale**: cubes and goals are drawn within ``0.1 R`` of the
  workspace centre (the Panda's: 0.095 m; ManiSkill's PickCube uses 0.1 m).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.agent.derived import colliding_geoms, geom_box, random_configurations, world_box
from robot_agents.agent.index import JointKind
from robot_agents.errors import ConfigError
from robot_agents.kinematics.rotations import z_rotation_quat
from robot_agents.model.scene import Prop
from robot_agents.parts.declaration import Arm, Base
from robot_agents.registry import agent_class
from robot_agents.sim.scene import Scene

FloatArray = npt.NDArray[np.float64]

#: Configurations drawn to measure the reach (fixed seed: the layout is deterministic).
REACH_SAMPLES = 1024
#: Table-top height above the floor, as a share of the reach.
TABLE_HEIGHT = 0.75
#: Cubes and goals are drawn within this share of the reach of the workspace centre.
SPAWN_HALF_SIZE = 0.1
#: Cube edge as a share of the gripper's opening, and of the reach without a gripper.
CUBE_PER_OPENING = 0.5
CUBE_PER_REACH = 0.04
#: Cube density (kg/m^3).
CUBE_DENSITY = 1000.0
#: Smallest cube edge (m).
MIN_CUBE_EDGE = 0.01
#: Mobile robots: the table top lies this share of the reach below the default
#: keyframe's tool (the Panda's rest tool is 0.18 R above its table).
TOOL_ABOVE_TABLE = 0.25
#: Mobile robots: clearance between the base's turning circle and the table, and
#: between a cube drawn nearest the robot and the table's edge, as shares of the reach.
TABLE_CLEARANCE = 0.02
#: An arm whose rest tool lies within this share of the reach of its shoulder,
#: horizontally, holds it up, and one whose rest tool lies farther than
#: :data:`STRETCHED_SHARE` holds it stretched out (the built-in arms rest it 0.25-0.65 R
#: ahead) ...
UPRIGHT_SHARE = 0.2
STRETCHED_SHARE = 0.7
#: ... and either gets its workspace centre this share of the reach ahead of its shoulder,
#: or, with a gripper, in the middle of where its tool reaches pointing down at the cube
#: and goal heights (see :func:`_middle_distance`), where that is nearer.
UPRIGHT_AHEAD = 0.5
#: An arm with a gripper whose tool reaches pointing down at the heights of cubes and
#: goals over a band of distances from its shoulder narrower than this share of the
#: reach (the cubes' spread, 0.2, and PushCube's goals up to 0.25 ahead of them) stands
#: on the floor next to a table risen to where it points down (see the module doc).
NARROW_BAND = 0.45
#: Configurations drawn (fixed seed) to find where an arm's tool reaches pointing down,
#: the largest tilt from straight down that counts (rad), and the fewest such tool
#: points that give a measure.
DOWN_SAMPLES = 8192
DOWN_TILT = math.radians(20.0)
DOWN_MIN_POINTS = 10
#: The axis of a tool frame without a gripper that points at what it touches (its z: a
#: flange's outward normal, as ROS-Industrial's ``tool0`` and the push solver take it).
TOOL_AXIS = (0.0, 0.0, 1.0)
#: How deep a contact of the robot with itself or the table may be in a configuration
#: counted as pointing down (m): deeper, the arm would press into it.
DOWN_CONTACT_DEPTH = 1e-3
#: Gripper positions, open to closed, over which the fingers' reach past the grasp point
#: is measured (``GripperGeometry.tip_reach``).
TIP_REACH_SAMPLES = 9
#: A gripper of one hinge keeps the closing axis its open fingers' nearest points give
#: unless that axis points this far from the way the jaw carries the tool point as it
#: closes (cosine; 45 deg): with the Unitree Z1 file's meshes decomposed, the open jaw's
#: nearest point to the tool point lay to its side, and the axis ran along the jaw's
#: width (PickCube 0 of 20, the cube set beside the jaws).
JAW_AXIS_AGREEMENT = math.cos(math.radians(45.0))
#: Geoms lower than the table top plus this (m) sweep the floor around the table.
LOW_GEOM_MARGIN = 0.01


@dataclass(frozen=True)
class GripperGeometry:
    """The open gripper as seen from its tool point (vectors in the tool frame).

    Attributes:
        opening: gap between the open fingers at the grasp point (m): the tool point, or
            the gripper's ``grasp_frame`` where it declares one.
        grasp_point: the middle of the gap on the closing axis through that point (m):
            where an object's centre goes for a grasp.
        closing_axis: unit vector from the first finger towards the second, square to
            the approach axis.
        approach_axis: unit vector from the arm's last joint to the point the opening is
            measured at: the way the fingers point.
        tip_reach: how far the fingers' colliding geometry reaches past the grasp point
            along the approach axis at any point of their stroke, open to closed (m): a
            grasp from above keeps the grasp point at least this high over the table.
        closed_point: where the closed fingers are (m): the middle of each finger's
            nearest point to the grasp point, the gripper closed. A parallel gripper's
            fingers close on the grasp point; a one-jaw gripper's moving jaw closes on
            its fixed jaw, off it along the closing axis (the SO-100 file's: 2.2 cm
            across the approach axis), where a push with the closed jaws must aim.
        closed_clearance: how far the grasp point lies from the nearest closed finger
            (m; 0 inside one): the SO-100 file's 2.6 cm, the Panda's 0.
    """

    opening: float
    grasp_point: tuple[float, float, float]
    closing_axis: tuple[float, float, float]
    approach_axis: tuple[float, float, float]
    tip_reach: float = 0.0
    closed_point: tuple[float, float, float] | None = None
    closed_clearance: float = 0.0


@dataclass(frozen=True)
class TableTopLayout:
    """Where a robot, its table and its workspace are (m, world frame).

    Attributes:
        reach: how far the tool gets from the shoulder (see the module doc).
        robot_pose: world pose of the robot's root ``(x, y, z, qw, qx, qy, qz)``.
        table_height: z of the table top; the workspace centre is ``(0, 0, table_height)``.
        table_center, table_half_size: the table box (a static prop from the floor up).
        rest_tcp: the default keyframe's tool position in this layout.
        gripper: the open gripper's geometry (``None`` without a gripper).
        cube_half_size: half the cube's edge.
        spawn_half_size: cubes and goals are drawn in ``[-s, s]`` of the centre.
        dof: joints of the arm that carries the end effector.
        mobile: the robot has a ``Base`` part and stands on the floor next to the table.
        pedestal: the robot stands on a pedestal of its own (its file's) on the floor next
            to the table, its tool out of reach of that floor (see the module doc).
        turning_radius: (mobile robots) the radius of the circle swept by the robot's
            geoms below the table top when the base turns in place (m); 0 otherwise.
        lowered: a tall arm stands on the floor next to a table risen to where it
            points down (see the module doc).
    """

    reach: float
    robot_pose: tuple[float, ...]
    table_height: float
    table_center: tuple[float, float, float]
    table_half_size: tuple[float, float, float]
    rest_tcp: tuple[float, float, float]
    gripper: GripperGeometry | None
    cube_half_size: float
    spawn_half_size: float
    dof: int
    mobile: bool = False
    pedestal: bool = False
    turning_radius: float = 0.0
    lowered: bool = False

    @property
    def center(self) -> FloatArray:
        """The workspace centre on the table top."""
        return np.array([0.0, 0.0, self.table_height])


_LAYOUTS: weakref.WeakKeyDictionary[type, TableTopLayout] = weakref.WeakKeyDictionary()


def robot_class(robot_uids: Any, where: str) -> type[Agent]:
    """The one robot class a table-top task takes."""
    specifier = robot_uids
    if isinstance(robot_uids, Sequence) and not isinstance(robot_uids, str):
        if len(robot_uids) != 1:
            raise ConfigError(f"{where}: expected one robot, got {robot_uids!r}.")
        specifier = robot_uids[0]
    return agent_class(specifier, where)


def tool_arm(agent: Agent, where: str) -> Arm:
    """The arm part that carries the robot's first end effector."""
    for part in agent.parts_by_name.values():
        if isinstance(part, Arm) and part.end_effectors:
            return part
    raise ConfigError(f"{where}: {type(agent).__name__} declares no end effector (an Arm part's end_effectors).")


def table_top_layout(cls: type[Agent]) -> TableTopLayout:
    """The layout of ``cls`` (see the module doc); computed once per class."""
    cached = _LAYOUTS.get(cls)
    if cached is None:
        cached = _measure_layout(cls)
        _LAYOUTS[cls] = cached
    return cached


def _measure_layout(cls: type[Agent]) -> TableTopLayout:
    where = f"table_top_layout({cls.__name__})"
    probe = Scene(cls, props=[Prop("layout_probe", "sphere", (1e-4,), mass=1e-3)])
    try:
        probe.reset()
        agent = probe.agents[0]
        arm = tool_arm(agent, where)
        model = probe.model
        data = mujoco.MjData(model)
        joints = [agent.index.joint(name, where) for name in agent.part_joints[arm.name]]
        keyframe = agent.keyframe_qpos(agent.keyframe_names()[0])
        data.qpos[:] = probe.world.qpos[0]
        data.qpos[agent.qpos_adr] = keyframe
        mujoco.mj_kinematics(model, data)
        shoulder = data.xanchor[joints[0].id].copy()
        tool = agent.frames.end_effector(None, where)
        rest_tcp = agent.kinematics.pose(data.qpos.copy(), tool)[0, :3]
        # Reach: the farthest tool position from the shoulder over sampled configurations.
        configs = random_configurations(model, agent.index, [j.name for j in joints], data.qpos, REACH_SAMPLES, where)
        tips = agent.kinematics.pose(configs, tool)[:, :3]
        reach = float(max(np.max(np.linalg.norm(tips - shoulder, axis=1)), np.linalg.norm(rest_tcp - shoulder)))
        if not reach > 1e-3:
            raise ConfigError(f"{where}: the end effector does not move away from the arm's first joint.")
        ahead = (rest_tcp - shoulder)[:2]
        yaw = -math.atan2(ahead[1], ahead[0]) if np.linalg.norm(ahead) > 0.05 * reach else 0.0
        # an arm turning on a hinge with its tool held up or stretched out: the workspace
        # centre goes UPRIGHT_AHEAD reach ahead of the shoulder, not under that tool
        off_centre = not UPRIGHT_SHARE * reach <= np.linalg.norm(ahead) <= STRETCHED_SHARE * reach
        centre_ahead = off_centre and joints[0].kind is JointKind.HINGE
        base = next((p for p in agent.parts_by_name.values() if isinstance(p, Base)), None)
        if base is not None:
            turn_joint = agent.index.joint(agent.part_joints[base.name][-1], where)
            axis = data.xanchor[turn_joint.id].copy()
            boxes = _robot_geom_boxes(agent, model, data)
        gripper = _gripper_geometry(agent, probe, data, keyframe, tool, joints[-1].id, where)
        cube_edge = CUBE_PER_OPENING * gripper.opening if gripper is not None else CUBE_PER_REACH * reach
        cube_edge = max(cube_edge, MIN_CUBE_EDGE)
        approach = gripper.approach_axis if gripper is not None else TOOL_AXIS
        spread = 2.0 * SPAWN_HALF_SIZE * reach  # from the cubes' centres up to the goals
        down: FloatArray | None = None  # tool points pointing down, measured once when needed
        # a robot standing on a pedestal of its own (its file's): its tool does not get
        # down to the heights of cubes and goals over the floor it stands on, so the table
        # top rises to where the tool works pointing down
        rise = 0.0
        lowest = float(min(np.min(tips[:, 2]), rest_tcp[2]))
        pedestal = base is None and lowest > 0.5 * cube_edge + spread
        lowered = False  # a tall arm standing on the floor next to a risen table (below)
        if pedestal:
            down = _pointing_down_points(agent, tool, joints, data.qpos, approach, model)
            rise = lowest - 0.5 * cube_edge
            if len(down) >= DOWN_MIN_POINTS:
                rise = _centred_band(down[:, 2], spread) - 0.5 * cube_edge
            # below what of the robot moves, as it rests (an arm hanging from above)
            moving = _robot_geom_boxes(agent, model, data, fixed=False)
            rise = min(rise, float(min((lo[2] for lo, _ in moving), default=np.inf)) - LOW_GEOM_MARGIN)
            boxes = _robot_geom_boxes(agent, model, data, fixed=True)
        ahead_distance = UPRIGHT_AHEAD * reach
        # a robot declaring no keyframe rests as its file draws it (every joint at zero):
        # that pose says nothing of where it works (the xArm7 file folds its tool in 0.2 m
        # from its base), so its centre goes where its tool points down (a gripper's
        # approach axis; a bare flange's or a tool's z, as the push solver takes it)
        file_rest = not cls.keyframes and joints[0].kind is JointKind.HINGE
        if base is None and ((centre_ahead and gripper is not None) or file_rest):
            if down is None:
                down = _pointing_down_points(agent, tool, joints, data.qpos, approach, model)
            band = (rise + 0.5 * cube_edge, rise + 0.5 * cube_edge + spread)  # over the table top
            middle = _middle_distance(down, shoulder, band)
            # a tool pointing down at the table top over too narrow a band of distances
            # for a push (a tall arm: the shoulder high over its mount floor), where a
            # table top risen to the median height at which it points down widens it:
            # the robot stands on the floor next to that table, as on a pedestal
            width = _band_width(down, shoulder, band)
            if not pedestal and gripper is not None and width is not None and width < NARROW_BAND * reach:
                risen = _centred_band(down[:, 2], spread) - 0.5 * cube_edge
                risen_band = (risen + 0.5 * cube_edge, risen + 0.5 * cube_edge + spread)
                risen_width = _band_width(down, shoulder, risen_band)
                # below the shoulder: the arm still stands over its table (a robosuite
                # iiwa, its first joint 0.15 m up, would have stood 5 cm into it)
                if 0.0 < risen < shoulder[2] and risen_width is not None and risen_width > width:
                    lowered, rise = True, risen
                    middle = _middle_distance(down, shoulder, risen_band)
                    boxes = _robot_geom_boxes(agent, model, data)
            if middle is not None:
                ahead_distance = middle if file_rest else min(ahead_distance, middle)
                centre_ahead = True
    finally:
        probe.close()
    turn = z_rotation_quat(yaw)
    mount = np.asarray(cls.check().mount_pose, dtype=np.float64)
    spawn = SPAWN_HALF_SIZE * reach
    # Turn the probe's world (robot at its mount pose) about z, then shift it so that the
    # workspace centre lies at the origin: a fixed robot's mount floor becomes the table
    # top; a mobile robot stays on the floor next to the table.
    rest_turned = np.empty(3)
    mujoco.mju_rotVecQuat(rest_turned, rest_tcp, turn)
    centre = rest_turned.copy()
    turning_radius = 0.0
    if base is None and centre_ahead:
        mujoco.mju_rotVecQuat(centre, shoulder, turn)
        centre[0] += ahead_distance
    fronts: list[float] = []  # of a pedestal robot's fixed geoms lower than the table top
    if pedestal or lowered:
        # the robot stands at its mount pose over the floor; the table starts clear of
        # what of it stands fixed lower than the table top (its pedestal; a lowered
        # arm's: every part of it lower than the table top as it rests), if anything
        table_height = rise
        turned = np.empty(3)
        for lo, hi in boxes:
            if lo[2] < rise + LOW_GEOM_MARGIN:
                for x, y in ((lo[0], lo[1]), (lo[0], hi[1]), (hi[0], lo[1]), (hi[0], hi[1])):
                    mujoco.mju_rotVecQuat(turned, np.array([x, y, 0.0]), turn)
                    fronts.append(float(turned[0]))
        if fronts:
            edge = max(fronts) + TABLE_CLEARANCE * reach
        shift = np.array([-centre[0], -centre[1], 0.0])
    elif base is None:
        table_height = TABLE_HEIGHT * reach
        shift = np.array([-centre[0], -centre[1], table_height])
    else:
        table_height = float(rest_turned[2]) - TOOL_ABOVE_TABLE * reach
        if not table_height >= MIN_CUBE_EDGE:
            raise ConfigError(
                f"{where}: a mobile robot's table top lies {TOOL_ABOVE_TABLE} reach ({TOOL_ABOVE_TABLE * reach:.3f} m) "
                f"below its default keyframe's tool, which is {rest_turned[2]:.3f} m above the floor; expected the "
                f"tool higher (the table top at least {MIN_CUBE_EDGE} m up)."
            )
        sweeping = [(lo, hi) for lo, hi in boxes if lo[2] < table_height + LOW_GEOM_MARGIN]
        corners = [np.array([x, y]) for lo, hi in sweeping for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]
        turning_radius = max((float(np.linalg.norm(c - axis[:2])) for c in corners), default=0.0)
        axis_turned = np.empty(3)
        mujoco.mju_rotVecQuat(axis_turned, axis, turn)
        edge = axis_turned[0] + turning_radius + TABLE_CLEARANCE * reach
    on_floor = bool(fronts) or base is not None  # standing next to the table, not over it
    if on_floor:
        # every cube drawn (turned any way) must lie on the table, clear of its near edge
        nearest_cube = edge + TABLE_CLEARANCE * reach + math.sqrt(2.0) * 0.5 * cube_edge + spawn
        centre[0] = max(centre[0], nearest_cube)
        shift = np.array([-centre[0], -centre[1], 0.0])
    root = np.empty(3)
    mujoco.mju_rotVecQuat(root, mount[:3], turn)
    root += shift
    quat = np.empty(4)
    mujoco.mju_mulQuat(quat, turn, mount[3:])
    front = 0.55 * reach
    back = edge - centre[0] if on_floor else min(root[0], 0.0) - 0.35 * reach
    return TableTopLayout(
        reach=reach,
        robot_pose=(*root.tolist(), *quat.tolist()),
        table_height=table_height,
        table_center=(0.5 * (back + front), 0.0, 0.5 * table_height),
        table_half_size=(0.5 * (front - back), 0.6 * reach, 0.5 * table_height),
        rest_tcp=(float(rest_turned[0] + shift[0]), float(rest_turned[1] + shift[1]), float(rest_turned[2] + shift[2])),
        gripper=gripper,
        cube_half_size=0.5 * cube_edge,
        spawn_half_size=spawn,
        dof=sum(j.nv for j in joints),
        mobile=base is not None,
        pedestal=pedestal,
        turning_radius=turning_radius,
        lowered=lowered,
    )


def _pointing_down_points(
    agent: Agent,
    tool: Any,
    joints: Sequence[Any],
    reference: FloatArray,
    approach: Sequence[float],
    model: mujoco.MjModel,
) -> FloatArray:
    """Tool positions ``(k, 3)`` (m, the probe scene's world: the floor the robot stands
    on, which becomes the table top, at z = 0) at which the tool points down (its
    ``approach`` axis within :data:`DOWN_TILT` of straight down) with the robot clear of
    itself and of that floor (``model``: the probe scene's; no contact deeper than
    :data:`DOWN_CONTACT_DEPTH`), over :data:`DOWN_SAMPLES` configurations drawn (fixed
    seed) within the arm joints' limits from ``reference`` (``(nq,)``). Near its base a
    small arm with a large gripper folds onto itself or onto the table to point down
    (the UR3 file with the Franka Hand: the hand against the upper arm, the elbow on
    the table)."""
    configs = random_configurations(
        agent.index.model, agent.index, [j.name for j in joints], reference, DOWN_SAMPLES, "table_top_layout", seed=1
    )
    poses = agent.kinematics.pose(configs, tool)
    axis = np.asarray(approach, dtype=np.float64)
    pointing = np.empty((DOWN_SAMPLES, 3))
    for k in range(DOWN_SAMPLES):
        mujoco.mju_rotVecQuat(pointing[k], axis, poses[k, 3:])
    chosen = -pointing[:, 2] >= math.cos(DOWN_TILT)
    robot = set(agent.index.subtree_bodies(agent.index.root_body_id))
    scratch = mujoco.MjData(model)
    for sample in np.flatnonzero(chosen).tolist():
        chosen[sample] = not _pressing(model, scratch, configs[sample], robot)
    points: FloatArray = poses[chosen, :3]
    return points


def _middle_distance(points: FloatArray, shoulder: FloatArray, band: tuple[float, float]) -> float | None:
    """The middle of the horizontal distances (m) from ``shoulder`` of the tool
    ``points`` (pointing down: :func:`_pointing_down_points`) at heights within ``band``
    (m above the floor the robot stands on); ``None`` when fewer than
    :data:`DOWN_MIN_POINTS` qualify. An arm resting upright can be too short at
    ``UPRIGHT_AHEAD`` reach to grasp pointing down: a written six-joint arm (1.14 m
    reach, a short wrist) reached at most 0.62 m ahead that way, and its centre at
    0.57 m left a third of its cubes beyond."""
    reach = _band_reach(points, shoulder, band)
    return None if reach is None else float(0.5 * (reach[0] + reach[1]))


def _band_width(points: FloatArray, shoulder: FloatArray, band: tuple[float, float]) -> float | None:
    """The spread (m) of the horizontal distances from ``shoulder`` of the tool
    ``points`` (pointing down) at heights within ``band`` (as :func:`_middle_distance`);
    ``None`` when fewer than :data:`DOWN_MIN_POINTS` qualify."""
    reach = _band_reach(points, shoulder, band)
    return None if reach is None else reach[1] - reach[0]


def _band_reach(points: FloatArray, shoulder: FloatArray, band: tuple[float, float]) -> tuple[float, float] | None:
    """The nearest and farthest horizontal distances (m) from ``shoulder`` of the tool
    ``points`` (pointing down) at heights within ``band`` (m); ``None`` when fewer than
    :data:`DOWN_MIN_POINTS` qualify."""
    within = points[(points[:, 2] >= band[0]) & (points[:, 2] <= band[1])]
    if len(within) < DOWN_MIN_POINTS:
        return None
    distance = np.linalg.norm(within[:, :2] - shoulder[:2], axis=1)
    return float(distance.min()), float(distance.max())


def _centred_band(heights: FloatArray, spread: float) -> float:
    """The lower end (m) of a band ``spread`` high centred on the median of ``heights``
    (m), raised where that puts it below the lowest of them: for an arm on a pedestal,
    with ``heights`` those at which its tool points down, the cubes' centres (the band's
    lower end: 1.39 m for a written arm on a 1.5 m pedestal, whose scripted PickCube
    succeeds 20 of 20 from 1.40 m up and 9 of 20 at 1.30 m) and the goals above them
    where it most often works that way."""
    middle = float(np.median(heights)) - 0.5 * spread
    return max(middle, float(np.min(heights)))


def _pressing(model: mujoco.MjModel, data: mujoco.MjData, qpos: FloatArray, robot: set[int]) -> bool:
    """Whether the robot at ``qpos`` touches itself or the floor (world geoms) deeper
    than :data:`DOWN_CONTACT_DEPTH` (MuJoCo's collision detection; self-collision
    filtering as the robot declares it)."""
    data.qpos[:] = qpos
    mujoco.mj_fwdPosition(model, data)
    bodies = model.geom_bodyid
    for contact in data.contact[: data.ncon]:
        first, second = int(bodies[contact.geom1]), int(bodies[contact.geom2])
        if (
            contact.dist < -DOWN_CONTACT_DEPTH
            and (first in robot or second in robot)
            and {first, second} <= robot | {0}
        ):
            return True
    return False


def _robot_geom_boxes(
    agent: Agent, model: mujoco.MjModel, data: mujoco.MjData, fixed: bool | None = None
) -> list[tuple[FloatArray, FloatArray]]:
    """World axis-aligned boxes (lower, upper corners) of the robot's colliding geoms
    in ``data``'s configuration; ``fixed``: ``True`` only those of the bodies no joint
    moves (a fixed robot's root and what is welded to it: its pedestal), ``False`` only
    the others, ``None`` all."""
    bodies = set(agent.index.subtree_bodies(agent.index.root_body_id))
    if fixed is not None:
        bodies = {b for b in bodies if (int(model.body_weldid[b]) == 0) == fixed}
    boxes = []
    for g in colliding_geoms(model, bodies):
        boxes.append(world_box(model, data, g))
    return boxes


def _jaw_closing(
    agent: Agent, gripper: Any, data: mujoco.MjData, names: Sequence[str], opened: Any, point: Any, where: str
) -> FloatArray | None:
    """For a gripper of one hinge (a jaw turning onto a fixed jaw): the closing axis as
    the jaw's motion gives it (world, unit): the way the tool point, carried by the jaw,
    moves as it closes (the hinge's axis crossed with the lever from its anchor), from
    the first finger towards the second (turned round where the jaw is the second);
    else ``None``."""
    if len(names) != 1:
        return None
    joint = agent.index.joint(names[0], where)
    if joint.kind is not JointKind.HINGE:
        return None
    _, shut = gripper.positions(1)
    sign = 1.0 if float(shut[0]) > float(opened[0]) else -1.0
    jaw = int(agent.index.model.jnt_bodyid[joint.id])
    first = {agent.index.body_id(link, where) for link in gripper.finger_links[0]}
    if jaw not in first:
        sign = -sign  # the moving jaw is the second finger: the axis runs towards it
    swept = sign * np.cross(data.xaxis[joint.id], point[:3] - data.xanchor[joint.id])
    length = float(np.linalg.norm(swept))
    return swept / length if length > 1e-9 else None


def _gripper_geometry(
    agent: Agent, probe: Scene, data: mujoco.MjData, keyframe: FloatArray, tool: Any, wrist: int, where: str
) -> GripperGeometry | None:
    """The open gripper measured at its grasp point: the nearest point of each finger's
    colliding geoms to it (MuJoCo's signed geom distances from a probe sphere there). The
    grasp point is the gripper's ``grasp_frame`` where it declares one, else the tool
    point; the results are in the tool frame."""
    parts = agent.grippers.parts
    if not parts:
        return None
    gripper = next(iter(parts.values()))
    if len(gripper.finger_links) < 2:
        return None
    model = probe.model
    qpos = keyframe.copy()
    names = agent.part_joints[gripper.name]
    opened, _ = gripper.positions(len(names))
    for name, value in zip(names, opened, strict=True):
        qpos[agent.index.joint(name, where).qpos_start] = value
    data.qpos[agent.qpos_adr] = qpos
    mujoco.mj_kinematics(model, data)
    point = np.empty(7)
    agent.kinematics.load(data.qpos.copy())
    agent.kinematics.loaded_pose(tool, point)
    measured_at = point.copy()  # the grasp frame's pose, where the gripper declares one
    if gripper.grasp_frame is not None:
        agent.kinematics.loaded_pose(agent.frames.frame(gripper.grasp_frame, where + " grasp_frame"), measured_at)
    probe_body = model.body("layout_probe")
    adr = int(model.jnt_qposadr[probe_body.jntadr[0]])
    data.qpos[adr : adr + 3] = measured_at[:3]
    mujoco.mj_kinematics(model, data)
    probe_geom = model.geom("layout_probe").id
    radius = float(model.geom_size[probe_geom, 0])
    nearest_points, gaps, finger_geoms = [], [], []
    for finger in gripper.finger_links[:2]:
        bodies = {b for link in finger for b in agent.index.subtree_bodies(agent.index.body_id(link, where))}
        geoms = colliding_geoms(model, bodies)
        if not geoms:
            return None
        finger_geoms.extend(geoms)
        best, best_point = np.inf, np.zeros(3)
        fromto = np.zeros(6)
        for g in geoms:
            distance = mujoco.mj_geomDistance(model, data, probe_geom, g, 1.0, fromto)
            if distance < best:
                best, best_point = float(distance), fromto[3:].copy()
        nearest_points.append(best_point)
        gaps.append(max(0.0, best - radius))
    opening = sum(gaps)
    if not opening > 0.0:
        return None
    # Into the tool frame: the closing axis (first finger's nearest point to the
    # second's), the approach axis (wrist joint to the point measured at), the grasp point.
    rotation = np.empty(9)
    mujoco.mju_quat2Mat(rotation, point[3:])
    to_tool = rotation.reshape(3, 3).T
    closing = to_tool @ (nearest_points[1] - nearest_points[0])
    approach = to_tool @ (measured_at[:3] - data.xanchor[wrist])
    approach /= max(float(np.linalg.norm(approach)), 1e-9)
    closing -= approach * float(closing @ approach)
    closing /= max(float(np.linalg.norm(closing)), 1e-9)
    swept = _jaw_closing(agent, gripper, data, names, opened, point, where)
    if swept is not None:  # one jaw: the axis its tip closes along, where the nearest points miss it
        swept = to_tool @ swept
        swept -= approach * float(swept @ approach)
        length = float(np.linalg.norm(swept))
        if length > 1e-9 and abs(float(closing @ swept)) < JAW_AXIS_AGREEMENT * length:
            closing = swept / length
    # the middle of the gap, on the closing axis through the point measured at
    grasp = to_tool @ (measured_at[:3] - point[:3]) + closing * 0.5 * (gaps[1] - gaps[0])
    # the fingers' farthest reach along the approach axis (their geoms' boxes), over
    # their stroke from open to closed (a linkage's pads swing out past the tool point
    # halfway: the Robotiq 2F-85's pressed on the table while closing on a cube)
    grasp_world = point[:3] + rotation.reshape(3, 3) @ grasp
    approach_world = rotation.reshape(3, 3) @ approach
    _, shut = gripper.positions(len(names))
    adrs = [agent.qpos_adr[agent.index.joint(name, where).qpos_start] for name in names]
    reach_past = 0.0
    for share in np.linspace(0.0, 1.0, TIP_REACH_SAMPLES):
        data.qpos[adrs] = opened + share * (shut - opened)
        mujoco.mj_kinematics(model, data)
        for g in finger_geoms:
            centre, axes, half = geom_box(model, data, g)
            farthest = (centre - grasp_world) @ approach_world + half @ np.abs(axes.T @ approach_world)
            reach_past = max(reach_past, float(farthest))
    # the closed fingers: each one's nearest point to the grasp point (the probe there)
    data.qpos[adrs] = shut
    data.qpos[adr : adr + 3] = grasp_world
    mujoco.mj_kinematics(model, data)
    closed_points, clearance = [], np.inf
    for finger in gripper.finger_links[:2]:
        bodies = {b for link in finger for b in agent.index.subtree_bodies(agent.index.body_id(link, where))}
        best, best_point = np.inf, np.zeros(3)
        for g in colliding_geoms(model, bodies):
            distance = mujoco.mj_geomDistance(model, data, probe_geom, g, 1.0, fromto)
            if distance < best:
                best, best_point = float(distance), fromto[3:].copy()
        closed_points.append(best_point)
        clearance = min(clearance, best - radius)
    closed_point = to_tool @ (0.5 * (closed_points[0] + closed_points[1]) - point[:3])
    data.qpos[adrs] = opened  # the gripper open again, as the caller's later measurements expect
    data.qpos[adr : adr + 3] = point[:3]
    mujoco.mj_kinematics(model, data)
    return GripperGeometry(
        opening=opening,
        grasp_point=tuple(grasp.tolist()),
        closing_axis=tuple(closing.tolist()),
        approach_axis=tuple(approach.tolist()),
        tip_reach=reach_past,
        closed_point=tuple(closed_point.tolist()),
        closed_clearance=max(0.0, clearance),
    )
