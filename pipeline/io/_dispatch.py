"""One entry for every format: :func:`sniff_format` tells a file's format from its first
bytes and :func:`load` hands the file to its reader (the table of :mod:`pipeline.io`)."""

from __future__ import annotations

import re

from ..errors import InputError
from ._common import LINE_END, decode, file_path, scene_attrs
from .lvm import MAGIC, read_lvm
from .mat import HDF5_SIGNATURE, is_mat_bytes, read_mat
from .sensitivity import parse_sensitivity
from .sensor import read_sensor
from .tdms import read_tdms
from .wpd import is_datasets_text, read_wpd

__all__ = ["FORMATS", "RECORD_SUFFIXES", "load", "sniff_format"]

#: Formats :func:`load` recognises.
FORMATS = ("sensor_csv", "wpd", "wpd_datasets", "tdms", "lvm", "mat")
#: File suffixes a folder of records is searched for (campaigns, ``make reproduce``).
RECORD_SUFFIXES = (".csv", ".tdms", ".lvm", ".mat")

_HEAD = 65536
_NUMERIC = re.compile(r"^\s*\"?\s*[+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?\s*\"?\s*$")


def sniff_format(path) -> str:
    """Tell a record file's format from its first bytes.

    Returns
    -------
    str
        ``"tdms"`` (starts with the ``TDSm`` tag), ``"mat"`` (a MATLAB header, or HDF5 data
        in a ``.mat`` file, or a ``.mat`` name), ``"lvm"`` (first line ``LabVIEW
        Measurement``, or a ``.lvm`` name), ``"wpd_datasets"`` (second line ``X,Y,...``),
        ``"wpd"`` (first line two numbers) or ``"sensor_csv"`` (a header row, possibly
        after ``#`` metadata lines).

    Raises
    ------
    InputError
        Missing file, a directory, an empty file, undecodable text, an HDF5 file that is
        not a MATLAB file, or a table of numbers without a header (neither format).
    """
    p = file_path(path)
    try:
        with open(p, "rb") as fh:
            head = fh.read(_HEAD)
            more = bool(fh.read(1))
    except FileNotFoundError:
        raise InputError("no such file; check the path", path=p) from None
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror or exc})", path=p) from exc
    if head.startswith(b"TDSm"):
        return "tdms"
    if not head.strip() and not more:
        raise InputError("file is empty; export the record again", path=p)
    suffix = p.suffix.lower()
    if suffix == ".tdms":
        return "tdms"  # read_tdms explains what is wrong with it
    if is_mat_bytes(head) or suffix == ".mat":
        return "mat"  # read_mat explains what is wrong with it
    if HDF5_SIGNATURE in (head[:8], head[512:520]):
        raise InputError(
            "an HDF5 file that is not a MATLAB v7.3 file (no MATLAB header); a record is read "
            "from .mat, .lvm, .tdms or CSV files — name it .mat if MATLAB wrote it",
            path=p,
        )
    if head.removeprefix(b"\xef\xbb\xbf").startswith(MAGIC.encode()) or suffix == ".lvm":
        return "lvm"  # read_lvm explains what is wrong with it
    if more and not head.startswith((b"\xff\xfe", b"\xfe\xff")):
        cut = max(head.rfind(b"\n"), head.rfind(b"\r"))  # a whole line: no cut character
        head = head[: cut + 1] if cut > 0 else head
    text = decode(head, p)
    if not text.strip():
        raise InputError("file is empty; export the record again", path=p)
    lines = [ln for ln in LINE_END.split(text) if ln.strip()]
    first = lines[0].strip()
    if first.startswith(MAGIC):  # UTF-16 text
        return "lvm"
    if first.startswith("#"):
        return "sensor_csv"
    if is_datasets_text(text):
        return "wpd_datasets"
    for sep in (";", "\t", ","):
        cells = first.split(sep)
        if len(cells) > 1 and all(_NUMERIC.match(c) for c in cells):
            if len(cells) == 2:
                return "wpd"
            raise InputError(
                f"the first line is {len(cells)} numbers: no header row. A sensor CSV needs "
                "a header naming its columns with units ('time [s],Fx [N],Fy [N],Fz [N]'); "
                "a WebPlotDigitizer export has two columns",
                path=p,
                line=1,
            )
    return "sensor_csv"


