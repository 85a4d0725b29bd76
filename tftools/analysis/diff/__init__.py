"""``tfx diff``'s work: two trees, each read from a recording, a tree file or a URDF, compared (``compare``: the
one definition of "differs")."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from tftools.analysis.description import described_differences, description_shape
from tftools.analysis.diff.damage import Damaged, damage_notes, damage_of
from tftools.analysis.diff.kept import kept_places
from tftools.analysis.diff.mimics import recorded_mimics
from tftools.analysis.diff.renames import renamed
from tftools.analysis.diff.subtrees import whole_subtrees
from tftools.analysis.differences import Difference, compare
from tftools.analysis.expected import Tolerances, TreeShape, shape_of
from tftools.analysis.tree_file import read_tree
from tftools.sources.errors import NoTransformsError
from tftools.sources.recording import Recording, read_recording
from tftools.sources.storage.locations import METADATA, is_url
from tftools.sources.urdf import read_urdf

#: Reads the paths of a recording (``read_recording`` by default, or one that shows progress).
Read = Callable[[Sequence[str]], Recording]


@dataclass(frozen=True)
class TreeDiff:
    """Trees ``a`` and ``b``, what differs between them beyond ``tolerances``; for each difference, what says a
    damaged recording may have made it (``damage_notes``: "" where none), and each side's damage (None: none)."""

    a: TreeShape
    b: TreeShape
    differences: list[Difference]
    tolerances: Tolerances
    notes: tuple[str, ...] = ()
    a_damaged: Damaged | None = None
    b_damaged: Damaged | None = None

    @property
    def damaged(self) -> tuple[str, str]:
        """The first problem of each side read only in part ("" for one read whole)."""
        a, b = self.a_damaged, self.b_damaged
        return (a.problem if a is not None else "", b.problem if b is not None else "")


@dataclass(frozen=True, slots=True, kw_only=True)
class DiffQuery:
    """What ``tfx diff`` asks beyond its two locations: the tolerances to compare with, each given one instead
    of the tree file's (FIRST's, else SECOND's) or the defaults (``Tolerances``); None: not given."""

    translation_mm: float | None = None
    rotation_deg: float | None = None
    rate_percent: float | None = None


def diff_trees(first: str, second: str, query: DiffQuery | None = None, *, read: Read | None = None) -> TreeDiff:
    """``tfx diff FIRST SECOND``: where the trees of two locations differ. Each is a recording (path or URL,
    read with ``read``, default ``read_recording``), a tree file (``.yaml``, ``tfx wtf --init``'s) or a URDF
    (``.urdf``: fixed joints as static edges at their origins; the frames above the robot and rates are no
    difference from it), compared with ``query``'s tolerances."""
    query = query or DiffQuery()
    read = read or read_recording
    robots = {location: read_urdf(location) for location in (first, second) if is_urdf(location)}
    (a, a_damaged), (b, b_damaged) = (
        (description_shape(robots[location]), None) if location in robots else _shape(location, read)
        for location in (first, second)
    )
    base = a.tolerances if is_tree_file(first) else b.tolerances  # a recording's are the defaults
    tolerances = overridden(base, query.translation_mm, query.rotation_deg, query.rate_percent)
    differences = whole_subtrees(renamed(kept_places(compare(a, b, tolerances), a, b, tolerances), tolerances))
    for location, other in ((first, b), (second, a)):
        if location in robots:  # the frames above a robot (odom, map) are no difference from its URDF
            differences = described_differences(differences, robots[location], other)
    notes = damage_notes(differences, a_damaged, b_damaged)
    return TreeDiff(a, b, differences, tolerances, notes, a_damaged, b_damaged)


def overridden(
    base: Tolerances,
    translation_mm: float | None = None,
    rotation_deg: float | None = None,
    rate_percent: float | None = None,
) -> Tolerances:
    """``base`` with the tolerances given (not None) instead; a ``ValueError`` for one that is no tolerance."""
    given = {"translation_mm": translation_mm, "rotation_deg": rotation_deg, "rate_percent": rate_percent}
    return dataclasses.replace(base, **{k: v for k, v in given.items() if v is not None})


def is_tree_file(location: str) -> bool:
    """A local YAML file other than a rosbag2 bag's own ``metadata.yaml``."""
    path = Path(location)
    return not is_url(location) and path.suffix in (".yaml", ".yml") and path.name != METADATA


def is_urdf(location: str) -> bool:
    return not is_url(location) and Path(location).suffix in (".urdf", ".xacro")


def _shape(location: str, read: Read) -> tuple[TreeShape, Damaged | None]:
    if is_tree_file(location):
        return read_tree(Path(location)), None
    return _recorded(lambda: read([location]), location)


def recorded_shape(read: Callable[[], Recording], source: str) -> TreeShape:
    """The shape of the recording ``read`` gives; an empty one (``TreeShape.empty`` says why) where it holds no
    transforms (read whole, without damage, none on topics not read: a --topic that missed /tf is an error), so
    that ``tfx diff`` finds it differs from a tree by every frame of that tree, and not from itself."""
    return _recorded(read, source)[0]


def _recorded(read: Callable[[], Recording], source: str) -> tuple[TreeShape, Damaged | None]:
    """``recorded_shape``, and what was damaged in the recording."""
    try:
        recording = read()
        shape = dataclasses.replace(shape_of(recording), mimics=recorded_mimics(recording))
    except NoTransformsError as error:
        if error.cause != "absent" or error.carriers:  # damaged, of a type not read, or on other topics
            raise
        return TreeShape({}, source, empty=f"no transforms on {', '.join(error.topics)}"), None
    return shape, damage_of(recording)
