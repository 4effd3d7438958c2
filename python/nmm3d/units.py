"""Units of the output columns (SI, as in the scenario file)."""

from __future__ import annotations

_QUANTITY_UNITS = {"displacement": "m", "velocity": "m/s", "rotation": "rad", "volume": "m³", "stress": "Pa"}
_DIAGNOSTIC_UNITS = {"time": "s", "dt": "s", "max_penetration": "m", "kinetic_energy": "J",
                     "elastic_energy": "J", "external_work": "J", "contact_energy": "J",
                     "friction_dissipation": "J", "numerical_dissipation": "J", "energy_error": "J",
                     "contact_event_dissipation": "J", "damping_dissipation": "J"}


def unit(column: str) -> str:
    """The unit of a ``history.csv`` column ``<monitor>.<quantity>.<component>`` or of a
    ``diagnostics.csv`` column; ``""`` when dimensionless or unknown."""
    parts = column.rsplit(".", 2)
    if len(parts) == 3 and parts[1] in _QUANTITY_UNITS:
        return _QUANTITY_UNITS[parts[1]]
    return _DIAGNOSTIC_UNITS.get(column, "")
