"""``FrameTable``: frame names interned as integer ids, in tf2's order."""

from __future__ import annotations

#: Id 0 is tf2's "no parent": a frame's parent is never 0.
NO_PARENT = 0


class FrameTable:
    """Names to ids and back. Ids start at 1 and follow first insertion, as tf2's do."""

    def __init__(self) -> None:
        self._ids: dict[str, int] = {}
        self.names: list[str] = ["NO_PARENT"]

    def __contains__(self, name: object) -> bool:
        return name in self._ids

    def get(self, name: str) -> int:
        """The id of ``name``, or ``NO_PARENT`` if unknown."""
        return self._ids.get(name, NO_PARENT)

    def intern(self, name: str) -> int:
        frame_id = self._ids.get(name)
        if frame_id is None:
            frame_id = self._ids[name] = len(self.names)
            self.names.append(name)
        return frame_id
