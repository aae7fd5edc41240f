"""One side of a paired benchmark: a process that times the analytic paths of the sources it imports.

Run as a script (``python benchmarks/paired_worker.py``) with ``PYTHONPATH`` set to a checkout's
sources, this checkout's or a baseline commit's; ``benchmarks.paired`` starts one for each side
and alternates its requests between them, so the two sides are timed within milliseconds of
each other. It reads one JSON request per line on stdin and answers one JSON line on stdout:

``{"op": "setup", "count": N, "seed": S, "batch_repeat": R}``
    build the benchmark's designs, compile (or load) the fast path, and answer each design's
    fast-path range (the driver checks the two sides shoot the same designs) and the CPUs.
``{"op": "time", "what": "fast" | "fast_no_loads" | "reference", "indices": [...], "repeat": K}``
    each listed design's best time of K shots, s.
``{"op": "batch"}``
    one batch (``fast.shoot``) of every design, ``batch_repeat`` times over, on every thread, s.
``{"op": "batch_one"}``
    the same batch on one thread, on the pinned CPU.
``{"op": "pin", "cpu": C}``
    run the single shots on CPU C only (the batch runs on every CPU).

It uses only what every commit since the fast path's first has: ``analytic.fast``'s
``simulate_fast``, ``pack_many``, ``shoot`` and ``compile``, the reference's ``simulate`` (``REFERENCES``), and
the benchmark's design sample (``DESIGN_SAMPLES``).
A commit's fast path without a ``loads`` switch times its only shot for ``fast_no_loads``.
"""

from __future__ import annotations

import sys

if __name__ == "__main__":     # run as a script: import the sources on PYTHONPATH, not this folder's modules
    del sys.path[0]

import inspect
import json
import math
import os
import time

import numpy as np


#: Where the benchmark's design sample has lived, newest first.
DESIGN_SAMPLES = ("benchmarks.designs", "crosscheck.benchmark", "analytic.bench")
#: Where the reference path's ``simulate`` has lived, newest first.
REFERENCES = ("analytic.reference", "analytic.simulate")


def _own(name: str):
    """Module ``name`` of the sources (the working folder), or None where they lack it. A copy of this
    project installed elsewhere on the path does not count, nor does it get to run: an editable
    install's finder would hand out its own module for any that the sources lack (``analytic.reference``
    to a commit that has only ``analytic.simulate``), so each package on the way is located before
    anything of it is imported."""
    import importlib
    import importlib.util
    from pathlib import Path

    sources, parts = Path.cwd().resolve(), name.split(".")
    for depth in range(1, len(parts) + 1):
        try:
            spec = importlib.util.find_spec(".".join(parts[:depth]))
        except ImportError:
            return None
        if spec is None or spec.origin is None or not Path(spec.origin).resolve().is_relative_to(sources):
            return None
    return importlib.import_module(name)


def _designs(count: int, seed: int) -> list:
    """The benchmark's designs, from the first of ``DESIGN_SAMPLES`` the sources hold."""
    for name in DESIGN_SAMPLES:
        module = _own(name)
        if module is not None and hasattr(module, "bench_designs"):
            return module.bench_designs(count, seed)
    raise ImportError(f"none of {', '.join(DESIGN_SAMPLES)} in {os.getcwd()}")


def _reference():
    """The reference path's ``simulate``, from the first of ``REFERENCES`` the sources hold."""
    for name in REFERENCES:
        module = _own(name)
        if module is not None:
            return module.simulate
    raise ImportError(f"none of {', '.join(REFERENCES)} in {os.getcwd()}")


class Side:
    """The timed calls of one checkout's sources."""

    def __init__(self, count: int, seed: int, batch_repeat: int):
        from analytic import fast

        self.fast = fast
        self.compile_s = fast.compile()
        self.designs = _designs(count, seed)
        self.rows = np.tile(fast.pack_many(self.designs), (batch_repeat, 1))
        simulate = _reference()
        has_loads = "loads" in inspect.signature(fast.simulate_fast).parameters
        no_loads = (lambda d: fast.simulate_fast(d, loads=False)) if has_loads else fast.simulate_fast
        self.calls = {"fast": fast.simulate_fast, "fast_no_loads": no_loads,
                      "reference": lambda d: simulate(d, histories=False)}
        self.all_cpus = sorted(os.sched_getaffinity(0))
        self.batch()        # the batch's threads start here, before any pin narrows the CPUs they inherit

    def ranges(self) -> list:
        shots = [self.fast.simulate_fast(d) for d in self.designs]
        return [None if s.range is None else float(s.range) for s in shots]

    def time(self, what: str, indices: list, repeat: int) -> list:
        call, best = self.calls[what], []
        for i in indices:
            design, fastest = self.designs[i], math.inf
            for _ in range(repeat):
                began = time.perf_counter()
                call(design)
                fastest = min(fastest, time.perf_counter() - began)
            best.append(fastest)
        return best

    def batch_one(self) -> float:
        """One batch on one thread (the CPU the shots are pinned to): the kernel's own speed."""
        import numba

        began = time.perf_counter()
        if "threads" in inspect.signature(self.fast.shoot).parameters:
            self.fast.shoot(self.rows, threads=1)
        else:                                  # a numba-parallel batch
            threads = numba.get_num_threads()
            numba.set_num_threads(1)
            try:
                self.fast.shoot(self.rows)
            finally:
                numba.set_num_threads(threads)
        return time.perf_counter() - began

    def batch(self) -> float:
        pinned = os.sched_getaffinity(0)
        os.sched_setaffinity(0, self.all_cpus)
        try:
            began = time.perf_counter()
            self.fast.shoot(self.rows)
            return time.perf_counter() - began
        finally:
            os.sched_setaffinity(0, pinned)


def serve(requests, answer) -> None:
    """Answer each request line until the input ends."""
    side = None
    for line in requests:
        request = json.loads(line)
        op = request["op"]
        if op == "setup":
            side = Side(request["count"], request["seed"], request["batch_repeat"])
            reply = {"designs": len(side.designs), "ranges": side.ranges(), "compile_s": side.compile_s,
                     "cpus": side.all_cpus}
        elif op == "time":
            reply = {"seconds": side.time(request["what"], request["indices"], request["repeat"])}
        elif op == "batch":
            reply = {"seconds": side.batch(), "shots": len(side.rows)}
        elif op == "batch_one":
            reply = {"seconds": side.batch_one(), "shots": len(side.rows)}
        elif op == "pin":
            os.sched_setaffinity(0, [request["cpu"]])
            reply = {"cpu": request["cpu"]}
        else:
            reply = {"error": f"unknown op {op!r}"}
        answer.write(json.dumps(reply) + "\n")
        answer.flush()


if __name__ == "__main__":
    answers = os.fdopen(os.dup(sys.stdout.fileno()), "w")
    sys.stdout = sys.stderr          # whatever the sources print stays out of the answers
    serve(sys.stdin, answers)
