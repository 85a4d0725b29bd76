"""``tfx echo`` output: tf_echo's text, JSON Lines, CSV, or lines to paste: static_transform_publisher's
command lines, a URDF joint, an entry of ``tfx static --from``."""

from __future__ import annotations

import csv
import json
import math
import shlex
from collections.abc import Iterable, Iterator
from typing import IO, Any
from xml.sax.saxutils import quoteattr

from tftools.analysis.echo import EchoSeries
from tftools.core.rotation import rpy_rebuilding
from tftools.core.time import format_sec, to_sec
from tftools.core.transform import Transform
from tftools.render import jsonl
from tftools.render.escape import printable

CSV_COLUMNS = (
    "time", "stamp_ns", "frame_id", "child_frame_id", "x", "y", "z",
    "qx", "qy", "qz", "qw", "roll", "pitch", "yaw", "error",
)  # fmt: skip


def write_text(series: EchoSeries, out: IO[str], precision: int = 3, matrix: bool = False) -> None:
    """What tf_echo prints for each time: the transform, or the failure and tf2's reason."""
    for row in _lookups(series, out):
        t, q, rpy = series.translations[row], series.rotations[row], series.rpy[row]
        deg = [math.degrees(a) for a in rpy]

        def shown(values: Iterable[float]) -> str:
            return ", ".join(fixed(float(v), precision) for v in values)

        out.write(f"At time {to_sec(int(series.stamps[row])):.{precision}f}\n")
        out.write(f"- Translation: [{shown(t)}]\n")
        out.write(f"- Rotation: in Quaternion [{shown(q)}]\n")
        out.write(f"            in RPY (radian) [{shown(rpy)}]\n")
        out.write(f"            in RPY (degree) [{shown(deg)}]\n")
        if matrix:
            m = Transform(tuple(t), tuple(q)).as_matrix()
            out.write("- Matrix:\n")
            for line in m:
                out.write("  " + " ".join(fixed(float(v), precision) for v in line) + "\n")


#: Beyond this, a number in fixed notation is a screenful of digits (1e308 has 309): shown with an exponent.
FIXED_LIMIT = 1e15


def fixed(value: float, precision: int) -> str:
    """``value`` with ``precision`` decimals as tf_echo prints it, or with an exponent past ``FIXED_LIMIT``."""
    return f"{value:.{precision}{'f' if abs(value) < FIXED_LIMIT or not math.isfinite(value) else 'e'}}"


#: How far (in units of the last place) a printed number may be from the double: the one or two ulps of
#: rounding that composing rotations leaves (0.4999999999999999 for 0.5), far below any instrument; and
#: below what a number is 0 (the 1.1e-16 m a rotation by 90 degrees leaves of an exact 0).
ULPS, ZERO = 2, 1e-15


def _exact(values: Iterable[float]) -> list[str]:
    """Each number as the shortest text of at most 15 significant digits within ``ULPS`` of it (0.5, not the
    0.4999999999999999 that composing rotations makes of it; 0.0 below ``ZERO``), else Python's shortest
    exact text."""
    return [_shortest(float(v)) for v in values]


def _shortest(value: float) -> str:
    if abs(value) < ZERO:
        return "0.0"
    for digits in range(1, 16):
        text = f"{value:.{digits}g}"
        if abs(float(text) - value) <= ULPS * math.ulp(value):
            return repr(float(text))
    return repr(value)


def write_static(series: EchoSeries, out: IO[str], ros2: bool) -> None:
    """For each lookup, the static_transform_publisher command line that publishes it, in the data's own
    ROS (as ``no_tf`` names its tools): ROS 2's (--x ... --frame-id ... --child-frame-id ...), else ROS 1's
    (x y z qx qy qz qw frame child)."""
    parent, child = printable(shlex.quote(series.target)), printable(shlex.quote(series.source))
    for row in _lookups(series, out):
        values = _exact([*series.translations[row], *series.rotations[row]])
        if ros2:
            flags = " ".join(f"--{k} {v}" for k, v in zip(("x", "y", "z", "qx", "qy", "qz", "qw"), values, strict=True))
            out.write(f"ros2 run tf2_ros static_transform_publisher {flags} ")
            out.write(f"--frame-id {parent} --child-frame-id {child}\n")
        else:
            out.write(f"rosrun tf2_ros static_transform_publisher {' '.join(values)} {parent} {child}\n")


