"""Helpers shared by the readers: raw bytes and their hash, decoding, attributes, errors."""

from __future__ import annotations

import functools
import hashlib
import math
import numbers
import os
import re
import threading
import warnings
from pathlib import Path

import numpy as np

from .._atomic import atomic_write_text  # noqa: F401  (re-exported)
from .._json import read_json  # noqa: F401  (re-exported)
from ..errors import InputError, PlaneImpactWarning, caller_level
from ..record import FORCE_CHANNELS
from ..scene import Scene

#: The readers' folder: their warnings point at the first frame outside it (caller_level).
IO_DIR = os.path.dirname(os.path.abspath(__file__))

__all__ = [
    "DEFAULT_AXES",
    "canonical_column",
    "resolve_axes",
    "read_raw",
    "decode",
    "scene_attrs",
    "base_attrs",
    "atomic_write_text",
    "check_plane",
    "meta_key",
    "first_non_increase",
    "LINE_END",
    "read_json",
    "read_decoupling",
    "decouple_columns",
    "DECOUPLE_AXES",
    "exact_floats",
]

#: Default map from record channel to tri-axial column (the seed's sensor: Oz normal,
#: Ox tangential, Oy out of plane).
DEFAULT_AXES = {"Fn": "Fz", "Ft": "Fx", "Fy": "Fy"}
TIME_NAMES = {"time", "t"}
#: A decimal number as the readers accept it (decimal point; commas replaced before).
NUMBER = re.compile(r"^[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?$")
#: Tokens pandas reads as NaN/inf; reported as "NaN or infinite", not as "not a number".
NONFINITE = re.compile(r"^[+-]?(?:nan|inf|infinity)$", re.IGNORECASE)
FORCE_NAMES = {"fn": "Fn", "ft": "Ft", "fx": "Fx", "fy": "Fy", "fz": "Fz"}
FORCE_COLUMNS = tuple(FORCE_NAMES.values())

#: Line ends the readers split on (pandas' C parser does the same): CRLF, LF, bare CR.
LINE_END = re.compile(r"\r\n|\n|\r")

#: Out-of-plane peak above this fraction of the normal peak triggers PlaneImpactWarning.
PLANE_TOLERANCE = 0.05


class BackgroundHash:
    """SHA-256 of a bytes object, or of a file read in blocks, computed in a thread (hashlib
    and file reads release the GIL), so a large file is hashed while pandas' C parser, which
    also releases it, tokenises the table."""

    def __init__(self, source):
        self._digest = None
        self._error = None
        self._path = None if isinstance(source, bytes | bytearray | memoryview) else source
        self._thread = threading.Thread(target=self._run, args=(source,), daemon=True)
        self._thread.start()

    def _run(self, source):
        try:
            if isinstance(source, bytes | bytearray | memoryview):
                self._digest = hashlib.sha256(source).hexdigest()
            else:
                with open(source, "rb") as fh:
                    self._digest = hashlib.file_digest(fh, "sha256").hexdigest()
        except OSError as exc:  # the file vanished or became unreadable meanwhile
            self._error = exc

    def hexdigest(self) -> str:
        self._thread.join()
        if self._error is not None:
            raise InputError(f"cannot read the file ({self._error})", path=self._path)
        return self._digest


def file_path(path) -> Path:
    """``path`` as a :class:`~pathlib.Path`; InputError for a non-path or a directory."""
    try:
        p = Path(os.fspath(path))
    except TypeError:
        raise InputError(f"expected a file path, got {path!r}") from None
    if p.is_dir():
        raise InputError("is a directory, not a file; give the path of one record file", path=p)
    return p


@functools.cache
def exact_floats() -> dict:
    """``pd.read_csv``'s keywords that read every number as the float it was written from.

    Before 3.1, pandas' C parser converts numbers with a fast routine that is one unit in
    the last place off for about a fifth of them (a record written and read back differs),
    and its exact converter must be asked for; pandas 3.1 made the exact one the only one and
    deprecated the keyword."""
    import pandas as pd

    major, minor = (int(n) for n in re.findall(r"\d+", pd.__version__)[:2])
    return {"float_precision": "round_trip"} if (major, minor) < (3, 1) else {}


