"""The result types: ``Shots`` of the fast path as statuses, rows and tables, and ``Shot.history``."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from analytic import fast
from analytic.design_file import default_design
from analytic.result import SHOT_COLUMNS, Shot, Shots, Status
from support import failure_designs, table_ii_sample


@pytest.fixture(scope="module")
def designs():
    # Every failure status, and designs that throw.
    return table_ii_sample(6, seed=11) + list(failure_designs().values())


@pytest.fixture(scope="module")
def shots(designs):
    return fast.shoot(designs, loads=True)


def test_statuses_are_status_members(shots, designs):
    assert shots.status.dtype == object and len(shots) == len(designs)
    assert all(isinstance(status, Status) for status in shots.status)
    assert set(shots.status) >= set(failure_designs())
    assert np.array_equal(shots.ok, [status is Status.OK for status in shots.status])


def test_each_row_is_that_designs_shot_as_the_fast_path_gives_it(shots, designs):
    singles = fast.simulate_fast_many(designs)
    for i, single in enumerate(singles):
        got = shots[i]
        assert got.design is designs[i] and got.history is None
        assert got.to_json() == single.to_json(), designs[i].name
    assert shots[-1].to_json() == singles[-1].to_json()
    with pytest.raises(IndexError):
        shots[len(designs)]


def test_shots_of_packed_rows_cannot_be_indexed(designs):
    packed = fast.shoot(fast.pack_many(designs[:2]))
    assert packed.designs is None
    with pytest.raises(TypeError, match="know no designs"):
        packed[0]


def test_the_table_holds_every_column_in_its_type(shots):
    table = shots.to_arrow()
    assert table.column_names == list(SHOT_COLUMNS) and table.num_rows == len(shots)
    assert table["status"].to_pylist() == [status.value for status in shots.status]
    assert np.array_equal(table["release_vy"].to_numpy(), shots.release_velocity[:, 1], equal_nan=True)
    assert np.array_equal(table["peak_sling_tension"].to_numpy(), shots.peak_sling_tension, equal_nan=True)
    assert table.schema.field("steps").type == "int64"
    frame = shots.to_pandas()
    assert list(frame.columns) == list(SHOT_COLUMNS) and (frame["status"] == "ok").sum() == shots.ok.sum()


def test_a_fast_shot_has_no_history_and_a_reference_one_has_all_of_it(designs):
    from analytic import simulate

    assert fast.simulate_fast(designs[0]).history is None
    shot = simulate(designs[0])
    history, n = shot.history, len(shot.history.t)
    assert history.q.shape == history.qdot.shape == (n, 3) and history.path.shape == (n, 2)
    assert history.stage.shape == history.sling_tension.shape == history.axle_load.shape == (n,)
    assert history.energy.total.shape == (n,) and history.flight_path.shape == (len(history.flight_t), 2)
    # Shots built by hand (a stand-in batch) know no designs either.
    stand_in = Shots(**{name: np.full(1, np.nan) for name in Shots.__dataclass_fields__
                        if name not in ("designs", "shot_at")})
    with pytest.raises(TypeError):
        stand_in[0]


# --------------------------------------------------------------------------- #
# Shot's own __init__: the dataclass's fields, filled at once
# --------------------------------------------------------------------------- #

def test_every_field_after_the_message_has_a_plain_default():
    # Shot.__init__ fills them from one dict of defaults: a default_factory would be shared.
    later = dataclasses.fields(Shot)[3:]
    assert [f.name for f in dataclasses.fields(Shot)[:3]] == ["design", "status", "message"]
    assert all(f.default is not dataclasses.MISSING and f.default_factory is dataclasses.MISSING for f in later)


def test_a_shot_holds_what_it_was_given_and_none_for_the_rest():
    design = default_design()
    shot = Shot(design, Status.OK, "thrown", apex_height=3.5, warnings=["a", "a"])
    assert (shot.design, shot.status, shot.message, shot.apex_height) == (design, Status.OK, "thrown", 3.5)
    assert shot.release_time is None and shot.history is None and shot.warnings == ("a",)
    assert list(vars(shot)) == [f.name for f in dataclasses.fields(Shot)]


def test_an_unknown_field_is_refused_as_the_dataclass_would():
    with pytest.raises(TypeError, match="unexpected keyword arguments: apex, rnage"):
        Shot(default_design(), Status.OK, "thrown", rnage=3.0, apex=1.0)


def test_a_shot_stays_frozen_and_copies_replaces_and_pickles_whole():
    shot = Shot(default_design(), Status.OK, "thrown", apex_height=3.5, landing_position=np.array([45.0, -0.6]))
    with pytest.raises(dataclasses.FrozenInstanceError):
        shot.apex_height = 4.0
    moved = dataclasses.replace(shot, apex_height=4.0)
    assert moved.apex_height == 4.0 and moved.landing_position is shot.landing_position
    back = pickle.loads(pickle.dumps(shot))
    assert back.apex_height == 3.5 and back.range == shot.range == 45.0
