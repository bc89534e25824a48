"""MATLAB ``.mat`` files: v4 to v7 with :func:`scipy.io.loadmat`, v7.3 (HDF5) with h5py.

Both libraries are maintained and already dependencies; what this module adds is how a
record is found in a file of variables, the same way for every version:

- **one vector per column**, named as a CSV column would be, with the unit as a suffix
  after an underscore (a MATLAB name holds no brackets): ``t_us``, ``time_s``,
  ``Fz_kN``, ``Fx_N``, ``Fz_V`` (volts: a sensitivity is needed); a name without a
  unit (``t``, ``Fz``) takes ``time_unit=``/``force_unit=``. Row and column vectors alike;
  double, single and integer classes (converted to float). The force names and the axis
  map are the sensor CSV's (``Fn``, ``Ft`` or ``Fx``, ``Fy``, ``Fz``; ``axes=`` names any
  other vector by its name without the unit suffix);
- time as a vector, or — what many lab scripts save — a sample rate ``fs`` (``fs_Hz``,
  ``fs_kHz``, ``fs_MHz``; also ``sample_rate``, ``sampling_rate``) or a step ``dt``
  (``dt_us``...) with an optional start ``t0`` (``t0_us``...): time = t0 + k·dt;
- the vectors at the top level of the file, or the fields of **one struct**
  (``data.time``, ``data.Fz``: the struct that holds a time, or the one ``variable=``
  names, ``"data"`` or ``"run.raw"``);
- a **2-D array** (samples × channels, or channels × samples) with its columns named by
  ``columns=``: a list of names as a CSV header would write them (``["time [s]",
  "Fz [V]", "Fx [V]"]``; ``None`` skips a column), for the one 2-D array of the file, or
  ``{"data": [...]}`` naming the array. A sidecar gives the same as ``"columns"``.

MATLAB's v7.3 dialect is read as MATLAB writes it: the 512-byte text header before the
HDF5 data, each variable's ``MATLAB_class`` attribute, arrays stored transposed (a
MATLAB 1×n row vector is an n×1 HDF5 dataset), char arrays as UTF-16 code units, structs
as groups, ``MATLAB_empty``. Cell arrays, sparse matrices, complex and logical arrays,
struct arrays and objects (``string``, ``datetime``, tables) are listed by
:func:`mat_variables` but hold no record: using one is an :class:`InputError` that says
what it is. The record's attributes keep the MATLAB header text (``meta_header``), the
version (``mat_version``), the struct or array used (``mat_variable``), the vectors no
channel reads (``ignored_columns``) and the variables that are no vector
(``ignored_variables``: a char, a cell array...).
"""

from __future__ import annotations

import io
import math
import re
import struct
import warnings

import numpy as np

from ..errors import InputError
from ._common import FORCE_COLUMNS, canonical_column, read_decoupling, read_raw, scene_attrs
from ._table import Column, table_record
from .metadata import UNITS as _META_UNITS
from .units import force_factor, split_unit, time_factor, volt_factor

__all__ = ["read_mat", "mat_variables", "is_mat_bytes", "Unsupported"]

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
_RATE_NAMES = {"fs", "samplerate", "samplingrate", "samplefrequency", "samplingfrequency"}
_STEP_NAMES = {"dt", "timestep", "sampleinterval", "samplinginterval", "samplingperiod"}
_START_NAMES = {"t0", "starttime", "tstart"}
_SUFFIX = re.compile(r"^(?P<base>.+?)_(?P<unit>[A-Za-z\u00b5\u03bc]+)$")


class Unsupported:
    """A variable that holds no numbers for a record: its kind (``"cell array"``...)."""

    def __init__(self, kind: str):
        self.kind = kind

    def __repr__(self) -> str:
        return f"<{self.kind}>"


def is_mat_bytes(head: bytes) -> bool:
    """Whether a file's first bytes (at least 520) are a MATLAB file's: the text header of
    v5–v7.3 (``MATLAB 5.0 MAT-file``, ``MATLAB 7.3 MAT-file``)."""
    return head.startswith(b"MATLAB ") and b"MAT-file" in head[:40]