def load(
    path,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    channels=None,
    decouple=None,
    sensitivity=None,
    columns=None,
    **scene_fields,
):
    """Read a record file of any supported format.

    Parameters
    ----------
    path : str, os.PathLike, list or dict
        The file. Two WebPlotDigitizer single-dataset exports are combined by a list
        (``[fn_path, ft_path]``, channels from the names or ``channels=[...]``) or a dict
        ``{"Fn": fn_path, "Ft": ft_path}``.
    time_unit : str, optional
        Time unit (``"s"``, ``"ms"``, ``"us"``/``"µs"``, ``"ns"``) for files that carry
        none: required for digitised exports. A unit in the file wins; a different
        argument is an error.
    force_unit : str, optional
        Force unit (``"N"``, ``"kN"``, ``"mN"``, ``"daN"``, ``"lbf"``), same rules.
    axes : dict, optional
        Sensor CSV and TDMS: record channel → file column, sign by a leading ``-``;
        default ``{"Fn": "Fz", "Ft": "Fx", "Fy": "Fy"}`` (see :mod:`pipeline.io.sensor`).
    channels : str, list or dict, optional
        Digitised files: which dataset is which channel (see :func:`read_wpd`).
    decouple : array_like or path, optional
        Sensor CSV and TDMS: the sensor's 3×3 decoupling (calibration) matrix, or a file
        holding it (:func:`read_decoupling`). It maps the raw (Fx, Fy, Fz), in N, to
        corrected forces before the axis map; the attributes record it
        (``decouple_matrix``, ``decouple_axes``, ``decouple_source``, ``decouple_sha256``).
    sensitivity : dict, optional
        Channels recorded in volts: record channel (after ``axes``) → ``(value, unit)``,
        unit ``"mV/N"``, ``"V/N"``, ``"N/V"`` or ``"N/mV"``: ``{"Fn": (0.225, "mV/N")}``
        (:mod:`pipeline.io.sensitivity`). A channel in volts without one is an error
        naming its column; the record keeps it in ``attrs["sensitivity"]``. Sensor CSV,
        TDMS, LabVIEW and MATLAB files.
    columns : list or dict, optional
        MATLAB files: the names of a 2-D array's columns, as a CSV header writes them
        (``["time [s]", "Fz [V]"]``, or ``{"data": [...]}``; see :mod:`pipeline.io.mat`).
    **scene_fields : float
        Scene fields (names as :meth:`pipeline.Scene.field_names`, SI units) stored in the
        record's attributes.

    Returns
    -------
    xarray.Dataset
        The record: coordinate ``time`` [s]; ``Fn``, ``Ft`` (``Fy``) [N]; attributes
        ``source``, ``sha256``, ``format``, ``kind``, ``source_time_unit``,
        ``source_force_unit``, metadata (``meta_<key>``) and the scene fields.

    Raises
    ------
    InputError
        Every problem with the input: empty file, header only, non-numeric cell, NaN or
        infinite value, time not strictly increasing, a unit that is not a time/force unit
        or clashes with the argument, no normal-force channel, a single sample,
        undecodable bytes, missing file or a directory, an unknown scene field.

    Examples
    --------
    >>> from pipeline.io import load
    >>> rec = load("data_samples/sensor_decimal_comma.csv", radius=0.0127)
    >>> rec = load("data_samples/wpd_datasets.csv", time_unit="us", force_unit="N")
    >>> rec = load("data_samples/sensor_volts.lvm", sensitivity={"Fn": (0.225, "mV/N"),
    ...            "Ft": (0.5, "mV/N")})
    """
    scene_attrs(scene_fields)  # fail early on a bad keyword, before reading anything
    sens = parse_sensitivity(sensitivity)
    if isinstance(path, dict | list | tuple):
        fmt = "digitised exports"
    else:
        fmt = sniff_format(path)
    common = {"time_unit": time_unit, "force_unit": force_unit, **scene_fields}
    if fmt != "mat":
        _refuse(columns=columns, fmt=_NAMES.get(fmt, fmt), hint="it names a MATLAB array's columns")
    if fmt in ("sensor_csv", "tdms", "lvm", "mat"):
        _refuse(channels=channels, fmt=_NAMES[fmt], hint="use axes= to map columns")
        reader = {"sensor_csv": read_sensor, "tdms": read_tdms, "lvm": read_lvm}.get(fmt)
        extra = {"columns": columns} if fmt == "mat" else {}
        return (reader or read_mat)(
            path, axes=axes, decouple=decouple, sensitivity=sens, **extra, **common
        )
    hint = "use channels= to name datasets"
    _refuse(axes=axes, fmt="digitised exports", hint=hint)
    _refuse(decouple=decouple, fmt="digitised exports", hint="they hold no raw axes")
    _refuse(sensitivity=sensitivity, fmt="digitised exports", hint="they hold forces, not volts")
    return read_wpd(path, channels=channels, **common)


_NAMES = {
    "sensor_csv": "sensor CSV files",
    "tdms": "TDMS files",
    "lvm": "LabVIEW Measurement files",
    "mat": "MATLAB files",
    "wpd": "digitised exports",
    "wpd_datasets": "digitised exports",
}


def _refuse(*, fmt, hint, **given):
    for name, value in given.items():
        if value is not None:
            raise InputError(f"{name}= does not apply to {fmt}; {hint}")
