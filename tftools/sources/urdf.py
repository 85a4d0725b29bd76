"""A robot's description (URDF) read within limits: its links, and its joints with their origins and axes.

The standard library's XML parser (expat) reads it, within metadata.yaml's limits on size, nesting and
element count (``sources.user_files``), with a document type declaration refused as soon as expat meets
it, after decoding and whatever the encoding: no entity is ever declared or expanded. A URDF is a plain
XML file of a few elements, and only a small part of it (``<link name>``, ``<joint>``'s type, parent,
child, origin, axis and mimic) says where frames are: no library would read that part better, and none
is needed. xacro is not expanded (it runs Python-like macros): a xacro file is refused with the command
that expands it.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass, replace
from functools import cached_property
from xml.parsers import expat

from tftools.core.errors import TfToolsError
from tftools.core.rotation import Quat, Vec3, matrix_apply, matrix_from_quat, quat_from_rpy
from tftools.sources.codecs.wire import MAX_FRAME_ID
from tftools.sources.user_files import MAX_BYTES, MAX_DEPTH, MAX_NODES, NotAFileError, UserFileError, number, read_bytes

#: xacro's namespace as xacro files spell it (``xmlns:xacro``), as a tag's prefix.
XACRO_NAMESPACES = ("{http://www.ros.org/wiki/xacro}", "{http://ros.org/wiki/xacro}")
#: Joints whose child moves with a joint state; a fixed joint's transform never changes.
MOVING_TYPES = frozenset({"revolute", "continuous", "prismatic"})
#: Joints whose child robot_state_publisher cannot place (several degrees of freedom, no single position).
FREE_TYPES = frozenset({"floating", "planar"})
JOINT_TYPES = MOVING_TYPES | FREE_TYPES | {"fixed"}


class UrdfError(TfToolsError):
    """A description that cannot be used: the message says what is wrong, ``hint`` what to do."""

    def __init__(self, source: str, problem: str, hint: str = "give a URDF file (xacro's output), or fix it") -> None:
        super().__init__(f"{source}: {problem}")
        self.hint = hint


@dataclass(frozen=True)
class Joint:
    """One joint: ``parent`` link -> ``child`` link, at ``origin`` (xyz, rpy) when its position is 0."""

    name: str
    type: str  # fixed, revolute, continuous, prismatic, floating, planar
    parent: str
    child: str
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)
    axis: Vec3 = (1.0, 0.0, 0.0)
    mimic: tuple[str, float, float] | None = None  # (joint, multiplier, offset)

    @property
    def moving(self) -> bool:
        return self.type in MOVING_TYPES

    @property
    def rotation(self) -> Quat:
        return quat_from_rpy(*self.rpy)

    def transform_at(self, position: float) -> tuple[Vec3, Quat]:
        """parent -> child (translation, quaternion) at joint ``position`` (radians or metres), as
        robot_state_publisher computes it (KDL): the origin, then the motion along or about the axis, made
        a unit vector."""
        rotation = self.rotation
        norm = math.hypot(*self.axis) or 1.0
        x, y, z = (a / norm for a in self.axis)
        if self.type == "prismatic":
            shift = matrix_apply(matrix_from_quat(rotation), (x * position, y * position, z * position))
            return (self.xyz[0] + shift[0], self.xyz[1] + shift[1], self.xyz[2] + shift[2]), rotation
        if self.type in ("revolute", "continuous"):
            s = math.sin(position / 2)
            return self.xyz, _multiply(rotation, (x * s, y * s, z * s, math.cos(position / 2)))
        return self.xyz, rotation


@dataclass(frozen=True)
class RobotDescription:
    """A URDF's robot: its ``name``, ``links`` in file order, ``joints`` in file order; ``source`` says
    where it came from (a path, or a recorded topic)."""

    name: str
    source: str
    links: tuple[str, ...]
    joints: tuple[Joint, ...]

    def joint_of(self, child: str) -> Joint | None:
        """The joint whose child is the link ``child`` (None for the root)."""
        return self._by_child.get(child)

    def joint(self, name: str) -> Joint:
        """The joint named ``name``."""
        return self._by_name[name]

    @cached_property
    def _by_child(self) -> dict[str, Joint]:
        return {j.child: j for j in self.joints}

    @cached_property
    def _by_name(self) -> dict[str, Joint]:
        return {j.name: j for j in self.joints}


def with_prefix(description: RobotDescription, prefix: str) -> RobotDescription:
    """``description`` with every link named ``prefix + link``, as robot_state_publisher's ``frame_prefix``
    (ROS 2) or ``tf_prefix`` (ROS 1) publishes them; joints keep their names (joint states use them)."""
    if not prefix:
        return description
    joints = tuple(replace(j, parent=prefix + j.parent, child=prefix + j.child) for j in description.joints)
    return RobotDescription(description.name, description.source, tuple(prefix + k for k in description.links), joints)


def _multiply(a: Quat, b: Quat) -> Quat:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def read_urdf(path: str | os.PathLike[str]) -> RobotDescription:
    """The robot described in the URDF file at ``path``; ``UrdfError`` says what is wrong with it."""
    name = str(path)
    try:
        raw = read_bytes(path, MAX_BYTES)
    except NotAFileError as e:
        raise UrdfError(name, str(e), f"{e.hint} (a URDF file, e.g. xacro robot.urdf.xacro > robot.urdf)") from None
    except UserFileError as e:
        raise UrdfError(name, str(e), "check that the file is readable") from None
    if name.endswith(".xacro"):
        raise _xacro(name)
    return parse_urdf(raw, name)


def _xacro(source: str) -> UrdfError:
    return UrdfError(
        source,
        "is xacro, which tfx does not expand",
        f"expand it first, then give its output: xacro {source if source.endswith('.xacro') else 'robot.urdf.xacro'}"
        " > robot.urdf",
    )


def parse_urdf(text: bytes | str, source: str) -> RobotDescription:
    """The robot described by URDF ``text`` (said to come from ``source``), read within the limits."""
    raw = text.encode() if isinstance(text, str) else text
    if len(raw) > MAX_BYTES:
        raise UrdfError(source, f"larger than {MAX_BYTES >> 20} MiB")
    root = _parsed(raw, source)
    if root.tag != "robot":
        raise UrdfError(source, f"its root element is <{_local(root.tag)}>, not <robot>: not a URDF")
    if any(_is_xacro(e) for e in root.iter()):
        raise _xacro(source)
    links = tuple(_name(e, "link", source) for e in root.findall("link"))
    joints = tuple(_joint(e, source) for e in root.findall("joint"))
    known = set(links)
    for j in joints:
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in known:
                raise UrdfError(source, f"joint {j.name}: its {role} link {link!r} is not a <link> of the robot")
    twice = next((c for c, n in Counter(j.child for j in joints).items() if n > 1), None)
    if twice is not None:
        raise UrdfError(source, f"link {twice} is the child of several joints: a URDF is a tree")
    robot = _name(root, "robot", source) if root.get("name") else ""
    return RobotDescription(robot, source, links, joints)


def _parsed(raw: bytes, source: str) -> ET.Element:
    """The document's root, built element by element by expat and stopped beyond the depth or count limits.

    Expat decides on a document type declaration after decoding, whatever the encoding (UTF-16 with or
    without a byte order mark): any declaration is refused when expat meets it, before an entity could be
    declared or expanded, while the text ``<!DOCTYPE`` inside a comment is only a comment."""
    parser = expat.ParserCreate(namespace_separator=" ")
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    builder = ET.TreeBuilder()
    depth = count = 0

    def refuse_declaration(*_: object) -> None:
        raise UrdfError(source, "has a document type declaration, which tfx does not read (URDF needs none)")

    def start(tag: str, attributes: dict[str, str]) -> None:
        nonlocal depth, count
        depth += 1
        count += 1
        if depth > MAX_DEPTH:
            raise UrdfError(source, f"nested deeper than {MAX_DEPTH} levels")
        if count > MAX_NODES:
            raise UrdfError(source, f"more than {MAX_NODES} elements")
        builder.start(_clark(tag), {_clark(k): v for k, v in attributes.items()})

    def end(tag: str) -> None:
        nonlocal depth
        depth -= 1
        builder.end(_clark(tag))

    parser.StartDoctypeDeclHandler = refuse_declaration
    parser.EntityDeclHandler = refuse_declaration
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        for at in range(0, len(raw), 1 << 16):
            parser.Parse(raw[at : at + (1 << 16)], False)
        parser.Parse(b"", True)
    except expat.ExpatError as e:
        raise UrdfError(source, f"not well-formed XML ({e})") from None
    if count == 0:
        raise UrdfError(source, "empty: not a URDF")
    return builder.close()


def _clark(name: str) -> str:
    """expat's ``uri local`` (the separator given to it) as ElementTree's ``{uri}local``."""
    uri, _, local = name.rpartition(" ")
    return f"{{{uri}}}{local}" if uri else local


def _is_xacro(element: ET.Element) -> bool:
    """An element of xacro's namespace (``xacro:macro``, ``xacro:include``), or an attribute that xacro
    would expand (``${wheel_radius}``, ``$(find pkg)``)."""
    return str(element.tag).startswith(XACRO_NAMESPACES) or any("${" in v or "$(" in v for v in element.attrib.values())


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _name(element: ET.Element, what: str, source: str, key: str = "name") -> str:
    """The ``key`` attribute of ``element`` (a ``<what>``): a name of at most ``MAX_FRAME_ID`` characters, the
    limit tf's names have wherever tfx reads them (a longer one is damage, and would swell every output)."""
    name = element.get(key)
    if not name:
        raise UrdfError(source, f"a <{what}> without a {key}")
    if len(name) > MAX_FRAME_ID:
        raise UrdfError(
            source,
            f"a <{what}> {key} of {len(name):,} characters, longer than {MAX_FRAME_ID:,}: not a frame name",
            f"names are at most {MAX_FRAME_ID:,} characters: fix the description",
        )
    return name


