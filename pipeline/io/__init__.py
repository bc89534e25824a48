"""Readers: lab files → records (:mod:`pipeline.record`)."""

from __future__ import annotations

from ..record import validate
from .sensor import read_sensor, write_sensor

__all__ = ["read_sensor", "write_sensor", "validate"]
