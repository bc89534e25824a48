"""
Read the record formats
=======================

:func:`pipeline.io.load` sniffs the format and returns a *record*: an ``xarray.Dataset``
with the coordinate ``time`` [s], ``Fn``, ``Ft`` and ``Fy`` [N], and the file's provenance
in its attributes (:doc:`/formats`). The samples below are one physical impact written in
each format (``data_samples/README.md``).

A lab sensor CSV from a decimal-comma locale (BOM, CRLF, ``;``, units in the header); the
scene fields given here are stored in the record's attributes:
"""

from pipeline.io import load

rec = load("../data_samples/sensor_decimal_comma.csv", radius=0.0127, angle_deg=15.0)
print(rec.attrs["format"], f"peak Fn {float(rec['Fn'].max()):.0f} N")

# %%
# Two WebPlotDigitizer exports of one figure, one per channel. They carry no units, so
# the call gives them; digitised points are irregular, and ``*_measured`` marks which
# instants were clicked on each channel.

dig = load({"Fn": "../data_samples/wpd_Fn.csv", "Ft": "../data_samples/wpd_Ft.csv"},
           time_unit="us", force_unit="N")
print(int(dig["Fn_measured"].sum()), "Fn points,", int(dig["Ft_measured"].sum()), "Ft points")

# %%
# A National Instruments TDMS file (time from the waveform properties):

tdms = load("../data_samples/sensor.tdms")
print(tdms.attrs["format"], tdms.sizes["time"], "samples")

# %%
# A LabVIEW Measurement file recorded in volts: each channel becomes newtons through its
# stated sensitivity (``sensitivity={"Fn": (0.225, "mV/N"), ...}``), here read from the
# record's sidecar by :func:`pipeline.report.load_sample`, as ``pipeline analyse`` does.
# MATLAB files (``.mat``, v4 to v7.3) are read the same way.

from pipeline.report import load_sample

lvm = load_sample("../data_samples/sensor_volts.lvm")
mat = load_sample("../data_samples/sensor_v73.mat")
print(lvm.attrs["format"], lvm.attrs["sensitivity"], f"peak Fn {float(lvm['Fn'].max()):.0f} N")
print(mat.attrs["format"], f"peak Fn {float(mat['Fn'].max()):.0f} N")

# %%
# Bad input raises :class:`~pipeline.errors.InputError` naming the file, the line and the
# column, and what to do:

from pipeline.errors import InputError

try:
    load("../data_samples/wpd_Fn.csv")  # units not given
except InputError as exc:
    print(exc)

# %%
# The records of the same impact, drawn together:

from pipeline.figures import new_figure, style

with style():
    fig, ax = new_figure(width=6.0, height=3.0)
    ax.plot(rec["time"] * 1e6, rec["Fn"], lw=1, label="sensor CSV")
    ax.plot(tdms["time"] * 1e6, tdms["Fn"], "--", lw=1, label="TDMS")
    ax.plot(lvm["time"] * 1e6, lvm["Fn"], ":", lw=1, label="LabVIEW, volts")
    measured = dig["Fn_measured"].values
    ax.plot(dig["time"][measured] * 1e6, dig["Fn"][measured], "k.", ms=3, label="digitised")
    ax.set_xlabel("time [µs]")
    ax.set_ylabel("Fn [N]")
    ax.legend()
