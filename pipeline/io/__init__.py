"""Readers: lab files → records (the layout of :mod:`pipeline.record`).

:func:`load` sniffs a file's format and hands it to the reader for it:

=================  ===============================================  ======================
``format``         file                                             reader
=================  ===============================================  ======================
``sensor_csv``     lab sensor CSV (``# key: value`` lines,          :func:`read_sensor`
                   header with units)
``wpd``            WebPlotDigitizer single-dataset export           :func:`read_wpd`
``wpd_datasets``   WebPlotDigitizer "export all" file               :func:`read_wpd`
``tdms``           NI TDMS (npTDMS)                                 :func:`read_tdms`
``lvm``            LabVIEW Measurement file (``.lvm``)              :func:`read_lvm`
``mat``            MATLAB ``.mat``, v4–v7 (scipy) and v7.3 (h5py)   :func:`read_mat`
=================  ===============================================  ======================

A channel recorded in volts becomes newtons through its stated sensitivity
(``sensitivity={"Fn": (0.225, "mV/N")}``, :mod:`pipeline.io.sensitivity`) in every format
but the digitised ones.

Every failure caused by the input raises :class:`pipeline.errors.InputError` naming the
file, the line and column where known, and what to do.
"""

from __future__ import annotations

from ..record import validate
from ._common import read_decoupling, read_json
from ._dispatch import FORMATS, RECORD_SUFFIXES, load, sniff_format
from .lvm import read_lvm
from .mat import mat_variables, read_mat
from .metadata import scene_from_metadata
from .sensitivity import Sensitivity, parse_sensitivity
from .sensor import read_sensor, write_sensor
from .stream import load_contact
from .tdms import read_tdms
from .wpd import read_wpd

__all__ = [
    "load",
    "load_contact",
    "sniff_format",
    "validate",
    "read_sensor",
    "write_sensor",
    "read_wpd",
    "read_tdms",
    "read_lvm",
    "read_mat",
    "mat_variables",
    "Sensitivity",
    "parse_sensitivity",
    "read_json",
    "read_decoupling",
    "scene_from_metadata",
    "FORMATS",
    "RECORD_SUFFIXES",
]