def _joint(element: ET.Element, source: str) -> Joint:
    name = _name(element, "joint", source)
    kind = element.get("type", "")
    if kind not in JOINT_TYPES:
        raise UrdfError(source, f"joint {name}: type {kind!r} is not one of {', '.join(sorted(JOINT_TYPES))}")
    links = []
    for role in ("parent", "child"):
        tag = element.find(role)
        if tag is None or not tag.get("link"):
            raise UrdfError(source, f"joint {name}: no <{role} link=...>")
        links.append(_name(tag, role, source, "link"))
    origin = element.find("origin")
    xyz = _vector(origin, "xyz", (0.0, 0.0, 0.0), name, source)
    rpy = _vector(origin, "rpy", (0.0, 0.0, 0.0), name, source)
    axis = _vector(element.find("axis"), "xyz", (1.0, 0.0, 0.0), name, source)
    mimic_tag = element.find("mimic")
    mimic = None
    if mimic_tag is not None and mimic_tag.get("joint"):
        _name(mimic_tag, "mimic", source, "joint")
        numbers = [
            _number(mimic_tag.get(k, d), f"joint {name}: mimic {k}", source)
            for k, d in (("multiplier", "1"), ("offset", "0"))
        ]
        mimic = (str(mimic_tag.get("joint")), numbers[0], numbers[1])
    return Joint(name, kind, links[0], links[1], xyz, rpy, axis, mimic)


def _vector(element: ET.Element | None, key: str, default: Vec3, joint: str, source: str) -> Vec3:
    if element is None or element.get(key) is None:
        return default
    parts = str(element.get(key)).split()
    if len(parts) != 3:
        raise UrdfError(source, f"joint {joint}: {key}={element.get(key)!r} is not three numbers")
    x, y, z = (_number(p, f"joint {joint}: {key}", source) for p in parts)
    return (x, y, z)


def _number(text: str, what: str, source: str) -> float:
    try:
        return number(text, what)
    except ValueError as error:
        raise UrdfError(source, str(error)) from None
