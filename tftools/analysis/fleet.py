"""Running one task per recording of a fleet: here, in local processes, or on an existing Dask cluster,
through one ``concurrent.futures`` path. ``run_fleet`` yields ``(index, result)`` as tasks finish; a task
that did not finish (its process or worker died, it ran out of its time, it raised in a worker) is an
``Unfinished`` that says why (an ``UnfinishedCause`` and its facts), for the caller to word as its own result.

Dask is the engine there: tasks are submitted with ``retries=1`` (a task that raised, e.g. timed out, runs
once more), and a worker that dies is handled by the scheduler, which runs its tasks elsewhere until they
have killed ``distributed.scheduler.allowed-failures`` workers (set it to 1 on the scheduler for "retried
once"), then reports ``KilledWorker``. The time limit is kept inside the task, so that every executor
applies it the same way: a thread runs the task, which gives up after the time (Python cannot stop a
thread: the abandoned task keeps its worker busy until it ends). Workers import this module: it stays small.
"""

from __future__ import annotations

import enum
import functools
import logging
import multiprocessing
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent import futures
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeVar
from urllib.parse import urlsplit

from tftools.core.errors import FleetUnavailableError

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["HERE", "Fleet", "TaskTimeoutError", "Unfinished", "UnfinishedCause", "run_fleet", "timed"]

T = TypeVar("T")
Group = Sequence[str]  # the paths of one recording (a split bag has several)

INSTALL_HINT = "install the extra: pip install 'tftools[fleet]'"
CONNECT_SECONDS = 5
_WORKER_HINT = "check that every worker has this tftools installed, and see the worker's log"


class TaskTimeoutError(Exception):
    """A recording's task ran out of its time."""


@dataclass(frozen=True)
class Fleet:
    """Where a fleet's tasks run: ``jobs`` local processes (1: in this process), or on the Dask scheduler
    at ``dask``; each within ``timeout`` seconds (none: no limit)."""

    jobs: int = 1
    dask: str | None = None
    timeout: float | None = None


#: One task after the other, in this process, without a time limit.
HERE = Fleet()


class UnfinishedCause(enum.Enum):
    """Why a task did not finish."""

    TIMED_OUT = "timed_out"  # it ran out of the fleet's time (on Dask: twice)
    WORKERS_DIED = "workers_died"  # the workers that ran it died each time
    FAILED = "failed"  # it raised, or its process died


#: What to do about each cause, in the library's words (a command line words them with its own options).
HINTS = {
    UnfinishedCause.TIMED_OUT: "give it more time, or check it alone",
    UnfinishedCause.WORKERS_DIED: "check it alone: it may crash or exhaust them",
    UnfinishedCause.FAILED: _WORKER_HINT,
}


@dataclass(frozen=True)
class Unfinished:
    """A task that did not finish: why (``cause``, said with its facts in ``why``)."""

    why: str
    cause: UnfinishedCause

    @property
    def hint(self) -> str:
        """What to do about it (``HINTS``)."""
        return HINTS[self.cause]


def run_fleet(
    groups: Sequence[Group], task: Callable[[Group], T], fleet: Fleet = HERE
) -> Iterator[tuple[int, T | Unfinished]]:
    """``task`` on each group of paths (each a recording), yielding ``(index in groups, result)`` as they
    finish. ``task`` must be picklable (a module's function, or a ``functools.partial`` of one) for
    ``fleet.jobs`` > 1 or Dask. Raises ``FleetUnavailableError`` when Dask is missing or its scheduler not reached."""
    check = timed(task, fleet.timeout)
    if fleet.dask is not None:
        return _on_dask(groups, check, fleet.dask)
    if fleet.jobs <= 1 or len(groups) <= 1:
        return _in_process(groups, check)
    return _in_processes(groups, check, fleet.jobs)


def timed(task: Callable[[Group], T], seconds: float | None) -> Callable[[Group], T]:
    """``task`` given up after ``seconds`` (none: no limit), raising ``TaskTimeoutError``."""
    return task if seconds is None else functools.partial(_within, task, seconds)


def _within(task: Callable[[Group], T], seconds: float, group: Group) -> T:
    outcome: futures.Future[T] = futures.Future()

    def run() -> None:
        try:
            outcome.set_result(task(group))
        except BaseException as error:  # handed to the waiting thread, which raises it
            outcome.set_exception(error)

    threading.Thread(target=run, name="tfx-check", daemon=True).start()
    try:
        return outcome.result(timeout=seconds)
    except futures.TimeoutError:  # the builtin TimeoutError only from Python 3.11
        raise TaskTimeoutError(f"its check took longer than {seconds:g} s") from None


def _in_process(groups: Sequence[Group], check: Callable[[Group], T]) -> Iterator[tuple[int, T | Unfinished]]:
    for index, group in enumerate(groups):
        try:
            yield index, check(group)
        except TaskTimeoutError as error:
            yield index, _timed_out(error, retried=False)