def read_raw(path, *, background_hash: bool = False) -> tuple[Path, bytes, str]:
    """Read a file's bytes; return ``(path, raw, sha256 hex digest)``.

    With ``background_hash=True`` the third item is a :class:`BackgroundHash` (call its
    ``hexdigest()``) instead of the digest string.

    Raises
    ------
    InputError
        Missing file, a directory, or an unreadable file.
    """
    p = file_path(path)
    try:
        raw = p.read_bytes()
    except FileNotFoundError:
        raise InputError("no such file; check the path", path=p) from None
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror or exc})", path=p) from exc
    if background_hash and len(raw) > (1 << 20):
        return p, raw, BackgroundHash(raw)
    return p, raw, hashlib.sha256(raw).hexdigest()


def decode(raw: bytes, path, encoding: str | None = None) -> str:
    """Decode a text file.

    Accepted without an ``encoding`` argument: UTF-8 with or without a byte-order mark, and
    UTF-16 with a byte-order mark (Excel's "Unicode text"). Anything else must be named with
    ``encoding=`` (e.g. ``"cp1252"`` for old Windows exports): guessing a legacy code page
    would turn a µ into another letter without a word.
    """
    if encoding is not None:
        try:
            text = raw.decode(encoding)
        except (LookupError, TypeError):
            raise InputError(
                f"unknown encoding {encoding!r}; give a codec name such as 'cp1252'", path=path
            ) from None
        except UnicodeDecodeError as exc:
            line = raw[: exc.start].count(b"\n") + 1
            raise InputError(
                f"bytes at offset {exc.start} are not valid {encoding}; "
                "re-save the file as UTF-8 or pass the right encoding=",
                path=path,
                line=line,
            ) from exc
        return text.removeprefix("\ufeff")
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise InputError(
                "starts with a UTF-16 byte-order mark but is not valid UTF-16; "
                "re-save the file as UTF-8",
                path=path,
            ) from exc
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputError(
            f"bytes at offset {exc.start} are not valid UTF-8 (this is not a UTF-8 text file); "
            "re-save it as UTF-8, or for a legacy Windows export call the reader with "
            "encoding='cp1252': pipeline.io.read_sensor(path, encoding='cp1252') for a "
            "sensor CSV, pipeline.io.read_wpd(path, encoding='cp1252', ...) for a "
            "WebPlotDigitizer export",
            path=path,
            line=line,
        ) from exc
    if "\x00" in text:  # valid UTF-8, but no text file holds NUL characters
        raise InputError(
            "holds NUL bytes: UTF-16 text without a byte-order mark, or not a text file; "
            "re-save it as UTF-8 (or pass encoding='utf-16-le' to the reader)",
            path=path,
            line=text[: text.index("\x00")].count("\n") + 1,
        )
    return text


def scene_attrs(fields: dict) -> dict:
    """Validate scene keyword arguments and return them as float attributes."""
    allowed = Scene.field_names()
    out = {}
    for name, value in fields.items():
        if name not in allowed:
            raise InputError(f"unknown keyword {name!r}; scene fields are: {', '.join(allowed)}")
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise InputError(f"scene field {name}={value!r} must be a number (SI units)")
        value = float(value)
        if math.isnan(value):
            raise InputError(f"scene field {name} is NaN; give a number (SI units)")
        out[name] = value
    return out


def base_attrs(path: Path, sha256: str, fmt: str, kind: str) -> dict:
    return {"source": path.name, "sha256": sha256, "format": fmt, "kind": kind}


_KEY_RE = re.compile(r"[^0-9A-Za-z_]+")


def meta_key(key: str) -> str:
    """Attribute name for a metadata key: ``"Sample rate"`` → ``"meta_sample_rate"``."""
    k = _KEY_RE.sub("_", key.strip()).strip("_").lower()
    return f"meta_{k or 'unnamed'}"


