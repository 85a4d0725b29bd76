"""``DamageError``: bytes of a recording that are not what its format says they should be, in every
format (a record cut short, an index pointing nowhere, a chunk or message that cannot be decompressed)."""

from __future__ import annotations


class DamageError(Exception):
    """What is wrong (a few words, said of the place when it is known), and where: the file offset,
    None when there is none to give (a message's bytes, a decompressed chunk's). The readers catch it
    where the damage can be read past, note what was lost and read on."""

    def __init__(self, what: str, offset: int | None = None) -> None:
        super().__init__(what)
        self.what = what
        self.offset = offset
