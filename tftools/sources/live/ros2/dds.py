"""Cyclone DDS as ROS 2's rmw_cyclonedds uses it: the domain, participants, QoS, raw samples."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from typing import Any

from cyclonedds.core import (
    DDSException,
    GuardCondition,
    InstanceState,
    Policy,
    Qos,
    ReadCondition,
    SampleState,
    ViewState,
    WaitSet,
)
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.internal import SampleInfo, load_cyclonedds
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from tftools.sources.live.errors import DdsError
from tftools.sources.live.ros2.conventions import QosProfile, discovery_config

_INFINITY = 0x7FFFFFFFFFFFFFFF  # DDS_INFINITY
_ANY_SAMPLE = SampleState.Any | ViewState.Any | InstanceState.Any

#: A participant's user data as rmw_cyclonedds sets it (rmw_node.cpp): the security enclave.
ROS_PARTICIPANT_USER_DATA = b"enclave=/;"


def qos(profile: QosProfile, *, writer: bool = False) -> Qos:
    """``profile`` as rmw_cyclonedds's create_readwrite_qos makes it, XCDR1 only as its sertype allows."""
    history = Policy.History.KeepAll if profile.keep_all else Policy.History.KeepLast(profile.depth)
    policies: list[Any] = [
        history,
        Policy.Reliability.Reliable(_INFINITY) if profile.reliable else Policy.Reliability.BestEffort,
        Policy.Durability.TransientLocal if profile.transient_local else Policy.Durability.Volatile,
        Policy.DataRepresentation(use_cdrv0_representation=True),
    ]
    if profile.transient_local:  # Cyclone keeps a transient local writer's history as its durability service
        policies.append(Policy.DurabilityService(0, history, -1, -1, -1))
    if writer:
        policies.append(Policy.WriterDataLifecycle(autodispose=False))
    return Qos(*policies)


#: Cyclone DDS's log categories (dds_public_log.h DDS_LC_FATAL, _ERROR, _WARNING): what it prints on stderr.
_LOG_FATAL = 1


def _quiet_log() -> None:
    """Cyclone DDS prints a line of its own on stderr for every malformed packet or sample a peer sends (100
    to 640 lines in 5 s of a hostile peer; its build exports no log sink to capture them): only its fatal
    errors are printed, tfx saying in its notices what a peer did. ``TFX_DEBUG=1`` keeps its whole log."""
    if not os.environ.get("TFX_DEBUG"):
        load_cyclonedds().dds_set_log_mask(_LOG_FATAL)