def _in_processes(
    groups: Sequence[Group], check: Callable[[Group], T], jobs: int
) -> Iterator[tuple[int, T | Unfinished]]:
    """Ctrl-C stops them all at once: the workers leave it to this process, which ends them."""
    pool = futures.ProcessPoolExecutor(max_workers=min(jobs, len(groups)), initializer=_leave_interrupts_to_the_parent)
    try:
        submitted = {pool.submit(check, group): index for index, group in enumerate(groups)}
        for future in futures.as_completed(submitted):
            index = submitted[future]
            try:
                yield index, future.result()
            except TaskTimeoutError as error:
                yield index, _timed_out(error, retried=False)
            except Exception as error:  # a process that died (BrokenProcessPool) must not stop the fleet
                yield index, _failed(error)
    except BaseException:  # Ctrl-C, or the reader gone: no task is worth finishing
        pool.shutdown(wait=False, cancel_futures=True)
        for worker in multiprocessing.active_children():
            worker.terminate()
        raise
    pool.shutdown()


def _leave_interrupts_to_the_parent() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _on_dask(
    groups: Sequence[Group], check: Callable[[Group], T], address: str
) -> Iterator[tuple[int, T | Unfinished]]:
    """Each recording a task on the cluster whose scheduler is at ``address``; connects before the first
    result is asked for, so that a missing Dask or scheduler is raised at once."""
    try:
        from distributed import KilledWorker
        from distributed import as_completed as finished
    except ImportError:
        raise FleetUnavailableError(None, "Dask's distributed package is not installed", INSTALL_HINT) from None
    logging.getLogger("distributed").setLevel(logging.ERROR)  # its rescheduling notices are ours to report
    client = _connect(address)

    def results() -> Iterator[tuple[int, T | Unfinished]]:
        with client:
            submitted = {client.submit(check, list(g), retries=1, pure=False): i for i, g in enumerate(groups)}
            for future in finished(submitted, loop=client.loop):  # type: ignore[no-untyped-call]
                index = submitted[future]
                try:
                    yield index, future.result()
                except KilledWorker:
                    why = "the workers that ran it died each time (see the scheduler's allowed-failures)"
                    yield index, Unfinished(why, UnfinishedCause.WORKERS_DIED)
                except TaskTimeoutError as error:
                    yield index, _timed_out(error, retried=True)
                except Exception as error:  # anything a task raised is that recording's outcome, not the fleet's
                    yield index, _failed(error)

    return results()


#: The transports a scheduler is reached by from another process (inproc is within one process; ucx needs
#: UCX's own packages, which the fleet extra does not install).
SCHEMES = ("tcp", "tls", "ws", "wss")
_ADDRESS_HINT = "start one (dask scheduler) and give its address, e.g. tcp://127.0.0.1:8786"


def scheduler_address(address: str) -> str:
    """``address`` when it names a scheduler as ``scheme://host:port`` over a transport of ``SCHEMES``;
    refused here with what is wrong, before Dask sees it (Dask's own refusals of such addresses surface as
    tracebacks from a half-built client)."""
    said = address or "''"
    try:
        parts = urlsplit(address)
        named = "://" in address and parts.scheme in SCHEMES and bool(parts.hostname) and parts.port is not None
    except ValueError:  # a port that is not a number, an IPv6 host without its closing bracket
        named = False
    if not named or parts.path not in ("", "/"):
        raise FleetUnavailableError(
            said, f"not a scheduler address (scheme://host:port, the scheme one of {', '.join(SCHEMES)})", _ADDRESS_HINT
        )
    return address


def _connect(address: str) -> Client:
    """A client of the scheduler at ``address``, within ``CONNECT_SECONDS`` and a little more: Dask's own
    connect timeout does not cover a peer that accepts the connection and never answers (the client waits
    for it for ever), so the client is made on a daemon thread that is left behind if it runs out of time."""
    from distributed import Client

    hint = _ADDRESS_HINT
    address = scheduler_address(address)
    made: list[Client] = []
    failed: list[BaseException] = []

    def make() -> None:
        try:
            made.append(Client(address, timeout=f"{CONNECT_SECONDS}s", set_as_default=False))  # type: ignore[no-untyped-call]
        except BaseException as error:  # handed to the caller's thread
            failed.append(error)

    maker = threading.Thread(target=make, name="tfx-dask-connect", daemon=True)
    maker.start()
    maker.join(CONNECT_SECONDS + 2)
    if made:
        return made[0]
    if not failed:
        raise FleetUnavailableError(address, f"the Dask scheduler did not answer within {CONNECT_SECONDS} s", hint)
    error = failed[0]
    if isinstance(error, ValueError):
        raise FleetUnavailableError(address, f"not a scheduler address ({error})", hint) from None
    if isinstance(error, OSError):  # refused, unreachable, timed out
        raise FleetUnavailableError(address, f"cannot reach the Dask scheduler ({error})", hint) from None
    raise error


def _timed_out(error: TaskTimeoutError, retried: bool) -> Unfinished:
    return Unfinished(f"{error}{', twice' if retried else ''}", UnfinishedCause.TIMED_OUT)


def _failed(error: BaseException) -> Unfinished:
    said = " ".join(str(error).split())  # Dask's messages run over several lines
    return Unfinished(f"its task failed ({type(error).__name__}: {said})", UnfinishedCause.FAILED)