def _version(raw: bytes) -> str:
    if raw.startswith(HDF5_SIGNATURE) or raw[512:520] == HDF5_SIGNATURE:
        return "7.3"
    if is_mat_bytes(raw):
        return "5"
    return "4"  # no text header: MATLAB's level-1 format, or not a MAT file at all


def mat_variables(path) -> dict:
    """The variables of a ``.mat`` file, as the record reader sees them.

    Returns
    -------
    dict
        ``{name: value}``: numeric arrays in MATLAB's orientation with singleton
        dimensions dropped (a row or column vector is 1-D, a scalar 0-d), ``str`` for char
        arrays, ``dict`` for a struct (its fields), :class:`Unsupported` for the rest.

    Raises
    ------
    InputError
        Not a MATLAB file, or a damaged one.
    """
    p, raw, _ = read_raw(path)
    return _variables(raw, p)[0]


def _variables(raw: bytes, p) -> tuple[dict, str, str]:
    """``(variables, version, header text)``."""
    version = _version(raw)
    header = raw[:116].decode("latin-1").strip(" \x00") if version != "4" else ""
    if version == "7.3":
        return _h5_variables(raw, p), version, header
    import scipy.io

    if version == "5":
        _check_v5(raw, p)  # before scipy, which trusts the tags: a damaged one may crash it
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # scipy's MatReadWarning: unreadable parts
            data = scipy.io.loadmat(io.BytesIO(raw), simplify_cells=True)
    except Exception as exc:  # scipy raises many types on a damaged or foreign file
        if version == "4" and not str(p).lower().endswith(".mat"):
            raise InputError("not a MATLAB file", path=p) from exc
        raise InputError(
            f"cannot read this MATLAB file ({type(exc).__name__}: {exc}); it is damaged or "
            "not a MAT-file — save it again from MATLAB (save(name, '-v7') or '-v7.3')",
            path=p,
        ) from exc
    return {k: _plain(v) for k, v in data.items() if not k.startswith("__")}, version, header


#: Item sizes [bytes] of the MAT-file v5 data types that hold numbers or text (MathWorks,
#: "MAT-File Format", Table 1-1): miINT8 … miUINT64, miUTF8/16/32.
_V5_ITEM = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 9: 8, 12: 8, 13: 8, 16: 1, 17: 2, 18: 4}
_MI_MATRIX, _MI_COMPRESSED = 14, 15
#: Array classes whose data are numbers, one per element: mxDOUBLE … mxUINT64.
_V5_NUMERIC = range(6, 16)