class _Domains:
    """Domains of this process, created once with ROS 2's discovery settings and shared (as
    rmw_cyclonedds's check_create_domain does): Cyclone refuses a second domain of the same id."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._domains: dict[int, tuple[Domain, int]] = {}

    def acquire(self, domain_id: int) -> None:
        with self._lock:
            domain, users = self._domains.get(domain_id) or (None, 0)
            if domain is None:
                _quiet_log()
                try:
                    domain = Domain(domain_id, discovery_config())
                except DDSException as error:
                    raise DdsError(f"join DDS domain {domain_id}", error) from None
            self._domains[domain_id] = (domain, users + 1)

    def release(self, domain_id: int) -> None:
        with self._lock:
            domain, users = self._domains[domain_id]
            if users > 1:
                self._domains[domain_id] = (domain, users - 1)
                return
            del self._domains[domain_id]
            domain.__del__()  # deletes the domain now, not when Python collects it


_DOMAINS = _Domains()


class Participant:
    """A DDS participant on ROS 2 domain ``domain_id``, announced as a ROS 2 participant."""

    def __init__(self, domain_id: int) -> None:
        self.domain_id = domain_id
        _DOMAINS.acquire(domain_id)
        try:
            self.dds = DomainParticipant(domain_id, qos=Qos(Policy.Userdata(ROS_PARTICIPANT_USER_DATA)))
        except DDSException as error:
            _DOMAINS.release(domain_id)
            raise DdsError(f"join DDS domain {domain_id}", error) from None
        self._topics: dict[tuple[str, type[Any]], Topic[Any]] = {}
        self._closed = False

    @property
    def guid(self) -> bytes:
        return self.dds.guid.bytes

    def topic(self, name: str, data_type: type[Any]) -> Topic[Any]:
        """The topic ``name`` of ``data_type`` (Cyclone allows several types under one name)."""
        key = (name, data_type)
        if key not in self._topics:
            self._topics[key] = Topic(self.dds, name, data_type)
        return self._topics[key]

    def reader(self, name: str, data_type: type[Any], profile: QosProfile) -> DataReader[Any]:
        return DataReader(self.dds, self.topic(name, data_type), qos=qos(profile))

    def writer(self, name: str, data_type: type[Any], profile: QosProfile) -> DataWriter[Any]:
        return DataWriter(self.dds, self.topic(name, data_type), qos=qos(profile, writer=True))

    def close(self) -> None:
        """Leave the domain: its readers and writers go with it (other participants see them go)."""
        if self._closed:
            return
        self._closed = True
        self.dds.__del__()  # dds_delete: the participant and all its entities, now
        _DOMAINS.release(self.domain_id)


class Waiter:
    """A thread that waits for samples on the readers it ``watch``es and calls ``step`` after each wait,
    until ``stop``; ``step`` returns the seconds to wait at most before the next call. A step that fails
    (a peer's or tfx's fault) is said through ``on_notice`` as dropping ``what``, and listening goes on."""

    def __init__(self, participant: Participant) -> None:
        self._waitset = WaitSet(participant.dds)
        self._wake = GuardCondition(participant.dds)
        self._conditions: list[Any] = []  # kept: Python deleting a condition would delete (detach) its DDS entity
        self._attach(self._wake)
        self._stopped = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self, step: Callable[[], float], name: str, on_notice: Callable[[str], None], what: str) -> None:
        self._thread = threading.Thread(target=self._run, args=(step, on_notice, what), name=name, daemon=True)
        self._thread.start()

    def _run(self, step: Callable[[], float], on_notice: Callable[[str], None], what: str) -> None:
        seconds = 1.0
        while not self._stopped.is_set():
            self._waitset.wait(duration(seconds=seconds))
            if self._stopped.is_set():
                return
            try:
                seconds = step()
            except Exception as error:
                on_notice(f"dropped {what}: {type(error).__name__}: {error}")

    def stop(self) -> None:
        if self._stopped.is_set():
            return
        self._stopped.set()
        self._wake.set(True)
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)

    def watch(self, reader: DataReader[Any]) -> None:
        self._attach(ReadCondition(reader, _ANY_SAMPLE))

    def _attach(self, condition: Any) -> None:
        self._conditions.append(condition)
        self._waitset.attach(condition)


#: The bytes of samples one take brings into Python at most (beside the one sample that crosses it): samples
#: of 60 MiB back to back, taken 256 at a time, held gigabytes.
TAKE_BYTES = 64 << 20


def take_raw(reader: DataReader[Any], limit: int = 256, max_bytes: int = TAKE_BYTES) -> list[tuple[bytes, SampleInfo]]:
    """Up to ``limit`` samples, and no more once ``max_bytes`` are taken, as the CDR bytes that arrived
    (encapsulation header first), each with its sample info: decoded by tftools in bulk rather than into
    one Python object per field. What is left stays in the reader (its waitset condition wakes again)."""
    from cyclonedds._clayer import ddspy_take  # what DataReader.take calls before deserializing

    samples: list[tuple[bytes, SampleInfo]] = []
    size = 0
    for _ in range(limit):
        if size >= max_bytes:
            break
        taken = ddspy_take(reader._ref, _ANY_SAMPLE, 1)  # one at a time: a sample's size is known once taken
        if isinstance(taken, int):
            raise DDSException(taken, f"Occurred while taking data in {reader!r}")
        if not taken:
            break
        data, info = taken[0]
        if info.valid_data:
            samples.append((data, info))
            size += len(data)
    return samples


def write_raw(writer: DataWriter[Any], data: bytes) -> None:
    """Write a sample given as its CDR bytes (encapsulation header first), as ``DataWriter.write`` writes
    the bytes it serializes: encoded by tftools, as bags are."""
    from cyclonedds._clayer import ddspy_write

    written = ddspy_write(writer._ref, data.ljust(len(data) + -len(data) % 4, b"\0"))  # DDS pads to 4 bytes
    if written < 0:
        raise DDSException(written, f"Occurred while writing sample in {writer!r}")
