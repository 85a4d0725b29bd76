"""Where a fleet's recordings are checked: here, in local processes (``--jobs``), or on an existing Dask
cluster (``--dask``). Each executor yields ``(index, BagReport)`` as recordings finish; a check that did not
finish (its process or worker died, it ran out of ``--timeout``, it raised) is a report that says so.

Dask is the engine: tasks are submitted with ``retries=1`` (a task that raised, e.g. timed out, runs
once more), and a worker that dies is handled by the scheduler, which runs its tasks elsewhere until
they have killed ``distributed.scheduler.allowed-failures`` workers (set it to 1 on the scheduler for
"retried once"), then reports ``KilledWorker``. The timeout is kept inside the task: a thread runs the
check and the task gives up after the time (Python cannot stop a thread: the abandoned check keeps its
worker busy until it ends)."""

from __future__ import annotations

import logging
import multiprocessing
import signal
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import TYPE_CHECKING

from tftools.cli.common import UsageError
from tftools.cli.deadline import CheckGroup, CheckTimeoutError

if TYPE_CHECKING:
    from distributed import Client

    from tftools.analysis.wtf.fleet import BagReport

Results = Iterator[tuple[int, "BagReport"]]

INSTALL_HINT = "install the extra: pip install 'tftools[fleet]'"
CONNECT_SECONDS = 5
_WORKER_HINT = "check that every worker has this tftools installed, and see the worker's log"


def in_process(groups: Sequence[Sequence[str]], check: CheckGroup) -> Results:
    for index, group in enumerate(groups):
        try:
            yield index, check(group)
        except CheckTimeoutError as error:
            yield index, _timed_out(group, error, retried=False)


def in_processes(groups: Sequence[Sequence[str]], check: CheckGroup, jobs: int) -> Results:
    """Ctrl-C stops them all at once: the workers leave it to this process, which ends them."""
    pool = ProcessPoolExecutor(max_workers=min(jobs, len(groups)), initializer=_leave_interrupts_to_the_parent)
    try:
        futures = {pool.submit(check, group): index for index, group in enumerate(groups)}
        for future in as_completed(futures):
            index = futures[future]
            try:
                yield index, future.result()
            except CheckTimeoutError as error:
                yield index, _timed_out(groups[index], error, retried=False)
            except Exception as error:  # a process that died (BrokenProcessPool) must not stop the fleet
                yield index, _failed(groups[index], error)
    except BaseException:  # Ctrl-C, or the reader gone: no check is worth finishing
        pool.shutdown(wait=False, cancel_futures=True)
        for worker in multiprocessing.active_children():
            worker.terminate()
        raise
    pool.shutdown()


def _leave_interrupts_to_the_parent() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def on_dask(groups: Sequence[Sequence[str]], check: CheckGroup, address: str) -> Results:
    """Each recording a task on the cluster whose scheduler is at ``address``."""
    from tftools.analysis.wtf.fleet import unchecked

    try:
        from distributed import KilledWorker
        from distributed import as_completed as finished
    except ImportError:
        raise UsageError("--dask needs Dask's distributed package, which is not installed", INSTALL_HINT) from None
    logging.getLogger("distributed").setLevel(logging.ERROR)  # its rescheduling notices are ours to report
    with _connect(address) as client:
        futures = {client.submit(check, list(group), retries=1, pure=False): i for i, group in enumerate(groups)}
        for future in finished(futures, loop=client.loop):  # type: ignore[no-untyped-call]
            index = futures[future]
            group = groups[index]
            try:
                yield index, future.result()
            except KilledWorker:
                why = "the workers that ran it died each time (see the scheduler's allowed-failures)"
                yield index, unchecked(tuple(group), why, "check it alone (tfx wtf BAG): it may crash or exhaust them")
            except CheckTimeoutError as error:
                yield index, _timed_out(group, error, retried=True)
            except Exception as error:  # anything a task raised is that recording's outcome, not the fleet's
                yield index, _failed(group, error)


def _connect(address: str) -> Client:
    from distributed import Client

    hint = "start one (dask scheduler) and give its address, e.g. --dask tcp://127.0.0.1:8786"
    try:
        return Client(address, timeout=f"{CONNECT_SECONDS}s", set_as_default=False)  # type: ignore[no-untyped-call]
    except ValueError as error:
        raise UsageError(f"--dask {address}: not a scheduler address ({error})", hint) from None
    except OSError as error:  # refused, unreachable, timed out
        raise UsageError(f"--dask {address}: cannot reach the Dask scheduler ({error})", hint) from None


def _timed_out(group: Sequence[str], error: CheckTimeoutError, retried: bool) -> BagReport:
    from tftools.analysis.wtf.fleet import unchecked

    why = f"{error}{', twice' if retried else ''}"
    return unchecked(tuple(group), why, "raise --timeout, or check it alone (tfx wtf BAG)")


def _failed(group: Sequence[str], error: BaseException) -> BagReport:
    from tftools.analysis.wtf.fleet import unchecked

    said = " ".join(str(error).split())  # Dask's messages run over several lines
    return unchecked(tuple(group), f"its task failed ({type(error).__name__}: {said})", _WORKER_HINT)
