"""``tfx static``: publish static transforms on /tf_static (latched in ROS 1, transient local in ROS 2), or add
them to a copy of a bag."""

from __future__ import annotations

import math
import shlex
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import live, options
from tftools.cli.arguments import positive_seconds
from tftools.cli.common import stdout, warn
from tftools.cli.errors import UsageError
from tftools.cli.outputs import check_output, check_replaceable
from tftools.render.escape import printable
from tftools.sources.user_files import number

if TYPE_CHECKING:  # the transforms, readers and writers load when used: --help needs none of them
    from tftools.core.transform import Transform

CONTEXT = {"ignore_unknown_options": True}  # so that negative numbers are arguments, not options


def _flag(name: str) -> object:
    return typer.Option(f"--{name}", help=f"ROS2 form: {name}.", rich_help_panel="ROS2 form")


def command(
    arguments: Annotated[
        list[str] | None,
        typer.Argument(
            help="ROS1 form: x y z yaw pitch roll FRAME CHILD, or x y z qx qy qz qw FRAME CHILD (radians, meters).",
            metavar="[X Y Z YAW PITCH ROLL | X Y Z QX QY QZ QW] FRAME CHILD",
        ),
    ] = None,
    x: Annotated[float | None, _flag("x")] = None,
    y: Annotated[float | None, _flag("y")] = None,
    z: Annotated[float | None, _flag("z")] = None,
    qx: Annotated[float | None, _flag("qx")] = None,
    qy: Annotated[float | None, _flag("qy")] = None,
    qz: Annotated[float | None, _flag("qz")] = None,
    qw: Annotated[float | None, _flag("qw")] = None,
    roll: Annotated[float | None, _flag("roll")] = None,
    pitch: Annotated[float | None, _flag("pitch")] = None,
    yaw: Annotated[float | None, _flag("yaw")] = None,
    frame_id: Annotated[str | None, _flag("frame-id")] = None,
    child_frame_id: Annotated[str | None, _flag("child-frame-id")] = None,
    degrees: Annotated[
        bool, typer.Option("--deg", help="Yaw, pitch and roll (either form) are in degrees, not radians.")
    ] = False,
    from_file: Annotated[
        Path | None,
        typer.Option("--from", help="A YAML file of several transforms (see tfx static --help)."),
    ] = None,
    bag: Annotated[
        str | None,
        typer.Option("--bag", "-b", help="Add the transforms to a copy of this bag (path or URL; needs -o)."),
    ] = None,
    output: Annotated[Path | None, typer.Option("--output", "-o", help="With -b: the copy to write.")] = None,
    repair: Annotated[
        bool,
        typer.Option(
            "--repair",
            help="With -b IN -o OUT: a copy whose own static transforms are complete, latched / transient local, "
            "and repeated through it (tfx wtf: static_volatile, statics_early).",
        ),
    ] = False,
    force: Annotated[
        bool,
        typer.Option("--force", help="With -o: replace an earlier output (a file or bag directory, never the input)."),
    ] = False,
    duration: Annotated[
        float | None, typer.Option(help="Stop publishing after DURATION seconds (default: Ctrl-C).")
    ] = None,
    ros1: options.Ros = None,
) -> None:
    """Publish static transforms on /tf_static, as static_transform_publisher
    does, until Ctrl-C.

    All go out in one message, as tf2_ros sends them, latched (ROS 1) or
    transient local (ROS 2): nodes that start later get them too.
    --from FILE.yaml lists several: what `rostopic echo /tf_static` or
    `ros2 topic echo /tf_static` prints, or entries like
    [cyan]{frame_id: base_link, child_frame_id: laser, x: 0.2, yaw: 3.14}[/].

    With -b IN -o OUT: a copy of the bag (ROS1 .bag, ROS2 bag directory or .mcap)
    with the transforms added on /tf_static at its start; the input bag is
    never modified. With --repair -b IN -o OUT: a copy whose own static
    transforms survive a replay (latched / transient local, complete, and
    repeated every few seconds, for playing from the middle or splitting).

    Examples: [cyan]tfx static 0.1 0 0.2 0 0 0 base_link laser[/]
    [cyan]tfx static 0.1 0 0.2 90 0 0 base_link laser --deg[/]
    [cyan]tfx static --x 0.1 --yaw 1.57 --frame-id base_link --child-frame-id laser[/]
    [cyan]tfx static --from extrinsics.yaml -b in.bag -o out.bag[/]
    [cyan]tfx static --repair -b recording/ -o repaired/[/]
    """
    from tftools.analysis.findings import counted
    from tftools.sinks.static import StaticQuery, checked, copy_with_statics, publish_static
    from tftools.sinks.static_bag import REPAIR_EVERY_S, STATIC_TOPIC
    from tftools.sources.live.static_file import read_static_transforms

    numbers = {"x": x, "y": y, "z": z, "qx": qx, "qy": qy, "qz": qz, "qw": qw, "roll": roll, "pitch": pitch, "yaw": yaw}
    if repair:
        if arguments or from_file is not None or any(v is not None for v in numbers.values()):
            raise UsageError("--repair takes no transforms: it uses the bag's own", "tfx static --repair -b IN -o OUT")
        bag, output = _copying(bag, output, force)
        copy = copy_with_statics(bag, output, StaticQuery(repair=True, force=force))
        every = f"at its start and every {REPAIR_EVERY_S:g} s"
        said = f"{counted(len(copy.transforms), 'static transform')} ({_edges(copy.transforms)}) {every}"
        stdout.print(printable(f"{copy.path}: a copy of {bag} whose {STATIC_TOPIC} is durable, with its {said}"))
        _undescribed(copy.undescribed)
        return
    transforms = read_static_transforms(from_file) if from_file is not None else []
    transforms += _given(arguments or [], numbers, frame_id, child_frame_id, degrees)
    if not transforms:
        raise UsageError("no transform given", "e.g. tfx static 0 0 1 0 0 0 base_link laser, or --from FILE.yaml")
    given, transforms = transforms, [checked(t) for t in transforms]  # refused before any work
    if bag is not None or output is not None:
        bag, output = _copying(bag, output, force)
        copy = copy_with_statics(bag, output, StaticQuery(tuple(given), force=force))
        added = f"{counted(len(copy.transforms), 'static transform')} added on {STATIC_TOPIC}"
        stdout.print(printable(f"{copy.path}: a copy of {bag} with {added}"))
        _undescribed(copy.undescribed)
        return
    if duration is not None:
        positive_seconds(duration, "--duration", "10")
    until = f"for {duration:g} s" if duration is not None else "until Ctrl-C"

    def started(where: str) -> None:
        live.say(f"publishing {_edges(transforms)} on {STATIC_TOPIC} to {where} {until}")

    publish_static(given, live.ros_name(ros1), duration, on_notice=warn, on_start=started)


