"""Checks against the expected tree (``tfx wtf --expect tree.yaml``): frames missing or new, other
parents, static edges moved, edges slower, other publishers; each a ``Difference`` of ``analysis.differences``."""

from __future__ import annotations

from collections.abc import Iterator

from tftools.analysis.differences import Change, Difference, compare, describe
from tftools.analysis.expected import shape_of
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene

HERE = "this recording"
#: Differences of one kind said one by one; beyond, one finding counts the rest and names a few (a tree
#: file of 100,000 frames against another recording made 20 MB of output, a finding per frame).
SHOWN = 10
NAMED = 5


def _differences(scene: Scene, change: Change) -> Iterator[Difference]:
    expected = scene.expected
    if expected is None:
        return
    found = scene.shared(
        "expected", lambda: compare(expected, shape_of(scene.recording, scene.tree), expected.tolerances)
    )
    yield from (d for d in found if d.change is change)


def _finding(scene: Scene, d: Difference, severity: Severity, code: str, hint: str) -> Finding:
    shape = d.after or d.before
    assert shape is not None and scene.expected is not None
    parent = (d.before or shape).parent
    return Finding(
        severity,
        code,
        describe(d, scene.expected.source, HERE),
        hint,
        frames=(parent, d.frame) if parent is not None else (d.frame,),
        authorities=tuple(shape.publishers or ()),
    )


def _counted(findings: Iterator[Finding], title: str) -> Iterator[Finding]:
    """The first ``SHOWN`` of ``findings`` (of one check), then one that counts the rest and names a few."""
    rest: list[Finding] = []
    for n, finding in enumerate(findings):
        if n < SHOWN:
            yield finding
        else:
            rest.append(finding)
    if rest:
        named = [f.frames[-1] for f in rest[:NAMED]]
        more = f", and {len(rest) - NAMED:,} others" if len(rest) > NAMED else ""
        yield Finding(
            min((f.severity for f in rest), key=lambda s: s.rank),  # the gravest
            rest[0].code,
            f"{len(rest):,} more frames as above ({title}): {', '.join(named)}{more}",
            rest[0].hint,
            frames=tuple(named),
        )


def _differences_as(code: str, severity: Severity, title: str, changes: tuple[Change, ...], hint: str) -> None:
    """Register the check ``code``: each difference of one of ``changes``, a finding with ``hint`` (the
    first ``SHOWN``, then one for the rest)."""

    def run(scene: Scene) -> Iterator[Finding]:
        found = (_finding(scene, d, severity, code, hint) for change in changes for d in _differences(scene, change))
        yield from _counted(found, title)

    register(code, severity, title)(run)


_differences_as(
    "expect_missing",
    Severity.error,
    "a frame of the expected tree is missing",
    (Change.lost,),
    "did its publisher run, and was its topic recorded? (or remove the frame from the expected tree)",
)
_differences_as(
    "expect_new",
    Severity.warning,
    "a frame the expected tree does not have",
    (Change.added,),
    "a new sensor or a misnamed frame? add it to the expected tree if it belongs there",
)
_differences_as(
    "expect_parent",
    Severity.error,
    "a frame under another parent than expected",
    (Change.reparented,),
    "check which node publishes this frame and its parent's name (URDF, launch files)",
)
_differences_as(
    "expect_static",
    Severity.error,
    "a static edge moved beyond the tolerance, or static no longer",
    (Change.static, Change.moved, Change.reordered),
    "recalibrated on purpose? update the expected tree (tfx wtf --init); else check the URDF, the calibration "
    "files and static_transform_publisher arguments, or widen the tolerance (tfx wtf --expect FILE --tolerance-mm 2)",
)


@register("expect_rate", Severity.warning, "an edge slower than expected")
def expect_rate(scene: Scene) -> Iterator[Finding]:
    return _counted(_rates(scene), "an edge slower or faster than expected")


def _rates(scene: Scene) -> Iterator[Finding]:
    for d in _differences(scene, Change.rate):
        slower = d.rate_change is not None and d.rate_change < 0  # None: the expected edge had no rate
        hint = (
            "an overloaded node or a throttled publisher? compare tfx monitor's rates, or widen the tolerance "
            "(tfx wtf --expect FILE --tolerance-rate 25)"
            if slower
            else "faster than expected: harmless for lookups; update the expected tree if it is the new normal"
        )
        yield _finding(scene, d, Severity.warning if slower else Severity.info, "expect_rate", hint)


_differences_as(
    "expect_publishers",
    Severity.info,
    "an edge published by other nodes than expected",
    (Change.publishers,),
    "a renamed or replaced node: update the expected tree if it is intended",
)
