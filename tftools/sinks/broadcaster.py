"""``StaticBroadcaster``: what a live system's static transform publisher offers (``tftools.sinks`` opens one)."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.core.transform import Transform
from tftools.sources.live.base import ContextManaged


class StaticBroadcaster(ContextManaged):
    """Publishes static transforms as the system's static_transform_publisher does (latched /
    transient local: subscribers that come later get them too), until ``close``: every transform
    sent so far in one message, a newer one replacing an older one of the same child frame
    (tf2_ros's StaticTransformBroadcaster::sendTransform)."""

    def __init__(self) -> None:
        self._transforms: dict[str, Transform] = {}

    @property
    def finished(self) -> bool:
        """True once the system asked it to stop."""
        raise NotImplementedError

    def describe(self) -> str:
        raise NotImplementedError

    def send(self, transforms: Sequence[Transform]) -> None:
        """Publish ``transforms`` with those sent before (raises ``LiveError`` if the system is not there)."""
        for transform in transforms:
            self._transforms[transform.child_frame_id] = transform
        self._publish(list(self._transforms.values()))

    def _publish(self, transforms: list[Transform]) -> None:
        raise NotImplementedError
