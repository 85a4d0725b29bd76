"""A ROS node's arguments given to tfx: ``rosrun tf tf_echo map base_link _precision:=5``'s private parameter,
``ros2 run tf2_ros tf2_echo map base_link --ros-args -p use_sim_time:=true``'s. tfx is no node: its options say
the same, and the usage error shows the command line with them."""

from __future__ import annotations

import re
import shlex
from collections.abc import Sequence

from tftools.cli.errors import UsageError

#: ``name:=value`` (a parameter, ROS 1's private ones with a leading ``_``) or ``from:=to`` (a remapping).
_ASSIGNMENT = re.compile(r"(_{0,2}[A-Za-z/~][\w/~.]*):=(.*)")
#: ROS 2's flags before an assignment (``-p`` a parameter, ``-r`` a remapping), dropped with it.
_ROS2_FLAGS = ("-p", "--param", "-r", "--remap")
#: tf_echo's parameters (ROS 1's ``_rate:=``, ``_precision:=``): tfx echo's options.
_ECHO_PARAMETERS = {"precision": "--precision", "rate": "--rate"}
_TRUE = ("true", "1", "yes", "on")


def refuse_ros_arguments(words: Sequence[str], options: set[str]) -> None:
    """A ``UsageError`` where ``words`` (tfx's arguments, the command first) hold a node's arguments
    (``--ros-args``, ``name:=value``), with the command line in tfx's ``options`` (the command's) where it has them."""
    if not words or not any(w == "--ros-args" or _ASSIGNMENT.fullmatch(w) for w in words[1:]):
        return
    fixed: list[str] = []
    unknown: list[str] = []
    for i, word in enumerate(words):
        found = _ASSIGNMENT.fullmatch(word) if i else None
        if word == "--ros-args" or (word in _ROS2_FLAGS and i + 1 < len(words) and _ASSIGNMENT.fullmatch(words[i + 1])):
            continue
        if found is None:
            fixed.append(word)
            continue
        option = _option(words[0], found.group(1).lstrip("_"), found.group(2), options)
        if option is None:
            unknown.append(word)
        else:
            fixed += option
    given = next(w for w in words[1:] if w == "--ros-args" or _ASSIGNMENT.fullmatch(w))
    said = f"{given}: a ROS node's argument (rosrun's _name:=value, ros2 run's --ros-args -p name:=value), not tfx's"
    if unknown:
        raise UsageError(said, f"{', '.join(unknown)}: no option of tfx {words[0]} says it; see tfx {words[0]} --help")
    raise UsageError(said, "in tfx's options: tfx " + " ".join(shlex.quote(w) for w in fixed))


def _option(command: str, name: str, value: str, options: set[str]) -> list[str] | None:
    """tfx's words for the parameter ``name:=value`` of a ROS tool, or None where ``command`` has none."""
    if name == "use_sim_time" and "--use-sim-time" in options:
        return ["--use-sim-time" if value.strip().lower() in _TRUE else "--wall-time"]
    option = _ECHO_PARAMETERS.get(name) if command == "echo" else None
    return [option, value] if option in options else None
