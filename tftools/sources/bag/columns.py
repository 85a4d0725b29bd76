"""``ColumnParts``: a decoder's columns, part after part, taken as those parts or whole."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

Column = npt.NDArray[Any]


class ColumnParts:
    """Named columns, each a list of parts: every ``add`` appends one part to each column."""

    def __init__(self, names: tuple[str, ...]) -> None:
        self.names = names
        self.parts: dict[str, list[Column]] = {name: [] for name in names}

    def __len__(self) -> int:
        """How many parts each column has."""
        return len(self.parts[self.names[0]])

    def add(self, **columns: Column) -> None:
        for name in self.names:
            self.parts[name].append(columns[name])

    def take_parts(self) -> list[dict[str, Column]]:
        """Each part's columns, as added; none are left."""
        taken = [dict(zip(self.names, part, strict=True)) for part in zip(*self.parts.values(), strict=True)]
        self.parts = {name: [] for name in self.names}
        return taken

    def take_whole(self, order: npt.NDArray[np.int64]) -> dict[str, Column]:
        """Every column whole, its rows in ``order``; none are left. Column after column, each
        one's parts freed as it is taken: only one column is ever held twice."""
        return {name: self._whole(name)[order] for name in self.names}

    def _whole(self, name: str) -> Column:
        parts = self.parts.pop(name)
        self.parts[name] = []
        return parts[0] if len(parts) == 1 else np.concatenate(parts)
