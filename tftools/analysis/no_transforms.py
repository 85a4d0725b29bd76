"""The one hint of every command (``wtf``'s ``no_tf`` finding among them) for a recording whose transforms
were not read: what else to read, or why nothing was."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from tftools.sources.errors import NoTransformsError, SourceError, tf_unrecorded

if TYPE_CHECKING:
    from tftools.analysis.data_frames import DataFrames


def no_transforms_hint(error: NoTransformsError, *, chosen: bool = True) -> str:
    """What to do about ``error``, in the command line's words; ``chosen``: the command's topics can be chosen
    with --topic (not tfx filter's)."""
    from tftools.sources.contents import DEFAULT_TOPICS  # not at import: numpy's, which `tfx --help` needs not

    # what else to read: other topics, or (tfx filter, which reads only the defaults) nothing but those
    other = "pick other topics with --topic" if chosen else "tfx filter reads /tf and /tf_static only"
    hint = {
        "unread": f"convert those topics to a type and encoding tfx reads, or {other}",
        "unreadable": f"`tfx wtf` names their type and encoding; {other}",
        "absent": f"{tf_unrecorded(error.ros2)}{', or' if chosen else ';'} {other}",
    }
    if error.cause in ("absent", "unread") and error.carriers:  # the recording has transforms, on topics not read
        carriers = error.carriers[:3]
        if not chosen:
            return f"{', '.join(carriers)}: of a transform type; {other}"
        if set(carriers) <= set(DEFAULT_TOPICS):
            return f"{' and '.join(carriers)} carry transforms: leave out --topic"
        options = " ".join(f"--topic {t}" for t in carriers)
        return f"{', '.join(carriers)}: of a transform type, read with {options}"
    return hint.get(error.cause, error.hint)


#: The headers read of each topic (per publisher) to name the frames a recording without transforms has its data
#: in, where a command other than wtf (which reads them all) says it: a topic's frame rarely changes (none of the
#: corpus's 317 topics of over 100 messages names a frame first after its 100th), so the hint says nothing of it.
DATA_HEADERS = 100


def no_transforms_data(error: NoTransformsError) -> DataFrames:
    """What the data of a recording without any transform (``error``'s, not one whose transforms are on other
    topics) says of the tree it needs, read again with the first ``DATA_HEADERS`` headers of each topic (a
    topic's frames as wtf, which reads them all, names them, but for one first sent later), so that every
    command says what wtf's ``no_tf`` does; nothing for a recording not on this machine or not read again."""
    # not at import: the readers, which `tfx --help` needs not
    from tftools.analysis.data_frames import DataFrames, data_frames
    from tftools.analysis.reading import Reading

    if error.cause not in ("absent", "unread") or error.carriers or not all(Path(p).exists() for p in error.paths):
        return DataFrames()
    try:
        reading = Reading(topics=tuple(error.topics), headers=(), allow_empty=True, header_limit=DATA_HEADERS)
        recording = reading.read(error.paths)
    except SourceError:  # it was read once: a second failure leaves the error as it was
        return DataFrames()
    contents = recording.contents
    others = {t: kind for f in contents.files for t, kind in f.topics.items() if t not in contents.topics}
    return data_frames(recording.stamped.streams, others)
