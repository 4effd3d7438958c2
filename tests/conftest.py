"""Shared fixtures: paths and a small scenario dictionary."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


@pytest.fixture
def cube() -> dict:
    """A 1 m cube falling freely for 0.1 s."""
    return {
        "analysis": {"duration": 0.1, "dt": 0.01, "gravity": [0.0, 0.0, -10.0], "max_displacement_ratio": 0.01,
                     "output_interval": 0.05},
        "cover": {"pattern": "tet6", "size": 0.5},
        "material": [{"name": "rock", "density": 2500.0, "young": 1e9, "poisson": 0.25}],
        "body": [{"name": "cube", "material": "rock", "shape": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}}],
        "monitor": [{"name": "cube", "select": {"body": "cube"}, "quantities": ["displacement", "velocity", "volume"]}],
    }