def check_plane(forces: dict, path) -> None:
    """Warn (:class:`PlaneImpactWarning`) when max|Fy| > 5 % of max|Fn|."""
    fy = forces.get("Fy")
    fn = forces.get("Fn")
    if fy is None or fn is None or len(fn) == 0:
        return
    peak_y = float(np.max(np.abs(fy)))
    peak_n = float(np.max(np.abs(fn)))
    if peak_y > PLANE_TOLERANCE * peak_n:
        ratio = peak_y / peak_n if peak_n > 0 else math.inf
        warnings.warn(
            f"{Path(os.fspath(path)).name}: out-of-plane peak |Fy| = {peak_y:.4g} N is "
            f"{100 * ratio:.1f} % of the normal peak |Fn| = {peak_n:.4g} N (> "
            f"{100 * PLANE_TOLERANCE:.0f} %); the plane-impact assumption is doubtful",
            PlaneImpactWarning,
            stacklevel=caller_level(IO_DIR),
        )


def to_newtons(values: np.ndarray, factor: float, path, column: str) -> np.ndarray:
    """``values`` × ``factor`` [N] of the force column ``column`` (``values`` finite),
    refused (:class:`InputError`) where the product leaves the float range: a unit or a
    sensitivity typed wrong by orders of magnitude."""
    with np.errstate(over="ignore", invalid="ignore"):
        out = values * factor
    if not np.all(np.isfinite(out)):
        raise InputError(
            f"column {column!r} overflows when converted to newtons (×{factor:g}); "
            "check its unit and sensitivity",
            path=path,
            column=column,
        )
    return out


def first_non_increase(t) -> tuple[int, str] | None:
    """``(i, "repeats" or "goes backwards")`` for the first step ``t[i] → t[i + 1]`` that
    does not go up; ``None`` when ``t`` strictly increases."""
    steps = np.diff(t)
    if np.all(steps > 0):
        return None
    i = int(np.argmax(~(steps > 0)))
    return i, "repeats" if steps[i] == 0 else "goes backwards"


def canonical_column(name: str) -> str:
    """``"F_z"``, ``"fz"``, ``"Fz"`` → ``"Fz"``; ``"Time"`` → ``"time"``; else the name."""
    key = name.replace("_", "").replace(" ", "").lower()
    if key in TIME_NAMES:
        return "time"
    return FORCE_NAMES.get(key, name)


def resolve_axes(columns: dict, axes, p: Path, *, others: dict | None = None, line=None) -> dict:
    """Record channel → (file column, sign).

    ``columns`` holds the recognised force columns by canonical name (``Fx``...); ``others``
    further columns by their name, which ``axes`` may name explicitly (``{"Fn": "Force Z"}``)
    but the default map never takes.
    """
    known = {**(others or {}), **columns}
    available = ", ".join(columns) or "none"
    if axes is not None and not isinstance(axes, dict):
        raise InputError(
            f"axes must be a dict such as {{'Fn': 'Fz', 'Ft': '-Fx'}}, got {axes!r}", path=p
        )
    chosen: dict = {}
    used = set()
    for name, spec in (axes or {}).items():
        if name not in FORCE_CHANNELS:
            raise InputError(
                f"axes key {name!r} is not a record channel; use {', '.join(FORCE_CHANNELS)}",
                path=p,
            )
        if spec is None:
            chosen[name] = None
            continue
        if not isinstance(spec, str) or not spec.strip():
            raise InputError(f"axes[{name!r}] must be a column name such as '-Fx'", path=p)
        spec = spec.strip()
        sign = -1.0 if spec.startswith("-") else 1.0
        col = canonical_column(spec.lstrip("+-").strip())
        if col not in known:
            match = [k for k in known if k.lower() == col.lower()]
            if len(match) != 1:
                raise InputError(
                    f"axes[{name!r}] = {spec!r} names no column of the file "
                    f"(columns: {', '.join(known) or 'none'})",
                    path=p,
                )
            col = match[0]
        if col in used:
            raise InputError(f"axes maps column {col!r} to two channels", path=p)
        used.add(col)
        chosen[name] = (col, sign)
    for name in FORCE_CHANNELS:
        if name in chosen:
            continue
        for col in (name, DEFAULT_AXES[name]):
            if col in columns and col not in used:
                chosen[name] = (col, 1.0)
                used.add(col)
                break
    chosen = {k: chosen[k] for k in FORCE_CHANNELS if chosen.get(k) is not None}
    if "Fn" not in chosen:
        raise InputError(
            f"no normal-force channel: the file has no 'Fn' or 'Fz' column (force columns: "
            f"{available}; other columns: {', '.join(others or {}) or 'none'}); name the "
            "normal-force column, e.g. axes={'Fn': 'Fx'}",
            path=p,
            line=line,
        )
    return chosen


