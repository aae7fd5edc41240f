"""Where things go in a drawn frame: its view, the close-up's place clear of the trajectory, pixels.

Plain geometry in metres and in fractions of the frame, no artists: every
frame has one view of the whole shot (``camera``), so that the ground keeps
one scale, and the close-up of the machine is as large as the space the
trajectory leaves it (``inset_rects``).
"""

from __future__ import annotations

import numpy as np

from analytic.design import Design
from engine_model.timeline import FrameState

#: Frame size, px (FRAME_INCHES at FRAME_DPI).
FRAME_DPI = 100
FRAME_INCHES = (9.6, 5.4)
FRAME_SIZE = (960, 540)
#: Fraction of the view left around what must be seen.
MARGIN = 0.06
#: The machine's close-up: (left, bottom, width, height) as fractions of the frame: the
#: smallest, used where no larger one keeps clear of the trajectory (``INSET_SCALES``).
INSET = (0.01, 0.52, 0.30, 0.42)
#: Sizes the close-up tries, largest first, as multiples of ``INSET``'s (its top-left corner kept).
INSET_SCALES = (1.8, 1.6, 1.45, 1.3, 1.15, 1.0)
#: The top of the close-up when it goes in the top-right corner, under the header's two lines.
INSET_RIGHT_TOP = 0.86
#: Frames ahead whose trajectory each frame's close-up already keeps clear of, so that it has
#: shrunk out of the projectile's way before the projectile gets there (0.2 s of playback at 25 fps).
INSET_LOOKAHEAD = 5
#: Sizes a frame's close-up may take between its size at the landing and the largest of
#: ``INSET_SCALES``: this many, evenly spaced (the steps of its shrinking).
INSET_STEPS = 25
#: Room under the ground for the scale's labels, as a fraction of what the view must show.
LABEL_ROOM = 0.06
#: Pixels kept between a placed box (close-up, summary) and the trajectory.
CLEARANCE_PX = 8.0


def _fit(x_min: float, x_max: float, y_min: float, y_max: float, aspect: float) -> tuple[float, ...]:
    """The box with a margin, widened to ``aspect`` (width / height), its bottom kept."""
    width, height = x_max - x_min, y_max - y_min
    x_min, x_max = x_min - MARGIN * width, x_max + MARGIN * width
    y_min, y_max = y_min - MARGIN * height, y_max + MARGIN * height
    width, height = x_max - x_min, y_max - y_min
    if width / height < aspect:
        extra = 0.5 * (aspect * height - width)
        x_min, x_max = x_min - extra, x_max + extra
    else:
        y_max = y_min + width / aspect
    return x_min, x_max, y_min, y_max


def machine_reach(design: Design) -> float:
    """How far the machine reaches from its pivot, m: the long arm with the sling, or the short arm
    with the counterweight's link (what every view keeps in sight)."""
    m = design.machine
    return max(m.arm_long + m.sling_length, m.arm_short + m.counterweight_link)


def camera(design: Design, state: FrameState) -> tuple[float, float, float, float]:
    """View (x_min, x_max, y_min, y_max), m: the machine's reach and ``state``'s trace, with a
    margin, widened to the frame's aspect ratio (the base stays at the bottom).

    ``render_shot`` calls it once, with the whole shot's trace, so that every
    frame has the same ground scale."""
    reach, h = machine_reach(design), design.machine.pivot_height
    top = max(reach, state.trace[:, 1].max())
    return _fit(min(state.frame_x - reach, state.trace[:, 0].min()),
                max(state.frame_x + reach, state.trace[:, 0].max()),
                -h - LABEL_ROOM * (top + h), top, FRAME_SIZE[0] / FRAME_SIZE[1])


def machine_view(design: Design, rect: tuple[float, float, float, float] = INSET) -> tuple[float, float, float, float]:
    """The inset's view, m: the machine's reach from the base up, at the aspect ratio of ``rect``."""
    reach, h = machine_reach(design), design.machine.pivot_height
    return _fit(-reach, reach, -h, reach, rect[2] * FRAME_SIZE[0] / (rect[3] * FRAME_SIZE[1]))


