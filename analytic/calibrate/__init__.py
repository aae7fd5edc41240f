"""Calibration: fit design parameters (loss coefficients, a drag factor, a release-angle offset) to measured shots.

``load_calibration(path)`` reads and checks a calibration file (``spec``);
``calibrate(spec)`` fits it by weighted least squares on the fast path
(``fit``) and returns a ``Calibration``; ``predict`` gives the range at new
settings with its uncertainty; ``report`` turns them into JSON, text, a plot
and the fitted designs (``fitted_file``); ``cli`` is
``python -m analytic calibrate``.
"""

from analytic.calibrate.fit import Calibration, CalibrationError, Prediction, calibrate
from analytic.calibrate.spec import (
                                     DRAG_FACTOR,
                                     QUANTITIES,
                                     RELEASE_ANGLE_OFFSET,
                                     CalibrationSpec,
                                     Measurement,
                                     Parameter,
                                     ShotSpec,
                                     load_calibration,
)

__all__ = [
                                     "DRAG_FACTOR",
                                     "QUANTITIES",
                                     "RELEASE_ANGLE_OFFSET",
                                     "Calibration",
                                     "CalibrationError",
                                     "CalibrationSpec",
                                     "Measurement",
                                     "Parameter",
                                     "Prediction",
                                     "ShotSpec",
                                     "calibrate",
                                     "load_calibration",
]