# ------------------------------------------------------------------ cross-talk decoupling
#: Order of the raw axes a decoupling matrix acts on.
DECOUPLE_AXES = ("Fx", "Fy", "Fz")


def read_decoupling(spec) -> tuple[np.ndarray, dict]:
    """A sensor's 3×3 decoupling matrix and its provenance attributes.

    Parameters
    ----------
    spec : array_like or str or os.PathLike
        The matrix (rows: corrected Fx, Fy, Fz; columns: raw Fx, Fy, Fz), or a file
        holding it: ``.json`` (``[[...], [...], [...]]`` or ``{"matrix": [[...]...]}``),
        ``.npy``, or text with three rows of three numbers (separated by commas,
        semicolons or spaces; ``#`` lines are comments) — a calibration sheet's export.

    Returns
    -------
    (numpy.ndarray, dict)
        The matrix, and attributes ``decouple_matrix`` (the nine numbers, row-major),
        ``decouple_axes`` (``"Fx,Fy,Fz"``), ``decouple_source`` (file name or ``"array"``)
        and, for a file, ``decouple_sha256``.

    Raises
    ------
    InputError
        A file that cannot be read or parsed, or a matrix that is not 3×3, finite and
        invertible.
    """
    if isinstance(spec, str | os.PathLike):
        p, raw, sha = read_raw(spec)
        src = p
        try:
            if p.suffix.lower() == ".npy":
                import io as _io

                matrix = np.load(_io.BytesIO(raw), allow_pickle=False)
            elif p.suffix.lower() == ".json":
                data = read_json(p, what="decoupling matrix file")
                matrix = data.get("matrix")
                if matrix is None:
                    raise InputError(
                        'the decoupling JSON needs a "matrix": [[...], [...], [...]]', path=p
                    )
            else:
                rows = [
                    [float(x) for x in re.split(r"[,;\s]+", ln.strip()) if x]
                    for ln in decode(raw, p).splitlines()
                    if ln.strip() and not ln.lstrip().startswith("#")
                ]
                matrix = rows
        except InputError:
            raise
        except Exception as exc:  # numpy's .npy reader raises many types on a corrupt file
            raise InputError(
                f"cannot read a 3×3 decoupling matrix ({exc}); write three rows of three numbers",
                path=p,
            ) from None
        attrs = {"decouple_source": p.name, "decouple_sha256": sha}
    else:
        matrix, src, attrs = spec, None, {"decouple_source": "array"}
    try:
        m = np.array(matrix, dtype=float)
    except (TypeError, ValueError):
        raise InputError(
            f"the decoupling matrix must be 3×3 numbers, got {matrix!r}", path=src
        ) from None
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise InputError(
            f"the decoupling matrix must be 3×3 and finite (rows corrected Fx, Fy, Fz; "
            f"columns raw Fx, Fy, Fz), got shape {m.shape}",
            path=src,
        )
    if np.linalg.cond(m) > 1e12:
        raise InputError("the decoupling matrix is singular; check its entries", path=src)
    attrs["decouple_matrix"] = ",".join(repr(float(x)) for x in m.ravel())
    attrs["decouple_axes"] = ",".join(DECOUPLE_AXES)
    return m, attrs


def decouple_columns(columns: dict, matrix: np.ndarray, path) -> dict:
    """``columns`` with Fx, Fy, Fz [N] replaced by ``matrix @ (Fx, Fy, Fz)``."""
    missing = [c for c in DECOUPLE_AXES if c not in columns]
    if missing:
        raise InputError(
            f"decouple= needs the raw Fx, Fy and Fz columns; the file has no {', '.join(missing)}",
            path=path,
        )
    raw = [columns[c] for c in DECOUPLE_AXES]
    out = dict(columns)
    for i, c in enumerate(DECOUPLE_AXES):
        out[c] = matrix[i, 0] * raw[0] + matrix[i, 1] * raw[1] + matrix[i, 2] * raw[2]
    return out