def _lookups(series: EchoSeries, out: IO[str]) -> Iterator[int]:
    """The rows of the lookups that succeeded; for each failed one, what tf_echo prints is written."""
    for row in range(len(series)):
        if series.valid[row]:
            yield row
        else:
            out.write(f"Failure at {format_sec(int(series.times[row]))}\n")
            out.write(f"Exception thrown:{printable(str(series.errors[row]))}\n")


def write_urdf(series: EchoSeries, out: IO[str]) -> None:
    """For each lookup, a fixed URDF joint from the target link to the source link: its ``<origin>``'s
    ``rpy`` is URDF's (fixed-axis roll about x, then pitch about y, then yaw about z, radians), the angles that
    make the rotation again (not tf_echo's, which lose it at a pitch of 90 degrees)."""
    parent, child = printable(series.target), printable(series.source)
    for row in _lookups(series, out):
        qx, qy, qz, qw = (float(v) for v in series.rotations[row])
        xyz, rpy = " ".join(_exact(series.translations[row])), " ".join(_exact(rpy_rebuilding((qx, qy, qz, qw))))
        out.write(f'<joint name={quoteattr(f"{parent}_to_{child}")} type="fixed">\n')
        out.write(f"  <parent link={quoteattr(parent)}/>\n  <child link={quoteattr(child)}/>\n")
        out.write(f'  <origin xyz="{xyz}" rpy="{rpy}"/>\n</joint>\n')


def write_yaml(series: EchoSeries, out: IO[str]) -> None:
    """For each lookup, an entry of a ``tfx static --from`` file: frames, translation, quaternion."""
    parent, child = (printable(json.dumps(n, ensure_ascii=False)) for n in (series.target, series.source))
    for row in _lookups(series, out):
        translation, rotation = ", ".join(_exact(series.translations[row])), ", ".join(_exact(series.rotations[row]))
        out.write(
            f"- {{frame_id: {parent}, child_frame_id: {child}, translation: [{translation}], rotation: [{rotation}]}}\n"
        )


def _records(series: EchoSeries) -> Iterator[dict[str, Any]]:
    for row in range(len(series)):
        record: dict[str, Any] = {
            "time": to_sec(int(series.times[row])),
            "stamp_ns": int(series.stamps[row] if series.valid[row] else series.times[row]),
            "frame_id": series.target,
            "child_frame_id": series.source,
        }
        if series.valid[row]:
            record["translation"] = series.translations[row].tolist()
            record["rotation"] = series.rotations[row].tolist()
            record["rpy"] = series.rpy[row].tolist()
        else:
            error = series.errors[row]
            record["error"] = type(error).__name__
            record["message"] = str(error)
        yield record


def write_json(series: EchoSeries, out: IO[str]) -> None:
    """One JSON object per line: time, stamp_ns, frames, translation, rotation, rpy (or error)."""
    jsonl.write_lines(_records(series), out)


def write_csv(series: EchoSeries, out: IO[str]) -> None:
    """A table for spreadsheets and plotting; failed rows have only the error column filled. Names
    with control characters are escaped (``printable``); JSON keeps them exact."""
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for record in _records(series):
        values = [*record.get("translation", [""] * 3), *record.get("rotation", [""] * 4), *record.get("rpy", [""] * 3)]
        writer.writerow(
            [
                record["time"],
                record["stamp_ns"],
                printable(record["frame_id"]),
                printable(record["child_frame_id"]),
                *values,
                printable(record.get("message", "")),
            ]
        )
