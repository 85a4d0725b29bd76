"""Findings that follow from another: each rule says once which finding explains which, and ``explain``
links them (``Finding.cause``), so that one root cause is said once, with what follows from it beneath."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

from tftools.analysis.detections import DETECTION
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.joint_sources import JOINT_SOURCES
from tftools.analysis.wtf.robots import robots_of
from tftools.analysis.wtf.timing import SAME_CLOCK_S


def _on_its_frames(cause: Finding, finding: Finding) -> bool:
    """A finding about frames (a joint's link) that the cause found in dispute, or about a link whose
    static transform came in the disputed message that tf2 keeps (another description's: same arrival)."""
    link = finding.frames[:-1] if finding.code == "urdf_parent" else finding.frames  # its last: the description's
    same_message = finding.code == "urdf_parent" and finding.first_time == cause.last_time != 0
    return bool(link) and (set(link) <= set(cause.frames) or same_message)


def _of_its_frame(cause: Finding, finding: Finding) -> bool:
    """A joint's finding (its parent and link) about the link the cause found sent on both tf topics, under that
    parent."""
    return finding.frames[-1:] == cause.frames[:1] and finding.frames[:1] == cause.frames[1:2]


def _same_change(first: Finding, finding: Finding) -> bool:
    """The same thing seen at the same moments on several edges (sent in one message): as many times, from
    the same time to the same time."""
    same = (first.first_time, first.last_time, first.count) == (finding.first_time, finding.last_time, finding.count)
    return same and (finding.first_time, finding.last_time) != (0, 0)


def _change(finding: Finding) -> tuple[tuple[int, int, int]]:
    """``_same_change``'s key: the moments and how many."""
    return ((finding.first_time, finding.last_time, finding.count),)


def _frames(finding: Finding) -> tuple[str, ...]:
    return finding.frames


def _shares_a_frame(first: Finding, finding: Finding) -> bool:
    """Findings naming a frame in common: one naming of the frames (a frame prefix), seen on two topics."""
    return bool(set(first.frames) & set(finding.frames))


#: ROS 1's robot_state_publisher stamps the fixed joints it sends on /tf this far (s) ahead of its clock
#: (``publishFixedTransforms``: now + 0.5 s), so they are that much further ahead than its machine's other edges.
RSP_POST_DATED_S = 0.5


def _one_clock_ahead(first: Finding, finding: Finding) -> bool:
    """Edges stamped ahead of their arrival by the same amount over the same time: one publishing machine's
    clock ahead of the recorder's (every publisher on it), not one post-dating publisher per edge; its fixed
    joints, never changing, that much and robot_state_publisher's half second further ahead (a real Guardian's
    clock 7.6 s ahead, its fixed joints 8.1 s)."""
    a, b = first.figures.get("ahead_s_median"), finding.figures.get("ahead_s_median")
    if not isinstance(a, float) or not isinstance(b, float):
        return False
    overlap = finding.first_time <= first.last_time and first.first_time <= finding.last_time
    further = finding if b > a else first
    post_dated = further.figures.get("constant") == 1.0 and abs(abs(a - b) - RSP_POST_DATED_S) <= SAME_CLOCK_S
    return overlap and (abs(a - b) <= SAME_CLOCK_S or post_dated)


def _one_clock_behind(first: Finding, finding: Finding) -> bool:
    """Edges that never arrived sooner than the same time after their stamps, over the same time, where ``delay``
    found a clock's offset (its ``clock_behind``: none sooner than a second, or every sample about as late as another
    edge's): one clock behind the recorder's (two real drones' and their MAVROS' edges, none sooner than 2.3 s; five
    days later 0.39-0.40 s), not one slow publisher per edge."""
    a, b = first.figures.get("late_s_min"), finding.figures.get("late_s_min")
    if not isinstance(a, float) or not isinstance(b, float):
        return False
    if first.figures.get("clock_behind") != 1.0 or finding.figures.get("clock_behind") != 1.0:
        return False
    overlap = finding.first_time <= first.last_time and first.first_time <= finding.last_time
    return overlap and abs(a - b) <= SAME_CLOCK_S


def _skipped(link: Finding, finding: Finding) -> bool:
    """Of links that tf puts under another parent than the description (tf's, the links, the description's):
    the joint missing from tf between the two parents (tf skips it)."""
    if len(link.frames) < 3:
        return False
    return finding.frames == (link.frames[0], link.frames[-1])


def edges_of(finding: Finding) -> set[tuple[str, str]]:
    """The edges a finding names as consecutive parent, child pairs."""
    return set(zip(finding.frames[0::2], finding.frames[1::2], strict=False))


def _placed_apart(cause: Finding, finding: Finding) -> bool:
    """A frame the disputing /tf_static publishers each send under another parent (of its parents, each from
    publishers none of the others came from): their two descriptions' layouts differ, one dispute."""
    apart = finding.figures.get("parents_each_from_other_static_publishers") == 1
    return apart and set(finding.authorities) <= set(cause.authorities)


def _during(cause: Finding, finding: Finding) -> bool:
    """A finding about one of the cause's edges at a time that overlaps the cause's."""
    return (
        len(finding.frames) == 2
        and edges_of(finding) <= edges_of(cause)
        and finding.first_time <= cause.last_time
        and cause.first_time <= finding.last_time
    )


#: How far (s) around the span of a file's lost messages a pause or a bad value is put down to them, at least, and
#: what share of that span further: a pause of tf begins with the last sample read before them and ends with the
#: first after (a slow publisher's a period away), no further (a real pause just before is the robot's).
DAMAGE_REACH_S, DAMAGE_REACH_SHARE = 1.0, 0.1


#: What a file's damage may explain (``in_the_damage``).
IN_DAMAGE = frozenset({"stall", "rate", "stale", "invalid_values", "jump", "time_backwards"})


def in_the_damage(cause: Finding, finding: Finding) -> bool:
    """A pause, stop or bad value of tf within the span of a file's lost messages (``DAMAGE_REACH_S``): lost or
    read from damaged bytes there, not the robot's."""
    if not cause.last_time or not finding.first_time:
        return False
    reach = max(int(DAMAGE_REACH_SHARE * (cause.last_time - cause.first_time)), int(DAMAGE_REACH_S * 1e9))
    return cause.first_time - reach <= finding.first_time and finding.last_time <= cause.last_time + reach


def _its_parents_by_topic(cause: Finding, finding: Finding) -> bool:
    """A frame sent on /tf_static and on /tf under parents the cause found it under (its frame, then those)."""
    return finding.frames[:1] == cause.frames[:1] and set(finding.frames[1:]) <= set(cause.frames[1:])


def _left_behind(cause: Finding, finding: Finding) -> bool:
    """Trees (named by their roots) all rooted, but for one, at parents the re-parented frame had: the frame
    left them, which split the tree."""
    return len(set(finding.frames) - set(cause.frames[1:])) <= 1


def _split_by_its_parents(cause: Finding, finding: Finding) -> bool:
    """``mixed_static`` on the re-parented frame's parents, or ``disconnected`` where it left them."""
    return _its_parents_by_topic(cause, finding) if finding.code == "mixed_static" else _left_behind(cause, finding)


def _on_the_older_clock(cause: Finding, finding: Finding) -> bool:
    """An edge whose stamps arrived as long after them as the older of two clocks' taking turns on the
    cause's edge (nearer its offset than the newer's): the replayed recording's, stamped on its clock, and
    stopping where the replay ended."""
    older, newer = cause.figures.get("older_offset_s"), cause.figures.get("newer_offset_s")
    offset = finding.figures.get("arrival_minus_stamp_s")
    if not isinstance(older, float) or not isinstance(newer, float) or not isinstance(offset, float):
        return False
    return abs(offset - older) < abs(offset - newer)


def _in_a_tree_apart(cause: Finding, finding: Finding) -> bool:
    """Sensor data in frames tf knows, but in a tree apart from the target: the recording's trees are apart."""
    return finding.figures.get("in_a_tree_apart") == 1


def _publisher(finding: Finding) -> tuple[str, ...]:
    """The nodes a finding names as its publishers; none where the recording names only topics (a ROS 2 bag's
    /tf), which would lump every publisher's edges together."""
    named = all(a and a.rsplit("/", 1)[-1] not in ("tf", "tf_static") for a in finding.authorities)
    return finding.authorities if finding.authorities and named else ()


def _same_publisher(first: Finding, finding: Finding) -> bool:
    """Findings of the same named publishers (one node's choice, seen on each of its edges)."""
    return bool(_publisher(first)) and _publisher(first) == _publisher(finding)


def _one_publisher(finding: Finding) -> tuple[tuple[str, ...]]:
    """``_same_publisher``'s key."""
    return (_publisher(finding),)


def _same_publisher_or_message(first: Finding, finding: Finding) -> bool:
    """Findings of the same named publishers, or, where the recording names none (a ROS 2 bag), seen at the same
    moments on other edges (one message's)."""
    if _publisher(first) or _publisher(finding):
        return _same_publisher(first, finding)
    return _same_change(first, finding)


def _publisher_or_change(finding: Finding) -> tuple[Hashable, ...]:
    """``_same_publisher_or_message``'s keys."""
    return (*_one_publisher(finding), *_change(finding))


def _same_nodes_at_once(first: Finding, finding: Finding) -> bool:
    """Edges that the same named nodes both send at once (``figures["at_once"]``): one pair of publishers."""
    both = first.figures.get("at_once") == finding.figures.get("at_once") == 1
    return both and bool(_publisher(first)) and _nodes(first) == _nodes(finding) and first.frames != finding.frames


def _nodes(finding: Finding) -> tuple[tuple[str, ...]]:
    """``_same_nodes_at_once``' key: the named publishers, in name order."""
    return (tuple(sorted(_publisher(finding))),)


def _same_change_elsewhere(first: Finding, finding: Finding) -> bool:
    """``_same_change`` on another edge by the same publisher (or, unnamed, the same topic): one edge's two kinds of
    the same finding stay apart, and so do two nodes'."""
    same_publisher = _publisher(first) == _publisher(finding)
    return same_publisher and first.frames != finding.frames and _same_change(first, finding)


def _same_edge(first: Finding, finding: Finding) -> bool:
    """Findings about the same edge (each naming it alone)."""
    return bool(first.frames) and first.frames == finding.frames


def _refused_to_the_end(cause: Finding, finding: Finding) -> bool:
    """A stale edge whose later transforms were refused for their values (``stale``'s ``refused_after``), under the
    refusal of that edge."""
    return _same_edge(cause, finding) and bool(finding.figures.get("refused_after"))


def _robots_alike(cause: Finding, finding: Finding) -> bool:
    """A tree apart whose root the same node of several robots sends without a robot's prefix (two drones'
    MAVROS sending fcu -> lidarlite_laser): no robot's tree holds it because its frames are every robot's."""
    return robots_of(cause.authorities) is not None and bool(cause.frames) and cause.frames[0] in finding.frames[1:]


def _under_it(first: Finding, finding: Finding) -> bool:
    """A frame under another the same finding found (one subtree: a second robot's links, each not in the
    description): the frame's parent is the cause's frame, both named with their parent."""
    placed = len(first.frames) == len(finding.frames) == 2 and bool(first.authorities)
    return placed and finding.frames[0] == first.frames[1]


def _detector(finding: Finding) -> tuple[tuple[str, str, tuple[str, ...]]] | tuple[()]:
    """``_same_detector``'s key: a detection's finding's code, camera frame and publishers; none for another finding."""
    if finding.figures.get(DETECTION) != 1 or not finding.frames:
        return ()
    return ((finding.code, finding.frames[0], finding.authorities),)


def _same_detector(first: Finding, finding: Finding) -> bool:
    """Findings of one kind about detections under the same camera frame by the same publishers: one detector's
    way with what it sees (e-Yantra Agri Bot's 44 tomatoes, each unseen, stale and at the camera's origin alike)."""
    return bool(_detector(first)) and _detector(first) == _detector(finding)


def _sources(finding: Finding) -> tuple[str] | tuple[()]:
    """``_same_sources``' key: the publisher whose joints came in messages of two kinds (``joint_sources``)."""
    publisher = finding.figures.get(JOINT_SOURCES)
    return (publisher,) if isinstance(publisher, str) else ()


def _same_sources(cause: Finding, finding: Finding) -> bool:
    """Findings about joints of one publisher fed by two sources of joint states (``joint_sources``)."""
    return bool(_sources(cause)) and _sources(cause) == _sources(finding)


@dataclass(frozen=True)
class Rule:
    """Findings of the codes ``follows`` follow from one of the codes ``causes`` when ``relates(cause, it)``."""

    causes: frozenset[str]
    follows: frozenset[str]
    relates: Callable[[Finding, Finding], bool]
    why: str
    #: Where ``relates`` holds only between findings sharing one of these keys: causes are looked up by them,
    #: not scanned (20,000 stale edges of one flooding message would take n² comparisons).
    keys: Callable[[Finding], Iterable[Hashable]] | None = None


#: A finding that follows from one that follows from another is said beneath the first (the root cause).
RULES = (
    Rule(
        frozenset({"bag_problem"}),
        IN_DAMAGE,
        in_the_damage,
        "pauses, stops and bad values of tf where the file is damaged: its messages there were lost, or read "
        "from damaged bytes, said once with the damage",
    ),
    Rule(
        frozenset({"static_conflict", "dynamic_on_static"}),
        frozenset({"urdf_moved", "urdf_parent", "urdf_missing"}),
        _on_its_frames,
        "a robot description that disagrees with tf on frames whose /tf_static values are in dispute: "
        "tf holds one of the disputed values, and the description agrees with another",
    ),
    Rule(
        frozenset({"static_conflict"}),
        frozenset({"multiple_parents"}),
        _placed_apart,
        "a frame that two disputing /tf_static publishers place under different parents: their descriptions' "
        "layouts differ, said once with the values they disagree on",
    ),
    Rule(
        frozenset({"multiple_parents"}),
        frozenset({"mixed_static", "disconnected"}),
        _split_by_its_parents,
        "a frame under one parent on /tf_static and another on /tf (a URDF's base_footprint -> base_link beside a "
        "driver's odom -> base_link): its two topics, and the tree it split by leaving a parent, follow from its "
        "two parents, said once",
    ),
    Rule(
        frozenset({"multiple_authorities"}),
        frozenset({"disconnected"}),
        _robots_alike,
        "a tree apart sent by the same node of several robots (each drone's MAVROS) under frame names without a "
        "robot's prefix: one frame for every robot, attached to none, said once with the publishers",
    ),
    Rule(
        frozenset({"multiple_authorities"}),
        frozenset({"clock", "stale"}),
        _on_the_older_clock,
        "edges stamped on the older of two clocks that take turns on one edge (a recording replayed with its own "
        "/tf beside live nodes): their clock, and their stop where the replay ended, follow from the replay, "
        "said once",
    ),
    Rule(
        frozenset({"multiple_authorities"}),
        frozenset({"multiple_authorities"}),
        _same_nodes_at_once,
        "edges that the same nodes both send at once (a humanoid's four force sensors from two state publishers): "
        "one pair of publishers, said once with its edges beneath",
        keys=_nodes,
    ),
    Rule(
        frozenset({"dynamic_on_static"}),
        frozenset({"dynamic_on_static"}),
        _same_change,
        "static edges changed by one /tf_static message: one change of a description (or a second one), said "
        "once; ROS 2 bags, which name no publisher, show a second description so",
        keys=_change,
    ),
    Rule(
        frozenset({"rate"}),
        frozenset({"rate"}),
        _same_change,
        "edges with the same pauses (or rhythm) at the same times: edges of one message, one publisher's "
        "pause, said once",
        keys=_change,
    ),
    Rule(
        frozenset({"invalid_values"}),
        frozenset({"stale"}),
        _refused_to_the_end,
        "an edge whose transforms after its last valid one were all refused for their values (an e-Yantra fruit "
        "detection's NaN, its stamps going on): tf2 holds nothing newer, which the refusal says first",
    ),
    Rule(
        frozenset({"stale"}),
        frozenset({"stale"}),
        _same_change,
        "edges that stop at the same stamp after as many samples: edges of one message, one publisher that "
        "stopped, said once",
        keys=_change,
    ),
    Rule(
        frozenset({"future"}),
        frozenset({"future"}),
        _one_clock_ahead,
        "edges stamped ahead of their arrival by the same amount at the same time (fixed joints on /tf by ROS 1 "
        "robot_state_publisher's half second more): one machine's clock ahead of the recorder's, said once",
    ),
    Rule(
        frozenset({"delay"}),
        frozenset({"delay"}),
        _one_clock_behind,
        "edges that never arrived sooner than the same time after their stamps (two real drones' edges, none "
        "sooner than 2.3 s): one clock behind the recorder's (or the recorder's ahead), said once",
    ),
    Rule(
        frozenset({"leading_slash"}),
        frozenset({"leading_slash"}),
        _shares_a_frame,
        "frames named with a leading '/' on /tf and /tf_static (or by two publishers) that share a frame: one "
        "naming (robot_state_publisher's frame_prefix, a tf_prefix), said once",
        keys=_frames,
    ),
    Rule(
        frozenset({"static_on_dynamic"}),
        frozenset({"static_on_dynamic"}),
        _same_publisher_or_message,
        "constant edges one node sends on /tf (Stage's stageros: each robot's base_link and laser mounts), or one "
        "message sends (a ROS 2 bag names no node: a real JetAcker's two joints): one publisher's choice, said once "
        "with its edges beneath",
        keys=_publisher_or_change,
    ),
    Rule(
        frozenset({"time_backwards"}),
        frozenset({"time_backwards", "rate"}),
        _same_sources,
        "joints a state publisher sent in messages of two kinds carrying them alike (e-Yantra Agri Bot's arm: 12 "
        "joints at 40 Hz, and 16 with the wheels at 10 Hz): two sources of joint states, whose stamps take turns "
        "(out of order, repeated) and whose rhythms mix, said once with each joint beneath",
        keys=_sources,
    ),
    Rule(
        frozenset({"time_backwards"}),
        frozenset({"time_backwards"}),
        _same_change_elsewhere,
        "edges stamped out of order (or again) at the same times as often: edges of one message (a real JetAcker's "
        "two joints, 7 samples each), one publisher's, said once",
        keys=_change,
    ),
    Rule(
        frozenset({"mixed_static"}),
        frozenset({"urdf_kind"}),
        _of_its_frame,
        "a fixed joint whose link is sent on /tf as well as /tf_static: the one choice of topic mixed_static says "
        "(Franka teleop's base and fr3_link0), not a second finding that it comes on /tf",
    ),
    Rule(
        frozenset({"mixed_static"}),
        frozenset({"mixed_static"}),
        _same_change_elsewhere,
        "frames sent on /tf_static and on /tf at the same times as often: frames of one message (Franka teleop's "
        "base and fr3_link0), one publisher's choice of topic, said once",
        keys=_change,
    ),
    Rule(
        frozenset({"urdf_extra"}),
        frozenset({"urdf_extra"}),
        _under_it,
        "frames the description lacks under another it lacks (a second robot's links, a sensor's frames): one "
        "subtree another node owns, said once at its top",
        keys=_frames,
    ),
    Rule(
        frozenset({"urdf_parent"}),
        frozenset({"urdf_missing"}),
        _skipped,
        "links that tf puts under another parent than the description (one finding), skipping a link, and that "
        "link's joint missing from tf: one layout of the links (tf skips a joint), not one problem per joint",
    ),
    Rule(
        frozenset({"disconnected"}),
        frozenset({"sensor_frame"}),
        _in_a_tree_apart,
        "sensor data whose frames tf knows, in another tree than the frame it is checked in: the trees apart, "
        "said once with the frames each holds; lookups of that data into the target fail because of it",
    ),
    Rule(
        frozenset({"sensor_wait"}),
        frozenset({"sensor_wait"}),
        _same_edge,
        "sensor streams that wait for one late edge (CyberShip Voyager's IMU, magnetometer and temperature, each "
        "waiting for the motion capture's world -> base_link): that edge's lag behind their stamps, said once with "
        "each stream beneath",
        keys=_frames,
    ),
    Rule(
        frozenset({"jump", "stale", "rate"}),
        frozenset({"jump", "stale", "rate"}),
        _same_detector,
        "detections under one camera frame by one publisher, each unseen, stale or jumping alike (a detector naming "
        "what it sees by its place in a list: 44 tomatoes): one detector's way with what it sees, said once with "
        "each object beneath",
        keys=_detector,
    ),
    Rule(
        frozenset({"stall"}),
        frozenset({"rate"}),
        _during,
        "an edge's pauses, one of them in a stall of many edges at once: one stop, not one per edge (the finding "
        "beneath it still says how many pauses that edge had)",
    ),
)


def severity_as_cause(code: str, severities: Mapping[str, Severity], rules: Sequence[Rule] = RULES) -> Severity:
    """The most severe a finding of ``code`` (a check's, ``severities[code]`` on its own) is made where it
    explains others (``explain``: as severe as the worst of them): for ``--list-checks``, which says so."""
    following = [severities[c] for rule in rules if code in rule.causes for c in rule.follows if c in severities]
    return min([severities[code], *following], key=_rank)


def explain(findings: Sequence[Finding], rules: Sequence[Rule] = RULES) -> list[Finding]:
    """``findings`` with each that follows from another (by the first rule, then the first cause, that
    explain it; of one code, an earlier one) linked to it, or to what that one follows from (its root
    cause); each cause as severe as the worst that follows from it (a recording's verdict and exit code
    go by causes); in order: causes by severity (as found), each followed by what it explains. Called
    again on findings it linked (with more added), it links them anew."""
    found = [replace(f, key="", cause="") for f in findings]
    cause_of: dict[int, int] = {}
    candidates = [_Candidates(rule, found) for rule in rules]
    for i, finding in enumerate(found):
        for rule, among in zip(rules, candidates, strict=True):
            if finding.code in rule.follows:
                j = next((j for j in among.for_(finding) if _may(rule, found[j], j, finding, i)), None)
                if j is not None:
                    cause_of[i] = j
                    break
    for i in list(cause_of):
        seen = {i}
        while cause_of[i] in cause_of and cause_of[i] not in seen:  # to the root cause
            seen.add(cause_of[i])
            cause_of[i] = cause_of[cause_of[i]]
        if cause_of[i] in seen:  # findings that would explain each other: none of them follows
            del cause_of[i]
    keys: dict[int, str] = {}
    for j in sorted(set(cause_of.values())):
        keys[j] = f"{found[j].code}:{sum(found[k].code == found[j].code for k in keys) + 1}"
    for j, key in keys.items():
        worst = min([found[j].severity, *(found[i].severity for i, c in cause_of.items() if c == j)], key=_rank)
        found[j] = replace(found[j], key=key, severity=worst)
    for i, j in cause_of.items():
        found[i] = replace(found[i], cause=keys[j])
    ordered = sorted((f for f in found if not f.cause), key=lambda f: f.severity.rank)
    following: dict[str, list[Finding]] = {}
    for f in found:
        if f.cause:
            following.setdefault(f.cause, []).append(f)
    return [g for f in ordered for g in (f, *_beneath(following.get(f.key, []) if f.key else [], f))]


class _Candidates:
    """The findings that may explain others by one rule (of its cause codes), in order: by key where the rule
    has keys, built on first use."""

    def __init__(self, rule: Rule, found: Sequence[Finding]) -> None:
        self.rule, self.found = rule, found
        self._all: list[int] | None = None
        self._by_key: dict[Hashable, list[int]] | None = None

    def for_(self, finding: Finding) -> Iterable[int]:
        if self._all is None:
            self._all = [j for j, f in enumerate(self.found) if f.code in self.rule.causes]
        if self.rule.keys is None:
            return self._all
        if self._by_key is None:
            self._by_key = {}
            for j in self._all:
                for key in dict.fromkeys(self.rule.keys(self.found[j])):
                    self._by_key.setdefault(key, []).append(j)
        lists = [self._by_key.get(key, []) for key in dict.fromkeys(self.rule.keys(finding))]
        return lists[0] if len(lists) == 1 else sorted({j for found in lists for j in found})


def _beneath(following: Sequence[Finding], cause: Finding) -> list[Finding]:
    """What follows from ``cause`` (``following``, as found): the same seen elsewhere (its code) first, then the
    rest. Gathered per cause in one pass: scanned per cause, 20,000 findings of a frame flood took minutes."""
    return sorted(following, key=lambda f: f.code != cause.code)


def _may(rule: Rule, cause: Finding, j: int, finding: Finding, i: int) -> bool:
    """Whether by ``rule`` the ``j``-th finding explains the ``i``-th: not itself, of one code only an earlier one."""
    earlier = j != i and (cause.code != finding.code or j < i)
    return earlier and cause.code in rule.causes and rule.relates(cause, finding)


def _rank(severity: Severity) -> int:
    return severity.rank