def _check_v5(raw: bytes, p) -> None:
    """Refuse a v5 MAT-file whose data element tags contradict each other or the file's
    size: an element running past its container, a numeric array whose data do not hold
    the elements its dimensions count, a data type no MAT-file has (in any array: its
    name, a char array's text, a struct's field names). SciPy's reader trusts
    the tags, and on such a file (one flipped byte of a type code suffices) it can crash
    the process instead of raising. Compressed elements are left to zlib, whose checksum
    catches their damage. The layout is MathWorks' "MAT-File Format" (v5, Chapter 1)."""
    order = {b"IM": "<", b"MI": ">"}.get(raw[126:128])
    if order is None:
        raise InputError(
            "cannot read this MATLAB file: its header's byte-order mark is damaged; save it "
            "again from MATLAB (save(name, '-v7'))",
            path=p,
        )

    def bad(what, at):
        raise InputError(
            f"cannot read this MATLAB file: {what} (byte {at}); it is damaged — save it again "
            "from MATLAB (save(name, '-v7') or '-v7.3')",
            path=p,
        )

    def elements(start, end):
        """(type, data start, byte count) of the data elements in raw[start:end]."""
        out, pos = [], start
        while pos < end:
            if pos + 8 > end:
                bad("a data element's tag is cut short", pos)
            first, second = struct.unpack_from(order + "II", raw, pos)
            if first >> 16:  # the small data element: up to 4 bytes inside its tag
                kind, n, data, nxt = first & 0xFFFF, first >> 16, pos + 4, pos + 8
                if n > 4:
                    bad("a small data element claims more than 4 bytes", pos)
            else:
                kind, n, data = first, second, pos + 8
                nxt = data + n + (0 if kind == _MI_COMPRESSED else -n % 8)
                if data + n > end:
                    bad("a data element runs past its container", pos)
            out.append((kind, data, n))
            pos = min(nxt, end)
        return out

    def matrix(start, n, at):
        if n == 0:  # an empty element (an empty cell's)
            return
        parts = elements(start, start + n)
        if len(parts) < 3 or parts[0][2] != 8 or parts[1][0] not in (5, 6):
            bad("an array's flags, dimensions or name are missing", at)
        flags = struct.unpack_from(order + "I", raw, parts[0][1])[0]
        cls, is_complex = flags & 0xFF, bool(flags & 0x800)
        dims = struct.unpack_from(order + f"{parts[1][2] // 4}i", raw, parts[1][1])
        if len(dims) < 2 or min(dims) < 0:
            bad("an array's dimensions are damaged", at)
        count = math.prod(dims)
        rest = parts[3:]
        if cls in _V5_NUMERIC:
            if len(rest) != 1 + is_complex:
                bad("a numeric array's real or imaginary part is missing", at)
            for kind, _, size in rest:
                if kind not in _V5_ITEM or size != count * _V5_ITEM[kind]:
                    bad("a numeric array's data do not match its dimensions", at)
        elif cls == 1:  # a cell array: one array per cell
            if len(rest) != count or any(kind != _MI_MATRIX for kind, _, _ in rest):
                bad("a cell array's cells do not match its dimensions", at)
        # every other part (a name, text, a struct's field names, a sparse array's indices)
        # is numbers or text: scipy reads an unknown type's data with no known item size
        if any(kind != _MI_MATRIX and kind not in _V5_ITEM for kind, _, _ in parts[2:]):
            bad("a data element's type is one no MAT-file has", at)
        for kind, data, size in rest:
            if kind == _MI_MATRIX:
                matrix(data, size, data - 8)

    for kind, data, n in elements(128, len(raw)):
        if kind == _MI_MATRIX:
            matrix(data, n, data - 8)


