"""The one hint of every command (``wtf``'s ``no_tf`` finding among them) for a recording whose transforms
were not read: what else to read, or why nothing was."""

from __future__ import annotations

from tftools.sources.errors import NoTransformsError, tf_unrecorded


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
