"""A Dask worker preload for the tests (``dask worker --preload tests/cli/dask_hook.py``): recordings whose
name holds ``slow_once`` hang on their first try, those with ``slow_always`` take 3 s on every try; each
try leaves ``started-<worker pid>-<n>-<name>`` in ``$TFX_TEST_MARKS``, so a test knows which worker to kill."""

from __future__ import annotations

import functools
import inspect
import os
import time
from pathlib import Path
from typing import Any

from tftools.analysis.wtf import fleet

_check_group = inspect.unwrap(fleet._check_group)  # dask may load a preload twice


@functools.wraps(_check_group)
def _tried(query: Any, progress: Any, paths: list[str]) -> fleet.BagReport:
    name = Path(paths[0]).name
    marks = Path(os.environ["TFX_TEST_MARKS"])
    tries = len(list(marks.glob(f"started-*-{name}")))
    (marks / f"started-{os.getpid()}-{tries}-{name}").touch()
    if "slow_once" in name and tries == 0:
        time.sleep(120)  # until the test kills this worker
    elif "slow_always" in name:
        time.sleep(3)
    report: fleet.BagReport = _check_group(query, progress, paths)
    return report


fleet._check_group = _tried  # type: ignore[assignment]  # (tasks name it: the worker unpickles this one)
