"""Compose robots and props into one MuJoCo scene.

Each robot spec is attached under a frame at its mount pose with a name prefix
(``"panda-0/"``), so several robots (even of the same kind) share one model.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import mujoco

from robot_agents.errors import ConfigError, ModelError, did_you_mean
from robot_agents.keywords import checked_keywords
from robot_agents.kinematics.rotations import look_at_xyaxes
from robot_agents.model.compiling import compile_spec
from robot_agents.model.materials import FrictionMaterial
from robot_agents.notes import mujoco_messages
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.spec import add_camera

#: The primitive shapes props (and the render frames' markers) take, by name.
PRIMITIVE_SHAPES = {
    "box": mujoco.mjtGeom.mjGEOM_BOX,
    "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
    "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
    "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE,
}


@checked_keywords
@dataclass(frozen=True)
class Prop:
    """A primitive object in the scene.

    Attributes:
        name: body name (a geom of the same name is created).
        shape: ``"box"`` (size = half extents, m), ``"sphere"`` (radius),
            ``"cylinder"`` / ``"capsule"`` (radius, half length).
        size: MuJoCo geom size (m).
        pos: initial position (m); quat: initial orientation ``(w, x, y, z)``.
        mass: kg; ``None`` makes the prop static (welded to the world).
        rgba: colour; friction: contact material (friction, and optionally contact
            softness: :class:`FrictionMaterial`).
    """

    name: str
    shape: str
    size: tuple[float, ...]
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    mass: float | None = 0.1
    rgba: tuple[float, float, float, float] = (0.8, 0.3, 0.2, 1.0)
    friction: FrictionMaterial = field(default_factory=FrictionMaterial)

    def __post_init__(self) -> None:
        if self.shape not in PRIMITIVE_SHAPES:
            raise ConfigError(
                f"Prop {self.name!r}: expected shape in {sorted(PRIMITIVE_SHAPES)}, got {self.shape!r}."
                + did_you_mean(self.shape, PRIMITIVE_SHAPES)
            )
        if self.mass is not None and not self.mass > 0:
            raise ConfigError(f"Prop {self.name!r}: expected mass > 0 kg or None (static), got {self.mass!r}.")


@dataclass(frozen=True)
class RobotMount:
    """Where a robot spec goes: its prefix and the world pose of its root."""

    prefix: str
    spec: mujoco.MjSpec
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class SceneOptions:
    """Physics options of the scene.

    Attributes:
        timestep: physics step (s), ``1 / sim_freq``.
        integrator: ``implicitfast`` integrates the actuators' velocity feedback
            implicitly, which keeps stiff PD gains stable at millisecond steps.
        floor: add a ground plane at z = 0.
        gravity: m/s^2.
        cone / impratio: MuJoCo's friction cone (``"pyramidal"`` or ``"elliptic"``) and
            the ratio of frictional to normal constraint impedance (a larger one makes
            static friction stiffer: less creep of feet or grasped objects under a
            sideways load).
        jacobian: MuJoCo's constraint Jacobian (``"auto"``: dense below 60 degrees of
            freedom, ``"dense"``, ``"sparse"``): the same physics up to rounding, at
            another cost.
        tolerance: the constraint solver's tolerance (MuJoCo's default 1e-8), which
            MuJoCo applies to the cost and gradient divided by ``meaninertia * nv``:
            a heavy robot loosens it, in absolute terms, for a light grasped body.
    """

    timestep: float = 0.002
    integrator: str = "implicitfast"
    floor: bool = True
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    cone: str = "pyramidal"
    impratio: float = 1.0
    jacobian: str = "auto"
    tolerance: float = 1e-8


#: MuJoCo's friction cones by name.
FRICTION_CONES = ("pyramidal", "elliptic")

#: MuJoCo's constraint Jacobians by name.
JACOBIANS = {
    "auto": mujoco.mjtJacobian.mjJAC_AUTO,
    "dense": mujoco.mjtJacobian.mjJAC_DENSE,
    "sparse": mujoco.mjtJacobian.mjJAC_SPARSE,
}
#: The Jacobians a robot may declare (``"auto"`` is what declaring none gives).
ROBOT_JACOBIANS = tuple(name for name in JACOBIANS if name != "auto")


#: The floor's contact (MuJoCo's ``solref``, ``solimp`` and ``solmix``): MuJoCo's
#: defaults, written out. Under a constant push ``a0`` (m/s^2) a contact settles about
#: ``(1 - d) * d * timeconst**2 * a0`` deep (``d`` the impedance, 0.95 here): a light link
#: driven at its full torque presses centimetres into this floor (docs/timestep.md,
#: "Where random actions press", has the measurements and a stiffer floor tried).
FLOOR_SOLREF = (0.02, 1.0)
FLOOR_SOLIMP = (0.9, 0.95, 0.001)
FLOOR_SOLMIX = 1.0


#: Where the scene's render camera stands and what it looks at (m, world frame).
RENDER_CAMERA_POS = (1.25, -1.0, 0.9)
RENDER_CAMERA_TARGET = (0.25, 0.0, 0.35)


def compose_scene(
    robots: Sequence[RobotMount],
    props: Sequence[Prop],
    options: SceneOptions,
    cameras: Sequence[CameraConfig] = (),
) -> mujoco.MjSpec:
    """A new scene spec with a floor, lights, a render camera, the props, the robots and
    the task's ``cameras`` (on ``"world"`` or any scene body, robot links by full name)."""
    integrators = {
        "euler": mujoco.mjtIntegrator.mjINT_EULER,
        "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
        "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
        "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    }
    if options.integrator not in integrators:
        raise ConfigError(
            f"SceneOptions.integrator: expected one of {sorted(integrators)}, got {options.integrator!r}."
        )
    if not options.timestep > 0:
        raise ConfigError(f"SceneOptions.timestep: expected a positive step in seconds, got {options.timestep!r}.")
    spec = mujoco.MjSpec()
    spec.modelname = "robot_agents_scene"
    spec.option.timestep = options.timestep
    spec.option.integrator = integrators[options.integrator]
    spec.option.gravity = list(options.gravity)
    if options.cone not in FRICTION_CONES or not options.impratio >= 1.0:
        raise ConfigError(
            f"SceneOptions: expected cone in {FRICTION_CONES} and impratio >= 1, got {options.cone!r}, {options.impratio!r}."
        )
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC if options.cone == "elliptic" else mujoco.mjtCone.mjCONE_PYRAMIDAL
    spec.option.impratio = float(options.impratio)
    if options.jacobian not in JACOBIANS:
        raise ConfigError(f"SceneOptions.jacobian: expected one of {sorted(JACOBIANS)}, got {options.jacobian!r}.")
    spec.option.jacobian = JACOBIANS[options.jacobian]
    if not 0.0 < options.tolerance < 1.0:
        raise ConfigError(f"SceneOptions.tolerance: expected a number in (0, 1), got {options.tolerance!r}.")
    spec.option.tolerance = float(options.tolerance)
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 960
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    world = spec.worldbody
    world.add_light(name="key_light", pos=[0.5, -1.0, 2.5], dir=[-0.2, 0.4, -1.0], diffuse=[0.6, 0.6, 0.6])
    if options.floor:
        spec.add_texture(
            name="grid",
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
            rgb1=[0.82, 0.84, 0.86],
            rgb2=[0.72, 0.74, 0.77],
            width=256,
            height=256,
        )
        spec.add_material(name="floor", textures=["", "grid"], texrepeat=[8, 8], reflectance=0.0)
        world.add_geom(
            name="floor",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[0, 0, 0.05],
            material="floor",
            solref=list(FLOOR_SOLREF),
            solimp=[*FLOOR_SOLIMP, 0.5, 2.0],
            solmix=FLOOR_SOLMIX,
        )
    world.add_camera(
        name="render_camera",
        pos=list(RENDER_CAMERA_POS),
        xyaxes=look_at_xyaxes(RENDER_CAMERA_POS, RENDER_CAMERA_TARGET),
        fovy=45,
    )
    for prop in props:
        _add_prop(spec, prop)
    for mount in robots:
        frame = world.add_frame(pos=list(mount.pos), quat=list(mount.quat))
        # A model file's keyframes stay out of the scene: the robot's keyframes are read
        # from its own model (its check) and the scene sets every state itself; attached,
        # MuJoCo warns that it cannot namespace them (gym_aloha's ALOHA arms, one arm kept).
        for key in list(mount.spec.keys):
            mount.spec.delete(key)
        try:
            with mujoco_messages("compose_scene"):
                frame.attach_body(mount.spec.worldbody.first_body(), mount.prefix, "")
        except ValueError as err:
            raise ModelError(f"compose_scene: attaching robot {mount.prefix!r} failed: {err}") from None
    for camera in cameras:
        add_camera(spec, camera, camera.uid, "scene cameras", allow_world=True)
    # The offscreen buffer must hold the largest camera image.
    for camera in spec.cameras:
        width, height = (int(v) for v in camera.resolution)
        spec.visual.global_.offwidth = max(spec.visual.global_.offwidth, width)
        spec.visual.global_.offheight = max(spec.visual.global_.offheight, height)
    return spec


def _add_prop(spec: mujoco.MjSpec, prop: Prop) -> None:
    body = spec.worldbody.add_body(name=prop.name, pos=list(prop.pos), quat=list(prop.quat))
    if prop.mass is not None:
        body.add_freejoint(name=f"{prop.name}_free_joint")
    geom = body.add_geom(
        name=prop.name,
        type=PRIMITIVE_SHAPES[prop.shape],
        size=list(prop.size) + [0.0] * (3 - len(prop.size)),
        rgba=list(prop.rgba),
        **({"mass": prop.mass} if prop.mass is not None else {}),
    )
    prop.friction.apply(geom)


def compile_scene(spec: mujoco.MjSpec) -> mujoco.MjModel:
    """Compile, turning MuJoCo's compiler errors into :class:`ModelError`."""
    return compile_spec(spec, "compile_scene")
