"""``CheckQuery``: what ``tfx wtf`` asks of a recording, as one value (``check(recording, query)``)."""

from __future__ import annotations

from dataclasses import dataclass

from tftools.analysis.expected import Tolerances, TreeShape
from tftools.analysis.reading import Reading
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.semantics import Semantics
from tftools.sources.bag.robot import ROBOT_TOPICS
from tftools.sources.urdf import RobotDescription


@dataclass(frozen=True, slots=True, kw_only=True)
class CheckQuery:
    """What to check of a recording, as ``tfx wtf``'s defaults have it: its tf ``topics`` (None: /tf and
    /tf_static) under tf2's ``semantics`` (None: the recording's own), within the ``thresholds``, every check
    but those ``ignore`` d (codes of ``CHECKS``); its sensor data (``sensor_topics``; None: every topic with a
    header in a bag, none live) against tf in ``target`` (None: ``choose_target``'s); against the ``expected``
    tree and the robot's description (``urdf``, else a recorded /robot_description) within
    ``urdf_tolerances`` (None: the expected tree's, else the defaults)."""

    topics: tuple[str, ...] | None = None
    semantics: Semantics | None = None
    thresholds: Thresholds | None = None
    ignore: tuple[str, ...] = ()
    target: str | None = None
    sensor_topics: tuple[str, ...] | None = None
    expected: TreeShape | None = None
    urdf: RobotDescription | None = None
    urdf_tolerances: Tolerances | None = None

    def reading(self) -> Reading:
        """What to read of a recording file for it: even one without transforms is checked (``no_tf``)."""
        headers = self.sensor_topics or ()
        return Reading(
            topics=self.topics, semantics=self.semantics, headers=headers, whole=ROBOT_TOPICS, allow_empty=True
        )

    @property
    def robot_tolerances(self) -> Tolerances | None:
        """The tolerances of the robot's description: given, or the expected tree's."""
        return self.urdf_tolerances or (self.expected.tolerances if self.expected else None)


#: ``tfx wtf``'s defaults: every check, within the default thresholds.
CHECK_DEFAULTS = CheckQuery()