def _undescribed(types: Sequence[str]) -> None:
    """Say, in one line, the types whose messages the copy holds without a definition, and what a reader needs."""
    if types:
        warn(
            f"the copy holds no definition of {', '.join(types)}, as its recording held none and tfx knows none: "
            "their messages are copied as recorded; to decode them, a reader needs their packages' .msg files "
            "(sourced in ROS 2, or given to rosbags' type store)"
        )


def _given(
    arguments: list[str], numbers: dict[str, float | None], frame: str | None, child: str | None, degrees: bool
) -> list[Transform]:
    """The transform of the positional arguments or of the flags (None of either: none); with
    ``degrees``, their yaw, pitch and roll are in degrees."""
    from tftools.sinks.static import static_transform

    flags_used = any(v is not None for v in numbers.values()) or frame is not None or child is not None
    if arguments and flags_used:
        raise UsageError("give the positional form or the --x ... --frame-id form, not both", "tfx static --help")
    rpy_used = len(arguments) in (8, 9) and _is_number(arguments[5]) and not _is_number(arguments[6])
    rpy_used = rpy_used or (flags_used and not any(numbers[k] is not None for k in ("qx", "qy", "qz", "qw")))
    if degrees and not rpy_used:
        raise UsageError("--deg is for yaw, pitch and roll", "e.g. tfx static 0 0 1 90 0 0 base_link laser --deg")
    if arguments:
        _not_a_recording(arguments)
        return [_positional(arguments, degrees)]
    if not flags_used:
        return []
    if frame is None or child is None:
        raise UsageError("--frame-id and --child-frame-id are both needed", "e.g. --frame-id map --child-frame-id odom")
    value = {k: (v if v is not None else 0.0) for k, v in numbers.items()}
    translation = [value["x"], value["y"], value["z"]]
    if any(numbers[k] is not None for k in ("qx", "qy", "qz", "qw")):
        if any(numbers[k] is not None for k in ("roll", "pitch", "yaw")):
            raise UsageError("give a quaternion or roll/pitch/yaw, not both", "--qx .. --qw or --roll --pitch --yaw")
        qw_given = numbers["qw"] if numbers["qw"] is not None else 1.0
        return [static_transform([*translation, value["qx"], value["qy"], value["qz"], qw_given], frame, child)]
    angles = [value["yaw"], value["pitch"], value["roll"]]
    _say_if_degrees_were_meant(dict(zip(("yaw", "pitch", "roll"), angles, strict=True)), degrees)
    return [static_transform([*translation, *angles], frame, child, degrees=degrees)]


