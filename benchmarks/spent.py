"""What a process spent on a span of its own work, and what the machine took from it meanwhile: for telling a
slow run of the work from a run the machine disturbed (``ratios.py``). Plain Python and Linux's /proc only:
``tf2_side.py`` runs it under Debian's Python, without tftools.

``usage()`` before the span, ``spent_since(before, key)`` after it: ``{key}_cpu_s`` the process's CPU time
(precise, not rusage's tick-scaled split), ``{key}_waited_s`` the time its threads were ready to run but
waited for a CPU another process held (the scheduler's run-queue delay), ``{key}_steal_s`` the time the
hypervisor ran something else on this machine's CPUs (all of them: a neighbour of the virtual machine), and
the minor and major page faults. The last three are 0 where /proc does not tell them.
"""

from __future__ import annotations

import os
import resource
import time

#: USER_HZ, the unit of /proc/stat's times.
_TICK_S = 1 / os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 0.01


def _waited_s() -> float:
    """The run-queue delay of every thread of this process so far (``/proc/self/task/*/schedstat``)."""
    total = 0
    try:
        for task in os.listdir("/proc/self/task"):
            with open(f"/proc/self/task/{task}/schedstat") as f:
                total += int(f.read().split()[1])
    except (OSError, IndexError, ValueError):
        return 0.0
    return total / 1e9


def _steal_s() -> float:
    """The machine's steal time so far, all CPUs (``/proc/stat``'s eighth column)."""
    try:
        with open("/proc/stat") as f:
            fields = f.readline().split()
        return int(fields[8]) * _TICK_S
    except (OSError, IndexError, ValueError):
        return 0.0


def usage() -> tuple[float, float, float, int, int]:
    faults = resource.getrusage(resource.RUSAGE_SELF)
    return time.process_time(), _waited_s(), _steal_s(), faults.ru_minflt, faults.ru_majflt


def spent_since(before: tuple[float, float, float, int, int], key: str) -> dict:
    names = ("cpu_s", "waited_s", "steal_s", "minor_faults", "major_faults")
    # rounded: /proc/stat's ticks made seconds differ from whole hundredths by the float's last bits
    return {f"{key}_{name}": round(now - then, 9) for name, then, now in zip(names, before, usage(), strict=True)}
