# ruff: noqa: N801 - the structs carry the names ROS 2 gives them on the wire
# mypy: disable-error-code="type-arg, assignment, attr-defined"
# (Cyclone DDS's IDL annotations are not types mypy knows.)
"""A Cyclone DDS reader of ROS 2's /diagnostics with its own definition of the type (ROS 2's name
``diagnostic_msgs::msg::dds_::DiagnosticArray_``, not tftools'), printing each sample as one JSON line:
the independent subscriber of the /diagnostics tests. Says "ready" once its reader exists."""

import json
import os
import sys
import time
from dataclasses import dataclass, field

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import byte, sequence
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from ros2_nodes import Header_  # beside it: the stand-in nodes' own std_msgs/Header


@dataclass
class KeyValue_(IdlStruct, typename="diagnostic_msgs::msg::dds_::KeyValue_"):
    key: str = ""
    value: str = ""


@dataclass
class DiagnosticStatus_(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticStatus_"):
    level: byte = 0  # rosidl's byte: IDL's octet
    name: str = ""
    message: str = ""
    hardware_id: str = ""
    values: sequence[KeyValue_] = field(default_factory=list)


@dataclass
class DiagnosticArray_(IdlStruct, typename="diagnostic_msgs::msg::dds_::DiagnosticArray_"):
    header: Header_ = field(default_factory=Header_)
    status: sequence[DiagnosticStatus_] = field(default_factory=list)


def main() -> None:
    participant = DomainParticipant(int(os.environ.get("ROS_DOMAIN_ID", "0")))
    topic = Topic(participant, "rt/diagnostics", DiagnosticArray_)
    # as a ROS 2 subscriber with the default QoS: reliable, volatile, keep last 10
    reader = DataReader(participant, topic, qos=Qos(Policy.Reliability.Reliable(0), Policy.History.KeepLast(10)))
    print("ready", flush=True)
    while True:
        for sample in reader.take(N=100):
            statuses = [
                {
                    "level": s.level if isinstance(s.level, int) else ord(s.level),
                    "name": s.name,
                    "message": s.message,
                    "hardware_id": s.hardware_id,
                    "values": {kv.key: kv.value for kv in s.values},
                }
                for s in sample.status
            ]
            stamp = sample.header.stamp.sec * 1_000_000_000 + sample.header.stamp.nanosec
            sys.stdout.write(json.dumps({"stamp": stamp, "status": statuses}) + "\n")
            sys.stdout.flush()
        time.sleep(0.05)


if __name__ == "__main__":
    main()
