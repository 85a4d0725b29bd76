"""A rospy node that prints each /diagnostics message it hears as one JSON line, with Debian's
diagnostic_msgs (not tftools'): the independent subscriber of the /diagnostics tests. Run with
/usr/bin/python3; says "ready" once subscribed."""

import json
import sys

import rospy
from diagnostic_msgs.msg import DiagnosticArray


def main() -> None:
    rospy.init_node("diagnostics_listener", anonymous=True, disable_signals=True)

    def heard(message: DiagnosticArray) -> None:
        statuses = [
            {
                "level": ord(s.level) if isinstance(s.level, bytes) else int(s.level),
                "name": s.name,
                "message": s.message,
                "hardware_id": s.hardware_id,
                "values": {kv.key: kv.value for kv in s.values},
            }
            for s in message.status
        ]
        publisher = message._connection_header.get("callerid", "")
        line = {"stamp": message.header.stamp.to_nsec(), "publisher": publisher, "status": statuses}
        sys.stdout.write(json.dumps(line) + "\n")
        sys.stdout.flush()

    rospy.Subscriber("/diagnostics", DiagnosticArray, heard, queue_size=100)
    print("ready", flush=True)
    rospy.spin()


if __name__ == "__main__":
    main()
