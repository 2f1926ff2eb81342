"""Writes ``src/robot_agents/robots/kscale/assets/stompy.xml`` (our primitive Stompy)
from the URDF ManiSkill 3.0.1 downloads for ``stompy``, read as data: the numbers of the
model file come from this script, not by hand.

The source: ``haosulab/ManiSkill-Stompy`` at tag v0.1.0 (``robot.urdf`` and ``meshes/``;
five meshes are absent from every mirror we could read, see the file's header). What
the script does, per body (one per moving joint, plus the root; the URDF's fixed-joint
links merged into the body they hang from, but ``link_head_1_head_1``, the head
camera's link, welded as its own body):

- the body's pose in its parent: the URDF's joint origins chained through the fixed
  joints; the joint's axis and range as the URDF's;
- the inertial: the merged links' masses, centres of mass and inertia tensors (each
  turned from its URDF inertial frame, shifted by the parallel-axis rule), as a full
  tensor;
- one box per link with a mesh: the smaller (by volume) of the mesh vertices' bounding
  box in the link frame and along their principal axes (a 20% smaller volume needed to
  take the latter); for an absent mesh, the uniform box with the link's mass and
  principal inertia.

Usage: ``python benchmarks/stompy_mjcf.py URDF_DIR`` prints the differences from the
committed file (exit status 1 if any); ``--write`` writes it. ``URDF_DIR`` holds
``robot.urdf`` and ``meshes/`` (e.g. ``git archive v0.1.0`` of the repository).
"""

from __future__ import annotations

import argparse
import difflib
import math
import struct
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "src/robot_agents/robots/kscale/assets/stompy.xml"
#: Links kept as bodies of their own, welded to their parent (a camera mounts on it).
WELDED = ("link_head_1_head_1",)
#: The root's height in the file (m): ManiSkill's ``standing`` pose.
ROOT_HEIGHT = 0.965


def rpy_matrix(rpy: list[float]) -> np.ndarray:
    """URDF rpy: Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    result: np.ndarray = rz @ ry @ rx
    return result


def origin(element: ET.Element | None) -> np.ndarray:
    """The ``(4, 4)`` transform of a URDF ``<origin>`` (identity when absent)."""
    result = np.eye(4)
    if element is not None:
        result[:3, :3] = rpy_matrix([float(v) for v in element.get("rpy", "0 0 0").split()])
        result[:3, 3] = [float(v) for v in element.get("xyz", "0 0 0").split()]
    return result


def quaternion(rotation: np.ndarray) -> np.ndarray:
    """(w, x, y, z) of a rotation matrix, w >= 0."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = np.array([0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s])
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = np.empty(4)
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q /= np.linalg.norm(q)
    return -q if q[0] < 0.0 else q


def stl_vertices(path: Path) -> np.ndarray:
    """The vertices ``(n, 3)`` of an STL file (binary or ASCII), m."""
    data = path.read_bytes()
    if data[:5] == b"solid" and b"facet" in data[:300]:
        rows = [line.split()[1:4] for line in data.decode().splitlines() if line.strip().startswith("vertex")]
        return np.array(rows, dtype=float)
    count = struct.unpack("<I", data[80:84])[0]
    facets = np.frombuffer(
        data[84 : 84 + 50 * count], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    )
    return facets["v"].reshape(-1, 3).astype(float)


