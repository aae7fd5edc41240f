"""The engine's Chipmunk objects over many shots in one process: every space the collector sees is whole.

pymunk frees a space, a body or a joint when the cyclic collector takes it (each
holds a handle to itself), in whatever order the collector finds them, and
Chipmunk aborts the process where a space and its bodies disagree
(``cpSpaceRemoveBody``: "Cannot remove a body that was not added to the space").
A cross-check worker runs one shot after another, so an earlier shot's space
may be freed in the middle of a later one. This runs engine shots of every kind
back to back in a child process with the older generations collected every
two thousand allocations (many times a shot), and checks after each such
collection that each live space's bodies and joints point back at it and at
bodies still alive, and that no body or joint points at a space that is gone.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

#: The child: the shots, then the problems found (a count per kind) as JSON on its last line.
CHILD = textwrap.dedent('''
    import collections, gc, json, sys
    import pymunk
    from pymunk._chipmunk import ffi, lib
    from crosscheck.cases import default_suite
    from engine_model import EngineError, simulate

    problems = collections.Counter()
    collections_seen = [0]

    def address(handle):
        return int(ffi.cast("uintptr_t", handle))

    def members(each, space, iterator):
        found = []
        each(space, iterator, ffi.new_handle(found))
        return found

    def check(phase, info):
        if phase != "stop" or info["generation"] == 0:   # (the young objects alone: too many to look at each)
            return
        collections_seen[0] += 1
        objects = gc.get_objects()
        spaces = [o for o in objects if isinstance(o, pymunk.Space)]
        live = {address(s._space) for s in spaces}
        bodies = {address(o._body) for o in objects if isinstance(o, pymunk.Body)}
        for space in spaces:
            for body in members(lib.cpSpaceEachBody, space._space, lib.ext_cpSpaceBodyIteratorFunc):
                if address(body) not in bodies:
                    problems["a space holds a body no Body owns"] += 1
                elif address(lib.cpBodyGetSpace(body)) != address(space._space):
                    problems["a space holds a body that points at another space"] += 1
            for joint in members(lib.cpSpaceEachConstraint, space._space, lib.ext_cpSpaceConstraintIteratorFunc):
                if {address(lib.cpConstraintGetBodyA(joint)), address(lib.cpConstraintGetBodyB(joint))} - bodies:
                    problems["a space holds a joint on a freed body"] += 1
        for o in objects:
            handle = (lib.cpBodyGetSpace(o._body) if isinstance(o, pymunk.Body)
                      else lib.cpConstraintGetSpace(o._constraint) if isinstance(o, pymunk.Constraint) else ffi.NULL)
            if handle != ffi.NULL and address(handle) not in live:
                problems["a body or joint points at a space that is gone"] += 1

    names = sys.argv[1:]
    cases = {case.name: case for case in default_suite(0)}
    gc.callbacks.append(check)
    gc.set_threshold(500, 4, 2)   # an older generation collected every 2,000 allocations
    for name in names:
        try:
            simulate(cases[name].design)
        except EngineError:
            pass
    gc.collect()
    print(json.dumps({"problems": dict(problems), "collections": collections_seen[0]}))
''')

#: One shot of each thing the engine does to its space: a plain swing (the groove removed at
#: lift-off), friction (its joints renewed after the opening half step, the base's removed), a
#: rolling frame (the sling and projectile removed for the run after release), a bolted and a
#: floating arm (its carriage and slider), drag in the swing, and failures that stop early.
NAMES = ("table3", "table3-all-losses", "table3-rolling-10kg-all-losses", "paper-table3-fixed-all-losses",
         "table3-floating-arm-all-losses", "swing-drag-headwind", "fails-never_lifts_off",
         "fails-hits_base_before_release", "table3-61deg", "sampled-arm-stalls")


@pytest.mark.slow
def test_every_space_the_collector_sees_is_whole_over_many_shots():
    done = subprocess.run([sys.executable, "-c", CHILD, *NAMES], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]   # Chipmunk's abort ends the process (SIGABRT: -6)
    found = json.loads(done.stdout.splitlines()[-1])
    assert found["collections"] > 50   # the check ran at collections mid-shot, not only at the end
    assert found["problems"] == {}