def _not_a_recording(arguments: list[str]) -> None:
    """``tfx static robot.bag``: a recording where the transform's numbers go, refused with what reads its statics."""
    from tftools.sources.storage.locations import names_a_recording

    bags = [a for a in arguments if names_a_recording(a)]
    if bags:
        bag = shlex.quote(bags[0])
        raise UsageError(
            f"{bags[0]} is a recording: tfx static publishes the transform its numbers give (x y z yaw pitch roll "
            "frame child)",
            f"to see the recording's static transforms: tfx frames {bag} (or tfx wtf {bag}, which checks them); to "
            f"make them survive a replay: tfx static --repair -b {bag} -o OUT",
        )


def _positional(arguments: list[str], degrees: bool = False) -> Transform:
    """static_transform_publisher's positional forms; tf1's trailing period is accepted and ignored."""
    from tftools.analysis.findings import counted
    from tftools.sinks.static import static_transform

    with_period = len(arguments) == 10 or (len(arguments) == 9 and not _is_number(arguments[6]))
    if with_period and _is_number(arguments[-1]):
        warn("the period (tf1's last argument) is not needed: /tf_static keeps them for late subscribers")
        arguments = arguments[:-1]
    if len(arguments) not in (8, 9):
        raise UsageError(
            f"{counted(len(arguments), 'argument')}: expected 8 (x y z yaw pitch roll frame child) "
            "or 9 (x y z qx qy qz qw frame child)",
            "tfx static --help",
        )
    *values, frame, child = arguments
    numbers = [_number(v) for v in values]
    if len(numbers) == 6:
        _say_if_degrees_were_meant(dict(zip(("yaw", "pitch", "roll"), numbers[3:], strict=True)), degrees)
    return static_transform(numbers, frame, child, degrees=degrees)


def _say_if_degrees_were_meant(angles: dict[str, float], degrees: bool) -> None:
    """ROS's tools take angles in radians: an angle past a whole turn (yaw 90) was almost surely meant in
    degrees. Taken as given, as the ROS tool would, with a warning that says so."""
    turned = [f"{name} {value:g}" for name, value in angles.items() if abs(value) > 2 * math.pi]
    if turned and not degrees:
        warn(
            f"{', '.join(turned)} taken in radians, as static_transform_publisher takes it (more than a whole "
            "turn): add --deg if you meant degrees"
        )


def _is_number(text: str) -> bool:
    try:
        number(text)
    except ValueError:
        return False
    return True


def _number(text: str) -> float:
    try:
        return number(text)
    except ValueError as error:
        raise UsageError(str(error), "x y z and angles in meters and radians, e.g. 0.1 or -1.57") from None


def _copying(bag: str | None, output: Path | None, force: bool) -> tuple[str, Path]:
    """-b IN -o OUT checked before any work."""
    from tftools.sinks.static import copyable

    if bag is None or output is None:
        raise UsageError("-b BAG and -o OUTPUT go together", "e.g. tfx static ... -b in.bag -o out.bag")
    check_output(output, [bag])
    copyable(bag)
    check_replaceable(output, force)
    return bag, output


def _edges(transforms: Sequence[Transform]) -> str:
    return ", ".join(f"{t.frame_id} -> {t.child_frame_id}" for t in transforms)
