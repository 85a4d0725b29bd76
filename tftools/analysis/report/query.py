"""``ReportQuery``: what ``tfx report`` asks of a recording, as one value (``report(recording, query)``)."""

from __future__ import annotations

from dataclasses import dataclass

from tftools.analysis.reading import Reading
from tftools.analysis.wtf.query import CheckQuery
from tftools.core.semantics import Semantics
from tftools.sources.urdf import RobotDescription


@dataclass(frozen=True, slots=True, kw_only=True)
class ReportQuery:
    """What to show of a recording, as ``tfx report``'s defaults have it: its tf ``topics`` (None: /tf and
    /tf_static) under tf2's ``semantics`` (None: the recording's own); its sensor data (``sensor_topics``;
    None: every topic with a header in a bag, none live) checked in ``target`` (None: ``choose_target``'s);
    against the robot's description (``urdf``, else a recorded /robot_description)."""

    topics: tuple[str, ...] | None = None
    semantics: Semantics | None = None
    target: str | None = None
    sensor_topics: tuple[str, ...] | None = None
    urdf: RobotDescription | None = None

    def checks(self) -> CheckQuery:
        """``tfx wtf``'s query of the same checks as the page's findings."""
        return CheckQuery(
            topics=self.topics,
            semantics=self.semantics,
            target=self.target,
            sensor_topics=self.sensor_topics,
            urdf=self.urdf,
        )

    def reading(self) -> Reading:
        """What to read of a recording file for it: even one without transforms is reported (its page says so,
        with ``tfx wtf``'s ``no_tf`` finding and what the recording holds)."""
        return self.checks().reading()


#: ``tfx report``'s defaults.
REPORT_DEFAULTS = ReportQuery()
