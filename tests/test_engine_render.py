"""Frames: how many, how big, where the projectile is drawn, and byte-identical on a second run."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from analytic.design_file import default_design
from engine_model.render import (FRAME_SIZE, PROJECTILE_COLOUR, FrameState, draw_frame, frame_times,
                                 render_shot)
from engine_model import simulate


@pytest.fixture(scope="module")
def shot():
    # A coarser step than the default keeps this quick; the frames do not care.
    return simulate(default_design(), dt=4e-4)


def _png_size_and_chunks(path) -> tuple[tuple[int, int], list[bytes]]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    chunks, i = [], 8
    while i < len(data):
        length = struct.unpack(">I", data[i:i + 4])[0]
        chunks.append(data[i + 4:i + 8])
        i += 12 + length
    width, height = struct.unpack(">II", data[16:24])
    return (width, height), chunks


def test_frames_at_fixed_intervals_up_to_the_landing(shot, tmp_path):
    fps = 4.0
    paths = render_shot(shot, tmp_path, fps=fps, progress=False)
    # Every 0.25 s from 0 through the landing, and the landing itself.
    expected = math.floor(shot.landing_time * fps) + 1 + (shot.landing_time * fps % 1 > 1e-9)
    assert len(paths) == expected
    assert [p.name for p in paths] == [f"frame_{i:05d}.png" for i in range(expected)]
    assert frame_times(shot, fps)[-1] == shot.landing_time
    size, chunks = _png_size_and_chunks(paths[-1])
    assert size == FRAME_SIZE == (960, 540)
    assert not {b"tEXt", b"iTXt", b"zTXt", b"tIME"} & set(chunks)  # nothing that varies between runs


def test_the_same_shot_renders_byte_identical_frames(shot, tmp_path):
    first = render_shot(shot, tmp_path / "a", fps=2.0, gif=True, progress=False)
    second = render_shot(shot, tmp_path / "b", fps=2.0, gif=True, progress=False)
    for a, b in zip(first + [tmp_path / "a" / "shot.gif"], second + [tmp_path / "b" / "shot.gif"], strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name


def test_the_projectile_is_drawn_where_it_is(shot):
    # A hand-made state and view: the view spans x -2..14 m (16 m over 960 px,
    # 60 px/m) and y -1..8 m (9 m over 540 px, 60 px/m). The projectile at
    # (5, 3) m falls at column (5 + 2) * 60 = 420, row (8 - 3) * 60 = 300.
    state = FrameState(time=1.0, label="test", long_tip=np.array([-0.5, 0.5]), short_tip=np.array([0.2, -0.2]),
                       counterweight=np.array([0.2, -0.4]), projectile=np.array([5.0, 3.0]),
                       sling_attached=False, trace=np.array([[0.0, -0.59], [5.0, 3.0]]))
    pixels = draw_frame(shot.design, state, (-2.0, 14.0, -1.0, 8.0)).astype(int)
    assert pixels.shape == (FRAME_SIZE[1], FRAME_SIZE[0], 4)
    red = tuple(int(PROJECTILE_COLOUR[i:i + 2], 16) for i in (1, 3, 5))
    rows, cols = np.nonzero(np.all(np.abs(pixels[:, :, :3] - red) < 40, axis=2))
    assert len(rows) > 20, "projectile not drawn"
    assert (cols.mean(), rows.mean()) == pytest.approx((420.0, 300.0), abs=1.0)