def _plain(value):
    """A loadmat value (simplify_cells) in the module's terms (see mat_variables)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, str):
        return value
    if isinstance(value, bool | np.bool_):
        return Unsupported("logical")
    if isinstance(value, int | float | np.integer | np.floating):
        return np.asarray(float(value))
    if isinstance(value, complex | np.complexfloating):
        return Unsupported("complex")
    if isinstance(value, list):
        return Unsupported("cell array")
    if isinstance(value, np.ndarray):
        kind = value.dtype.kind
        if kind in "iuf":
            return np.squeeze(value)
        if kind == "b":
            return Unsupported("logical array")
        if kind == "c":
            return Unsupported("complex array")
        if kind == "U":
            return "\n".join(value.ravel().tolist())
        return Unsupported("cell or struct array")
    if hasattr(value, "tocsc"):
        return Unsupported("sparse matrix")
    return Unsupported(f"MATLAB {type(value).__name__}")


def _cls(obj) -> str | None:
    value = obj.attrs.get("MATLAB_class")
    if value is None:
        return None
    return value.decode("ascii", "replace") if isinstance(value, bytes) else str(value)


_NUMERIC_CLASSES = {
    "double",
    "single",
    "int8",
    "int16",
    "int32",
    "int64",
    "uint8",
    "uint16",
    "uint32",
    "uint64",
}


def _h5_variables(raw: bytes, p) -> dict:
    import h5py

    try:
        with h5py.File(io.BytesIO(raw), "r") as f:
            return {k: _h5(v) for k, v in f.items() if not k.startswith("#")}
    except Exception as exc:  # h5py raises OSError, KeyError, ValueError... on damage
        raise InputError(
            f"cannot read this MATLAB v7.3 (HDF5) file ({type(exc).__name__}: {exc}); it is "
            "damaged or truncated — copy it again, or save it from MATLAB once more",
            path=p,
        ) from exc


def _h5(obj):
    import h5py

    cls = _cls(obj)
    if isinstance(obj, h5py.Group):
        if "MATLAB_sparse" in obj.attrs:
            return Unsupported("sparse matrix")
        if cls not in (None, "struct"):
            return Unsupported(f"MATLAB {cls} object")
        return {k: _h5(v) for k, v in obj.items()}
    if not isinstance(obj, h5py.Dataset):
        return Unsupported("HDF5 link")
    if obj.attrs.get("MATLAB_empty"):
        return "" if cls == "char" else np.zeros(0)
    if "MATLAB_object_decode" in obj.attrs and cls != "char":
        return Unsupported(f"MATLAB {cls} object")
    if cls == "cell" or obj.dtype.kind == "O":
        return Unsupported("cell array" if cls in (None, "cell") else f"{cls} array")
    if obj.dtype.names is not None:
        return Unsupported("complex array")
    data = np.asarray(obj[()])
    if cls is not None:
        data = data.T  # MATLAB stores column-major: HDF5 holds the transpose
    if cls == "char":
        rows = np.atleast_2d(data)
        return "\n".join("".join(map(chr, row.tolist())) for row in rows)
    if cls == "logical" or data.dtype.kind == "b":
        return Unsupported("logical array")
    if cls is not None and cls not in _NUMERIC_CLASSES:
        return Unsupported(f"MATLAB {cls} object")
    if data.dtype.kind not in "iuf":
        return Unsupported(f"{data.dtype} array")
    return np.squeeze(data)


def _describe(value) -> str:
    if isinstance(value, Unsupported):
        return value.kind
    if isinstance(value, dict):
        return "struct"
    if isinstance(value, str):
        return "char"
    shape = "×".join(str(n) for n in value.shape) or "scalar"
    return f"{shape} {value.dtype}"


def _listing(variables: dict, prefix: str = "") -> str:
    parts = []
    for name, value in variables.items():
        parts.append(f"{prefix}{name} ({_describe(value)})")
    return ", ".join(parts) or "no variables"


def _name_unit(name: str) -> tuple[str, str | None]:
    """``"Fz_kN"`` → ``("Fz", "kN")``, ``"time [s]"`` → ``("time", "s")``, ``"F_z"`` →
    ``("F_z", None)``: a suffix is a unit only when it is one."""
    base, unit = split_unit(name)
    if unit is not None:
        return base, unit
    m = _SUFFIX.match(name)
    if m and any(f(m.group("unit")) is not None for f in (time_factor, force_factor, volt_factor)):
        return m.group("base"), m.group("unit")
    if m and _frequency(m.group("unit")) is not None:
        return m.group("base"), m.group("unit")
    return name, None


def _frequency(unit: str) -> float | None:
    return _META_UNITS["frequency"].get(unit.lower())


def _squash(name: str) -> str:
    return name.replace("_", "").replace(" ", "").lower()


def _is_vector(value) -> bool:
    return isinstance(value, np.ndarray) and value.ndim == 1


def _is_table(value) -> bool:
    return isinstance(value, np.ndarray) and value.ndim == 2


def _has_time(fields: dict) -> bool:
    for name, value in fields.items():
        base, _ = _name_unit(name)
        if _is_vector(value) and canonical_column(base) == "time":
            return True
        if isinstance(value, np.ndarray) and value.ndim == 0:
            if _squash(base) in _RATE_NAMES | _STEP_NAMES:
                return True
    return False


def _lookup(variables: dict, path: str, p):
    value = variables
    for part in path.split("."):
        if not isinstance(value, dict) or part not in value:
            raise InputError(
                f"no variable {path!r} in the file (variables: {_listing(variables)})", path=p
            )
        value = value[part]
    return value


def _tables(variables: dict) -> list[str]:
    """Dotted names of the 2-D numeric arrays, at the top level and in top-level structs."""
    out = []
    for name, value in variables.items():
        if _is_table(value):
            out.append(name)
        elif isinstance(value, dict):
            out += [f"{name}.{k}" for k, v in value.items() if _is_table(v)]
    return out


def _choose(variables: dict, columns, variable, p):
    """``(fields dict, variable path, names of a 2-D array's columns or None)``."""
    if isinstance(columns, dict):
        if len(columns) != 1 or variable is not None:
            raise InputError(
                "columns= as a dict names one 2-D array: {'data': ['time [s]', 'Fz [N]']}",
                path=p,
            )
        ((variable, columns),) = columns.items()
    if columns is not None and not isinstance(columns, list | tuple):
        raise InputError(
            f"columns= must be a list of column names such as ['time [s]', 'Fz [N]'], got "
            f"{columns!r}",
            path=p,
        )
    if variable is not None:
        if not isinstance(variable, str) or not variable:
            raise InputError(f"variable={variable!r} must name a struct or a 2-D array", path=p)
        value = _lookup(variables, variable, p)
        if isinstance(value, dict) and columns is None:
            return value, variable, None
        if _is_table(value) and columns is not None:
            return {variable: value}, variable, list(columns)
        if _is_table(value):
            raise InputError(
                f"variable {variable!r} is a {_describe(value)} array: name its columns, "
                "columns=['time [s]', 'Fz [N]', ...] (or the sidecar's \"columns\")",
                path=p,
            )
        raise InputError(
            f"variable {variable!r} is a {_describe(value)}: name a struct of vectors or a "
            "2-D array with columns=",
            path=p,
        )
    tables = _tables(variables)
    if columns is not None:
        if len(tables) != 1:
            raise InputError(
                f"columns= names the columns of a 2-D array, and the file holds "
                f"{len(tables)} ({', '.join(tables) or 'none'}; variables: "
                f"{_listing(variables)}); name it: columns={{'data': [...]}}",
                path=p,
            )
        return {tables[0]: _lookup(variables, tables[0], p)}, tables[0], list(columns)
    if _has_time(variables):
        return variables, "", None
    structs = [k for k, v in variables.items() if isinstance(v, dict) and _has_time(v)]
    if len(structs) == 1:
        return variables[structs[0]], structs[0], None
    if len(structs) > 1:
        raise InputError(
            f"several structs hold a time ({', '.join(structs)}); name one: "
            f"pipeline.io.read_mat(path, variable={structs[0]!r})",
            path=p,
        )
    if tables:
        shapes = ", ".join(f"{t} ({_describe(_lookup(variables, t, p))})" for t in tables)
        raise InputError(
            f"no time vector, but 2-D arrays: {shapes}; name the columns of one, "
            f"columns={{{tables[0]!r}: ['time [s]', 'Fz [N]', ...]}} (or the sidecar's "
            '"columns")',
            path=p,
        )
    raise InputError(
        "no record in the file: no time vector (t, time, t_s, time_us...) nor sample rate "
        f"(fs) beside the force vectors (variables: {_listing(variables)}); save the vectors "
        "named as CSV columns with their unit, e.g. t_s, Fz_N",
        path=p,
    )


def _table_columns(name: str, table: np.ndarray, names: list, p) -> list[tuple[str, object]]:
    k = len(names)
    if table.shape[1] == k:
        data = table
    elif table.shape[0] == k:
        data = table.T  # channels in rows
    else:
        raise InputError(f"columns= names {k} columns but {name!r} is {_describe(table)}", path=p)
    out = []
    for j, col in enumerate(names):
        if col is None or (isinstance(col, str) and not col.strip()):
            continue
        if not isinstance(col, str):
            raise InputError(f"columns[{j}] = {col!r} must be a column name or None", path=p)
        out.append((col.strip(), data[:, j]))
    return out


def read_mat(
    path,
    *,
    time_unit=None,
    force_unit=None,
    axes=None,
    sensitivity=None,
    decouple=None,
    columns=None,
    variable=None,
    **scene_fields,
):
    """Read a MATLAB ``.mat`` file (v4–v7.3) into a record.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    time_unit, force_unit : str, optional
        Units of vectors whose names carry none (``t``, ``Fz``); a unit in the name wins and
        a contradicting argument is an error. ``force_unit="V"`` with a sensitivity.
    axes : dict, optional
        Record channel → vector name (without its unit suffix), sign by a leading ``-``.
    sensitivity : dict, optional
        ``{"Fn": (0.225, "mV/N")}`` for channels in volts (:mod:`pipeline.io.sensitivity`).
    decouple : array_like or path, optional
        The sensor's 3×3 decoupling matrix (:func:`pipeline.io.read_decoupling`).
    columns : list or dict, optional
        Names of a 2-D array's columns, as a CSV header writes them (see module notes).
    variable : str, optional
        The struct (or 2-D array) holding the record: ``"data"``, ``"run.raw"``.
    **scene_fields : float
        Scene fields stored in the attributes (names as :class:`pipeline.Scene`).

    Returns
    -------
    xarray.Dataset
        The record (``format="mat"``, ``kind="sensor"``), SI units.

    Raises
    ------
    InputError
        Not a MATLAB file or a damaged one, no time or no normal force, a vector of another
        length, a cell/complex/sparse variable where a vector is needed, a unit that is not
        a force (or volts without a sensitivity), NaN or infinite values, time not strictly
        increasing.
    """
    scene = scene_attrs(scene_fields)
    matrix = None if decouple is None else read_decoupling(decouple)
    p, raw, sha = read_raw(path)
    variables, version, header = _variables(raw, p)
    fields, where, names = _choose(variables, columns, variable, p)
    if names is not None:
        items = _table_columns(where, fields[where], names, p)
    else:
        items = list(fields.items())
    time_cols, cols, scalars, ignored = [], [], {}, []
    for name, value in items:
        base, unit = _name_unit(name)
        canon = canonical_column(base)
        if isinstance(value, np.ndarray) and value.ndim == 0:
            scalars[_squash(base)] = (float(value), unit, name)
            continue
        if not _is_vector(value):
            if canon == "time" or canon in FORCE_COLUMNS:
                raise InputError(
                    f"variable {name!r} is a {_describe(value)}, not a vector of numbers; save "
                    "it as a double vector",
                    path=p,
                )
            ignored.append(name)
            continue
        col = Column(base, value, unit)
        (time_cols if canon == "time" else cols).append(col)
    if len(time_cols) > 1:
        raise InputError(
            f"two time vectors ({', '.join(c.name for c in time_cols)}); keep one", path=p
        )
    time = time_cols[0] if time_cols else _time_from_rate(scalars, cols, time_unit, p)
    attrs = {
        "mat_version": version,
        "mat_variable": where,
        **({"meta_header": header} if header else {}),
    }
    return table_record(
        p,
        sha,
        "mat",
        time=time,
        columns=cols,
        time_unit=time_unit,
        force_unit=force_unit,
        axes=axes,
        sensitivity=sensitivity,
        decouple=matrix,
        scene=scene,
        attrs=attrs if not ignored else {**attrs, "ignored_variables": ",".join(ignored)},
    )


def _time_from_rate(scalars: dict, cols: list, time_unit, p) -> Column:
    """Time = t0 + k·dt from a sample rate ``fs`` or a step ``dt`` (see module notes)."""
    if not cols:
        raise InputError("no vectors of samples in the file", path=p)
    forces = [c for c in cols if canonical_column(c.name) in FORCE_COLUMNS]
    n = (forces or cols)[0].values.size
    rate = [v for k, v in scalars.items() if k in _RATE_NAMES]
    step = [v for k, v in scalars.items() if k in _STEP_NAMES]
    if len(rate) + len(step) != 1:
        raise InputError(
            "no time vector, and "
            + ("both a sample rate and a step" if rate and step else "no sample rate (fs)")
            + "; save the time vector (t_s) or one of fs [Hz] / dt",
            path=p,
        )
    if rate:
        value, unit, name = rate[0]
        factor = 1.0 if unit is None else _frequency(unit)
        if factor is None:
            raise InputError(f"{name}: {unit!r} is not a frequency unit (Hz, kHz, MHz)", path=p)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            dt = 1.0 / (value * factor)
        t_unit, what = "s", f"{name} = {value:g}"
    else:
        value, t_unit, name = step[0]
        dt, what = value, f"{name} = {value:g}"
    if not (np.isfinite(dt) and dt > 0):
        raise InputError(f"{what}: the sample step must be a positive number", path=p)
    t0 = 0.0
    start = [v for k, v in scalars.items() if k in _START_NAMES]
    if start:
        t0, unit0, name0 = start[0]
        if unit0 is not None and unit0 != t_unit:
            f0, ft = time_factor(unit0), time_factor(t_unit or time_unit or "s")
            if f0 is None or ft is None:
                raise InputError(f"{name0}: {unit0!r} is not a time unit", path=p)
            t0 = t0 * f0 / ft
    with np.errstate(over="ignore", invalid="ignore"):  # refused as not finite
        t = t0 + dt * np.arange(n)
    return Column(f"{what} (t0 = {t0:g})", t, t_unit)