def box_fit(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centre, rotation and half sizes of a box around ``vertices`` (see the module doc)."""
    low, high = vertices.min(0), vertices.max(0)
    best = ((low + high) / 2, np.eye(3), (high - low) / 2)
    centre = vertices.mean(0)
    _, axes = np.linalg.eigh(np.cov((vertices - centre).T))
    if np.linalg.det(axes) < 0:
        axes[:, 0] *= -1
    projected = (vertices - centre) @ axes
    low2, high2 = projected.min(0), projected.max(0)
    if np.prod(high2 - low2) < 0.8 * np.prod(high - low):
        best = (centre + axes @ ((low2 + high2) / 2), axes, (high2 - low2) / 2)
    return best


def inertia_box(mass: float, principal: np.ndarray) -> np.ndarray:
    """Half sizes of the uniform box with ``mass`` and principal inertia ``principal``."""
    a, b, c = principal
    squares = [6 / mass * (b + c - a), 6 / mass * (a + c - b), 6 / mass * (a + b - c)]
    return np.sqrt(np.maximum(squares, 1e-8)) / 2


def fmt(values: np.ndarray | list[float] | float, digits: int = 6) -> str:
    return " ".join(f"{float(x):.{digits}g}" if abs(x) > 1e-12 else "0" for x in np.atleast_1d(values))


@dataclass
class Body:
    name: str
    joint: ET.Element | None
    pose: np.ndarray  # in the parent body
    links: list[tuple[str, np.ndarray]] = field(default_factory=list)
    children: list[Body] = field(default_factory=list)


class Generator:
    def __init__(self, urdf_dir: Path) -> None:
        self.dir = urdf_dir
        root = ET.parse(urdf_dir / "robot.urdf").getroot()
        self.links = {link.get("name", ""): link for link in root.findall("link")}
        self.children: dict[str, list[ET.Element]] = {}
        parents = set()
        for joint in root.findall("joint"):
            self.children.setdefault(_child(joint, "parent"), []).append(joint)
            parents.add(_child(joint, "child"))
        self.root_name = next(n for n in self.links if n not in parents)
        self.absent: dict[str, np.ndarray] = {}

    def tree(self) -> Body:
        root = Body(self.root_name, None, np.eye(4))
        self._walk(self.root_name, root, np.eye(4))
        return root

    def _walk(self, link: str, body: Body, pose: np.ndarray) -> None:
        body.links.append((link, pose))
        for joint in self.children.get(link, []):
            child, offset = _child(joint, "child"), pose @ origin(joint.find("origin"))
            if joint.get("type") == "fixed" and child not in WELDED:
                self._walk(child, body, offset)
            else:
                sub = Body(child, joint, offset)
                body.children.append(sub)
                self._walk(child, sub, np.eye(4))

    def inertial(self, body: Body) -> tuple[float, np.ndarray, np.ndarray]:
        parts = []
        for link, pose in body.links:
            element = self.links[link].find("inertial")
            if element is None:
                continue
            mass = float(_attr(element, "mass", "value"))
            frame = pose @ origin(element.find("origin"))
            i = {k: float(_attr(element, "inertia", k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
            tensor = np.array(
                [[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]]
            )
            parts.append((mass, frame[:3, 3], frame[:3, :3] @ tensor @ frame[:3, :3].T))
        total = sum(p[0] for p in parts)
        centre = sum(p[0] * p[1] for p in parts) / total
        inertia = np.zeros((3, 3))
        for mass, position, tensor in parts:
            d = position - centre
            inertia += tensor + mass * (d @ d * np.eye(3) - np.outer(d, d))
        return total, centre, inertia

    def geoms(self, body: Body) -> list[str]:
        lines = []
        for link, pose in body.links:
            element = self.links[link].find("collision")
            mesh = None if element is None else element.find("geometry/mesh")
            if element is None or mesh is None:
                continue
            path = self.dir / mesh.get("filename", "")
            if path.exists():
                mesh_pose = origin(element.find("origin"))
                vertices = stl_vertices(path) @ mesh_pose[:3, :3].T + mesh_pose[:3, 3]
                centre, rotation, half = box_fit(vertices)
            else:
                inertial = self.links[link].find("inertial")
                if inertial is None:
                    continue
                frame = origin(inertial.find("origin"))
                i = {k: float(_attr(inertial, "inertia", k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
                tensor = np.array(
                    [[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]]
                )
                principal, axes = np.linalg.eigh(tensor)
                if np.linalg.det(axes) < 0:
                    axes[:, 0] *= -1
                rotation, centre = frame[:3, :3] @ axes, frame[:3, 3]
                half = inertia_box(float(_attr(inertial, "mass", "value")), principal)
                self.absent[link] = 2 * half
            position, turned = pose[:3, :3] @ centre + pose[:3, 3], pose[:3, :3] @ rotation
            color = self.links[link].find("visual/material/color")
            rgba = "0.6 0.6 0.6 1" if color is None else color.get("rgba", "0.6 0.6 0.6 1")
            lines.append(
                f'<geom name="{link.removeprefix("link_")}" type="box" size="{fmt(np.maximum(half, 0.001), 4)}" '
                f'pos="{fmt(position, 5)}" quat="{fmt(quaternion(turned))}" rgba="{rgba}"/>'
            )
        return lines

    def body_lines(self, body: Body, depth: int) -> list[str]:
        pad = "  " * depth
        if body.joint is None:
            out = [
                f'{pad}<body name="{body.name}" childclass="stompy" pos="0 0 {ROOT_HEIGHT}">',
                f'{pad}  <freejoint name="root"/>',
            ]
        else:
            out = [
                f'{pad}<body name="{body.name}" pos="{fmt(body.pose[:3, 3])}" quat="{fmt(quaternion(body.pose[:3, :3]))}">'
            ]
        mass, centre, inertia = self.inertial(body)
        full = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
        out.append(f'{pad}  <inertial pos="{fmt(centre)}" mass="{mass:.6g}" fullinertia="{fmt(full)}"/>')
        joint = body.joint
        if joint is not None and joint.get("type") != "fixed":
            kind = "slide" if joint.get("type") == "prismatic" else "hinge"
            limit = joint.find("limit")
            low, high = ("0", "0") if limit is None else (limit.get("lower", "0"), limit.get("upper", "0"))
            out.append(
                f'{pad}  <joint name="{joint.get("name")}" type="{kind}" axis="{_attr(joint, "axis", "xyz")}" '
                f'range="{low} {high}"/>'
            )
        out += [f"{pad}  {line}" for line in self.geoms(body)]
        for child in body.children:
            out += self.body_lines(child, depth + 1)
        out.append(f"{pad}</body>")
        return out

    def document(self) -> str:
        body = "\n".join(self.body_lines(self.tree(), 2))
        absent = "\n".join(
            f"      {link.removeprefix('link_')}: {' x '.join(f'{v:.3f}' for v in size)} m"
            for link, size in self.absent.items()
        )
        return HEADER.format(absent=absent) + body + FOOTER


def _child(element: ET.Element, tag: str) -> str:
    found = element.find(tag)
    return "" if found is None else found.get("link", "")


def _attr(element: ET.Element, tag: str, name: str) -> str:
    found = element.find(tag)
    if found is None or found.get(name) is None:
        raise ValueError(f"stompy_mjcf: <{tag} {name}> missing in {element.get('name')!r}")
    return str(found.get(name))


HEADER = """<!--
  K-Scale Labs' Stompy humanoid (37 joints on a free torso), primitive shapes only.
  Generated by benchmarks/stompy_mjcf.py (see there how each number is derived).

  Source, read as data: haosulab/ManiSkill-Stompy robot.urdf, tag v0.1.0 (commit
  f7cd030c42a1b68b5aa211beec5d5ba948656296; what ManiSkill 3.0.1 downloads for uid
  "stompy"), K-Scale Labs' Onshape export (MIT licence), 151 links and 150 joints.
  How the numbers here come from it:
  - Bodies: one per moving joint (37) plus the root; the URDF's fixed-joint links are
    merged into the body they hang from, but link_head_1_head_1 (welded, its
    own body: ManiSkill's head camera is mounted on it). Body and joint names are the URDF's (the body
    is the moving joint's child link). Body positions and orientations are the URDF's
    joint origins chained through the fixed joints; axes and ranges are the URDF's.
    Forward kinematics checked against SAPIEN loading the URDF (ManiSkill's own loader)
    at ManiSkill's "standing" keyframe: every body within 1e-6 m and 1e-6 in quaternion
    (tests/test_stompy.py chains the URDF's origins independently).
  - Inertials: per body, the merged links' masses, centres of mass and inertia tensors
    (each turned from its URDF inertial frame, parallel-axis shifted), as a full tensor.
    Total 27.601 kg. The four inertials v0.1.0 comments out (two calf pulleys, 5.6 g, and
    two hand camera mounts, 3.3 g: degenerate tensors) are left out as there.
  - Geoms: one box per URDF link with a mesh, in that link's frame: the smaller of the
    mesh's bounding box in the link frame and its principal-axes bounding box (our fit of
    the STL vertices; no mesh is copied). Five meshes are absent from the archived repo
    (their blobs are not in any mirror we can read); their boxes are the uniform boxes
    with the link's URDF mass and principal inertia (an estimate of their size):
{absent}
    Every box is drawn and collides (the robot does not collide with itself: the agent
    sets disable_self_collisions, as ManiSkill's); colours are the URDF's materials.
  - The URDF gives no joint damping, friction or armature; the drives (stompy.py) add
    what they declare.
-->
<mujoco model="stompy">
  <compiler angle="radian" autolimits="true"/>

  <default>
    <default class="stompy">
      <geom type="box" density="0" group="2"/>
    </default>
  </default>

  <worldbody>
"""
FOOTER = """
  </worldbody>
</mujoco>
"""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    parser.add_argument("urdf_dir", type=Path, help="folder holding robot.urdf and meshes/")
    parser.add_argument("--write", action="store_true", help=f"write {OUT.name} (default: show differences)")
    args = parser.parse_args(argv)
    text = Generator(args.urdf_dir).document()
    if args.write:
        OUT.write_text(text)
        print(f"wrote {OUT}")
        return 0
    diff = list(
        difflib.unified_diff(OUT.read_text().splitlines(), text.splitlines(), "committed", "generated", lineterm="")
    )
    print("\n".join(diff) if diff else f"{OUT.name} is as generated")
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main())
