"""A map over worker processes in which a worker's death costs only the task it was running.

``concurrent.futures.ProcessPoolExecutor`` breaks as a whole when one worker
dies (``BrokenProcessPool``): every pending task fails with it, and which task
killed it is not said. An engine run is C code (Chipmunk) that can abort the
process, so the cross-check keeps its own small pool: each worker has a pipe
and runs one task at a time, the parent knows which task each worker holds,
and a worker that dies is replaced; its task's result is a ``WorkerLost`` that
names how it died, and the other tasks go on.
"""

from __future__ import annotations

import multiprocessing
import signal
import traceback
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any


@dataclass(frozen=True)
class WorkerLost:
    """The result of a task whose worker process died: ``reason`` says how (``"died with SIGABRT"``,
    ``"exited with status 3"``)."""

    reason: str


class TaskError(RuntimeError):
    """A task raised in its worker: the worker's traceback, as text."""


def _serve(connection: Connection, function: Callable) -> None:
    """A worker: run ``function(*task)`` for each ``(index, task)`` received until ``None``."""
    while True:
        message = connection.recv()
        if message is None:
            return
        index, task = message
        try:
            connection.send((index, True, function(*task)))
        except Exception:   # sent to the parent, which raises it: a worker's bug is not a lost worker
            connection.send((index, False, traceback.format_exc()))


def _death(exitcode: int | None) -> str:
    """How a process with ``exitcode`` ended, in words."""
    if exitcode is not None and exitcode < 0:
        try:
            return f"died with {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"died with signal {-exitcode}"
    return f"exited with status {exitcode}"


def map_in_processes(function: Callable, tasks: Sequence[tuple], workers: int,
                     done: Callable[[], Any] = lambda: None) -> list:
    """``[function(*task) for task in tasks]`` on ``workers`` processes, in the tasks' order.

    Parameters
    ----------
    function : called in a worker process with each task's arguments; its result is sent back
        (pickled).
    tasks : each a tuple of arguments.
    workers : processes at once (at least 1).
    done : called in this process after each task ends (a progress bar's update).

    Returns
    -------
    list
        Each task's result, or a ``WorkerLost`` where its worker died running it.

    Raises
    ------
    TaskError
        A task raised: the exception is a bug, not a lost worker; its traceback is the message.
    """
    context = multiprocessing.get_context()
    results: list = [None] * len(tasks)
    waiting = deque(range(len(tasks)))
    running: dict[Connection, tuple[multiprocessing.Process, int]] = {}
    idle: list[tuple[Connection, multiprocessing.Process]] = []

    def start() -> tuple[Connection, multiprocessing.Process]:
        parent, child = context.Pipe()
        process = context.Process(target=_serve, args=(child, function), daemon=True)
        process.start()
        child.close()
        return parent, process

    try:
        while waiting or running:
            while waiting and len(running) < max(1, workers):
                connection, process = idle.pop() if idle else start()
                index = waiting.popleft()
                connection.send((index, tasks[index]))
                running[connection] = (process, index)
            ready = wait([*running, *(process.sentinel for process, _ in running.values())])
            for connection in list(running):
                process, index = running[connection]
                if connection in ready or connection.poll():
                    try:
                        _, ok, result = connection.recv()
                    except EOFError:   # died before its result came: the sentinel says how
                        process.join()
                        results[index] = WorkerLost(_death(process.exitcode))
                        connection.close()
                    else:
                        if not ok:
                            raise TaskError(result)
                        results[index] = result
                        idle.append((connection, process))
                    del running[connection]
                    done()
                elif process.sentinel in ready:
                    process.join()
                    results[index] = WorkerLost(_death(process.exitcode))
                    connection.close()
                    del running[connection]
                    done()
    finally:
        for connection, process in idle + [(c, p) for c, (p, _) in running.items()]:
            try:
                connection.send(None)
            except OSError:
                pass
            connection.close()
            process.join(timeout=5)
            if process.is_alive():
                process.kill()
                process.join()
    return results
