"""Firing tables: for each target and projectile mass, the settings of one field that land on it.

``firing_table`` (``table``) aims at every target from one scan a projectile
mass, optionally at a calibration's fitted parameters with the band its fit
gives; ``output`` writes the CSV, the JSON and a printable card; ``cli`` is
``python -m analytic firing-table``.
"""

from analytic.firing.table import Entry, FiringTable, firing_table

__all__ = ["Entry", "FiringTable", "firing_table"]
