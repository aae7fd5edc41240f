"""Long tools run as jobs: one thread each, with progress and cancel, bounded in time and in number per client."""

from __future__ import annotations

import itertools
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable

from analytic.design import DesignError

#: How long a job may run, s: the cross-check of a large machine takes tens of seconds.
JOB_SECONDS = 120.0
#: Jobs one client may have running at once, and all clients together (the machine's cores).
JOBS_PER_CLIENT = 1
JOBS_IN_ALL = 2
#: Finished jobs kept for their clients to collect, at most.
KEPT = 64


class Cancelled(Exception):
    """The job was cancelled, or ran past ``JOB_SECONDS``."""


@dataclass
class Job:
    """One tool's run: its progress (0-1), its state and, when done, its result or error."""

    id: str
    client: str
    tool: str
    started: float = field(default_factory=time.monotonic)
    progress: float = 0.0
    state: str = "running"   # running, done, error, cancelled
    result: Any = None
    error: dict[str, str] | None = None
    cancel: threading.Event = field(default_factory=threading.Event)
    #: Set when the job's thread has returned: until then it counts against the limits, cancelled or not.
    ended: threading.Event = field(default_factory=threading.Event)

    def check(self) -> None:
        """Raise ``Cancelled`` if the job was cancelled or is over its time."""
        if self.cancel.is_set():
            raise Cancelled("cancelled")
        if time.monotonic() - self.started > JOB_SECONDS:
            raise Cancelled(f"stopped after {JOB_SECONDS:g} s, the longest a tool may run")

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "tool": self.tool, "state": self.state, "progress": self.progress,
                "result": self.result, "error": self.error, "ended": self.ended.is_set()}


class TooMany(Exception):
    """A client (or all of them) already has as many jobs running as allowed."""


class Jobs:
    """The jobs of one server."""

    def __init__(self) -> None:
        self._jobs: dict[str, Job] = {}
        self._lock = threading.Lock()
        self._ids = itertools.count(1)

    def start(self, client: str, tool: str, work: Callable[[Job], Any]) -> Job:
        """Run ``work(job)`` in a thread; ``TooMany`` when the limits are reached."""
        with self._lock:
            # A cancelled job whose thread still works (a tool checks between its steps) still counts.
            working = [job for job in self._jobs.values() if not job.ended.is_set()]
            mine = [job for job in working if job.client == client]
            if len(mine) >= JOBS_PER_CLIENT:
                raise TooMany(f"a tool is already running for this page (at most {JOBS_PER_CLIENT}); cancel it "
                              f"or wait" if any(job.state == "running" for job in mine) else
                              "the cancelled tool is still stopping (at its next step); try again shortly")
            if len(working) >= JOBS_IN_ALL:
                raise TooMany(f"{JOBS_IN_ALL} tools are running on this server; try again shortly")
            job = Job(str(next(self._ids)), client, tool)
            self._jobs[job.id] = job
            for old in [j for j in self._jobs.values() if j.ended.is_set()][:-KEPT]:
                del self._jobs[old.id]
        threading.Thread(target=self._run, args=(job, work), daemon=True).start()
        return job

    @staticmethod
    def _run(job: Job, work: Callable[[Job], Any]) -> None:
        try:
            result = work(job)
            if job.state == "running":
                job.result, job.progress, job.state = result, 1.0, "done"
        except Cancelled as stop:
            job.state, job.error = "cancelled", {"error": str(stop), "field": ""}
        except DesignError as error:
            job.state, job.error = "error", {"error": str(error), "field": error.field}
        except Exception as error:   # a tool's failure is reported on the page, never a dead thread
            job.state, job.error = "error", {"error": f"{type(error).__name__}: {error}", "field": ""}
        finally:
            job.ended.set()

    def get(self, job_id: str) -> Job | None:
        return self._jobs.get(job_id)

    def cancel(self, job_id: str) -> Job | None:
        """Stop a job: at once for its client; its thread stops at its work's next ``check`` (a
        work that does not check runs on to its end, its result dropped), and counts against the
        limits until then."""
        job = self._jobs.get(job_id)
        if job is not None and job.state == "running":
            job.cancel.set()
            job.state, job.error = "cancelled", {"error": "cancelled", "field": ""}
        return job
