"""Sensor model: an ideal record → what a tri-axial piezo rig would export (placeholder)."""


def to_sensor(record, **options):
    raise NotImplementedError("to_sensor is being written")