def box_pixels(rect: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """A rectangle in fractions of the frame (left, bottom, width, height) as pixels
    (left, top, right, bottom), rows from the top."""
    left, bottom, width, height = rect
    return (left * FRAME_SIZE[0], (1.0 - bottom - height) * FRAME_SIZE[1], (left + width) * FRAME_SIZE[0],
            (1.0 - bottom) * FRAME_SIZE[1])


def crossed(box: tuple[float, float, float, float], points: np.ndarray) -> int:
    """How many of ``points`` ((k, 2) pixels) fall within ``CLEARANCE_PX`` of ``box`` (pixels)."""
    left, top, right, bottom = box
    inside = ((points[:, 0] > left - CLEARANCE_PX) & (points[:, 0] < right + CLEARANCE_PX)
              & (points[:, 1] > top - CLEARANCE_PX) & (points[:, 1] < bottom + CLEARANCE_PX))
    return int(np.count_nonzero(inside))


def overlap(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    """Whether two boxes (left, top, right, bottom) overlap."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def inset_rect(view: tuple[float, float, float, float], trace: np.ndarray) -> tuple[float, float, float, float]:
    """The close-up's rectangle (fractions of the frame): the largest of ``INSET_SCALES`` that keeps
    clear of ``trace`` ((k, 2), m) drawn in ``view``, in the top-left corner where ``INSET`` is, or
    in the top-right one under the header; ``INSET`` where none is clear."""
    points = pixels_of(view, trace)
    left, bottom, width, height = INSET
    top = bottom + height
    for scale in INSET_SCALES:
        w, h = scale * width, scale * height
        for rect in ((left, top - h, w, h), (1.0 - left - w, INSET_RIGHT_TOP - h, w, h)):
            if rect[1] > 0.0 and not crossed(box_pixels(rect), points):
                return rect
    return INSET


def _corner_rect(rect: tuple[float, float, float, float], scale: float) -> tuple[float, float, float, float]:
    """``INSET`` at ``scale`` in the corner ``rect`` holds: its top kept, and its left side, or its right
    side for a rectangle in the frame's right half."""
    w, h = scale * INSET[2], scale * INSET[3]
    left = rect[0] if rect[0] + 0.5 * rect[2] < 0.5 else rect[0] + rect[2] - w
    return (left, rect[1] + rect[3] - h, w, h)


def inset_rects(view: tuple[float, float, float, float], traces: list[np.ndarray],
                machine: tuple[float, float, float, float] | None = None) -> list[tuple[float, ...]]:
    """Each frame's close-up (fractions of the frame), for frames whose trajectories so far are ``traces``
    (each (k, 2), m, the last the whole shot's): in the corner ``inset_rect`` picks for the whole shot,
    the largest size up to ``INSET_SCALES[0]`` clear of the trajectory ``INSET_LOOKAHEAD`` frames on
    and of the box ``machine`` ((x_min, x_max, y_min, y_max), m: where the scene draws the machine),
    never growing again once it has shrunk, and never smaller than ``inset_rect``'s."""
    final = inset_rect(view, traces[-1])
    if machine is not None:   # its corners as pixels (left, top, right, bottom)
        (left, top), (right, bottom) = pixels_of(view, np.array([[machine[0], machine[3]], [machine[1], machine[2]]]))
        machine = (left, top, right, bottom)
    smallest = final[2] / INSET[2]
    scales = np.linspace(max(INSET_SCALES[0], smallest), smallest, INSET_STEPS)
    rects, largest = [], scales[0]
    for i in range(len(traces)):
        points = pixels_of(view, traces[min(i + INSET_LOOKAHEAD, len(traces) - 1)])
        clear = next((scale for scale in scales if scale <= largest
                      and not crossed(box_pixels(_corner_rect(final, scale)), points)
                      and not (machine is not None and overlap(box_pixels(_corner_rect(final, scale)), machine))),
                     smallest)
        largest = clear
        rects.append(final if clear == smallest else _corner_rect(final, clear))
    return rects


def pixels_of(view: tuple[float, float, float, float], points: np.ndarray) -> np.ndarray:
    """``pixel`` of each of ``points`` ((k, 2), m): (k, 2) columns and rows."""
    x_min, x_max, y_min, y_max = view
    return np.column_stack([(points[:, 0] - x_min) / (x_max - x_min) * FRAME_SIZE[0],
                            (y_max - points[:, 1]) / (y_max - y_min) * FRAME_SIZE[1]])


def pixel(view: tuple[float, float, float, float], point: np.ndarray) -> tuple[float, float]:
    """Where a point (m) falls in a frame drawn with ``view``: (column, row) in px from the top left."""
    x_min, x_max, y_min, y_max = view
    return ((point[0] - x_min) / (x_max - x_min) * FRAME_SIZE[0],
            (y_max - point[1]) / (y_max - y_min) * FRAME_SIZE[1])
