"""The benchmarks: both models and both analytic paths timed as ratios to baselines measured in the same run.

``python -m benchmarks [DESIGN.toml] [--json] [--plot FILE.png] [--cold]
[--baseline REV] [--markdown FILE.md]`` (also ``python -m analytic bench``).
Six parts, each in its own module:

* **paths** (``paths``): the analytic model's two paths on the same designs
  (``designs``: the paper's optimum and a seeded uniform sample over its
  Table II bounds, kept whether they throw or fail). Each design's time is
  the best of ``repeat`` runs; reported: the median shot of the reference
  (``simulate(histories=False)``, scipy's DOP853 stepped from Python: the
  same summary the fast path gives), of the reference with its histories
  (what ``python -m analytic simulate`` runs) and of the fast path, with and
  without the peak loads (what finding them costs, in time and in
  evaluations); the speed-up as the ratio of medians; the batch's throughput
  on every thread and on one; and the agreement of the two paths
  (``crosscheck.comparison.compare_shots``, the cross-check's own comparer).
  Also, in ``scipy_route``, scipy with the model compiled as its right-hand
  side, the cheaper route not taken.
* **friction** (``paths``): the same designs with typical losses
  (``designs.TYPICAL_LOSSES``) on both paths: the time per shot and the
  evaluations as ratios to the ideal machine's in the same run, and the
  paths' agreement with friction.
* **rolling** (``paths``): the same designs on a rolling frame
  (``designs.ROLLING_FRAME``), without and with the typical losses: the
  paths' agreement (outcomes and range), untimed.
* **models** (``models``): one design through every way the project can
  shoot it, each as a multiple of one reference shot of it (the baseline):
  the reference at a tighter tolerance and without histories, the fast path,
  the engine at its default step and at twice it.
* **compile** (``measure``): loading the fast path's machine code from the
  disk cache; with ``--cold``, compiling it in a fresh process with an empty
  cache (tens of seconds of CPU), apart from every shot time.
* **sweep throughput** (``sweep``): one sweep (``--sweep-shots`` designs
  drawn over the paper's problem box, chunks of ``--sweep-chunk``) end to
  end, Parquet written, in this process on every core and on a 2-worker Dask
  ``LocalCluster``: shots per second of each, their ratio (what the cluster
  loses to scheduling and moving results), the cluster's start-up apart,
  each worker's peak memory, and whether the two tables are identical.

``suite.run`` runs them all; ``baseline`` writes an earlier commit's sources
out and ``paired`` times them beside this checkout's, one worker process
(``paired_worker``) per side pinned to the same CPU, interleaved shot by
shot, so that the machine's drift falls on both sides alike; ``report`` and ``plot`` write the
text, the documentation's performance page and the figure; ``cli`` is the
command line. This package sits above everything it measures: nothing in
``analytic``, ``engine_model`` or ``crosscheck`` imports it.
"""
