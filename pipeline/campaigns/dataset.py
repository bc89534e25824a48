"""The campaign Dataset: gathering per-record results, the campaign's trends, writing.

:func:`assemble` builds the ``record``-dimension Dataset from tasks and their results;
:func:`trends` fits the friction law and the two damping hypotheses to the measured
per-record values; :func:`write_campaign` writes the Dataset, a CSV table and the figures.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__, figures
from .._atomic import atomic_files, atomic_write_bytes, atomic_write_text
from .._json import json_ready
from ..contact import alpha_hunt_crossley, cor_hunt_crossley_alpha
from ..errors import InputError
from ..scene import Scene
from ..score import METRICS, PHASES
from .tasks import FIT_PARAMETERS, OUTCOMES, RecordResult, RecordTask, task_fields

__all__ = ["assemble", "Gathered", "trends", "with_trends", "table_of", "write_campaign"]

#: Per-record numbers besides the outcomes: name → (units, long name).
_NUMBERS = {
    "e_t_rigid": ("1", "tangential restitution of the centre, rigid prediction (Routh)"),
    "omega_rigid": ("rad/s", "spin after impact, rigid prediction (Routh)"),
    "rebound_deg_rigid": ("deg", "rebound angle from the normal, rigid prediction"),
    "mu_record": ("1", "friction coefficient estimated from the record (Ft/Fn plateau)"),
    "mu_rigid": ("1", "friction coefficient the rigid prediction used"),
    "e_rigid": ("1", "restitution the rigid prediction used"),
    "F_max": ("N", "peak normal force in the window"),
    "t_contact": ("s", "duration of the contact window"),
    "noise_Fn": ("N", "noise level of Fn"),
}
_TEXTS = (
    "file",
    "sha256",
    "format",
    "regime",
    "mu_source",
    "e_source",
    "scene_source",
    "scene_json",
)
_LONG = {
    "e_n": "normal restitution, Poisson (measured)",
    "e_t": "tangential restitution of the centre (measured)",
    "omega": "spin after impact (measured)",
    "rebound_deg": "rebound angle from the normal (measured)",
    "Pn_f": "final normal percussion (measured)",
    "Pt_f": "final tangential percussion (measured)",
}


class Gathered:
    """The per-record results of a campaign gathered as columns, as they arrive.

    A :class:`~pipeline.campaigns.tasks.RecordResult` holds its numbers and strings in
    dictionaries (~13 kB a record in memory); gathered here they are one float in an array
    per number and one shared string object per distinct text (~2 kB a record), so that a
    campaign of many records holds its results in little more memory than its Dataset.

    Parameters
    ----------
    n : int — records of the campaign
    """

    def __init__(self, n: int):
        self.n = int(n)
        self.numbers: dict[str, np.ndarray] = {}
        self.texts: dict[str, np.ndarray] = {}
        self._strings: dict[str, str] = {}

    def _text(self, key: str) -> np.ndarray:
        if key not in self.texts:
            self.texts[key] = np.full(self.n, "", dtype=object)
        return self.texts[key]

    def add(self, i: int, r: RecordResult) -> None:
        """Record ``r`` as the ``i``-th result."""
        row = {
            "name": r.name,
            "status": r.status,
            "reason": r.reason,
            "warnings": "\n".join(r.warnings),
            "report_error": r.report_error,
        }
        for k, v in row.items():
            self._text(f"result:{k}")[i] = self._strings.setdefault(v, v)
        for k, v in r.texts.items():
            self._text(k)[i] = self._strings.setdefault(v, v)
        for k, v in r.numbers.items():
            if k not in self.numbers:
                self.numbers[k] = np.full(self.n, np.nan)
            self.numbers[k][i] = v

    @classmethod
    def of(cls, results) -> Gathered:
        """The results of a list, in order."""
        g = cls(len(results))
        for i, r in enumerate(results):
            g.add(i, r)
        return g

    def number(self, key: str) -> np.ndarray:
        """The number ``key`` of every record (NaN where a record has none)."""
        return self.numbers[key].copy() if key in self.numbers else np.full(self.n, np.nan)

    def text(self, key: str) -> np.ndarray:
        """The text ``key`` of every record (``""`` where a record has none)."""
        return self.texts[key].copy() if key in self.texts else np.full(self.n, "", dtype=object)

    def result(self, key: str) -> np.ndarray:
        """``name``, ``status``, ``reason``, ``warnings`` (one a line) or ``report_error``
        of every record."""
        return self.text(f"result:{key}")


def assemble(tasks: list[RecordTask], results) -> xr.Dataset:
    """The campaign Dataset from tasks and their results (a list in the same order, or a
    :class:`Gathered`)."""
    g = results if isinstance(results, Gathered) else Gathered.of(results)
    n = g.n
    names = list(g.result("name"))
    status = g.result("status")
    num = g.number

    angle, speed, v_t0 = num("angle"), num("speed"), num("v_t0")
    for i, t in enumerate(tasks):  # failed records still get their coordinates if known
        if status[i] != "ok":
            try:
                s = Scene.from_dict(task_fields(t)[0])
                angle[i], speed[i], v_t0[i] = s.angle_deg, s.speed, s.v_t0
            except InputError:
                pass
    repeat = _repeats(tasks, angle, speed)
    ds = xr.Dataset(
        coords={
            "record": ("record", np.array(names, dtype=object)),
            "angle": ("record", angle, {"units": "deg", "long_name": "incidence from the normal"}),
            "speed": ("record", speed, {"units": "m/s", "long_name": "impact speed"}),
            "v_t0": ("record", v_t0, {"units": "m/s", "long_name": "initial tangential speed"}),
            "repeat": ("record", repeat, {"long_name": "repeat at this angle and speed"}),
            "phase": ("phase", np.array(PHASES, dtype=object)),
            "metric": ("metric", np.array(METRICS, dtype=object)),
        }
    )
    ds["status"] = ("record", status)
    ds["reason"] = ("record", g.result("reason"))
    ds["warnings"] = (
        "record",
        g.result("warnings"),
        {"long_name": "the library's warnings for the record, one a line"},
    )
    for k in _TEXTS:
        ds[k] = ("record", g.text(k))
    for k, units in OUTCOMES.items():
        ds[k] = ("record", num(k), {"units": units, "long_name": _LONG[k]})
        ds[f"{k}_std"] = (
            "record",
            num(f"{k}_std"),
            {"units": units, "long_name": f"bootstrap standard deviation of {k}"},
        )
    for k, (units, long) in _NUMBERS.items():
        ds[k] = ("record", num(k), {"units": units, "long_name": long})
    for key, long in (("score", "deviation score"), ("score_std", "its bootstrap std")):
        arr = np.array(
            [[num(f"{key}/{p}/{m}") for m in METRICS] for p in PHASES], dtype=float
        ).transpose(2, 0, 1)
        ds[key] = (
            ("record", "phase", "metric"),
            arr.reshape(n, len(PHASES), len(METRICS)),
            {"units": "1", "long_name": f"{long} against Routh's broken line (pipeline.score)"},
        )
    fitted = sorted(k for k in g.numbers if k.startswith("fit_"))
    for k in fitted:
        base = k.removeprefix("fit_").removesuffix("_std")
        ds[k] = ("record", num(k), {"units": FIT_PARAMETERS.get(base, "1")})
    n_failed = int(np.sum(status != "ok"))
    ds.attrs.update(
        {
            "title": "pipeline campaign",
            "pipeline_version": __version__,
            "n_records": n,
            "n_failed": n_failed,
            "options_json": json.dumps(json_ready(tasks[0].options if tasks else {})),
            "conventions": "units in each variable's attrs; *_std: 1-sigma bootstrap spread",
        }
    )
    return ds


def _repeats(tasks, angle, speed) -> np.ndarray:
    """Repeat numbers: the table's, else the n-th record (0, 1, ...) of the same angle and
    speed (rounded to 1e-6 of their unit) in campaign order."""
    seen: dict = {}
    out = np.zeros(len(tasks), dtype=np.int64)
    for i, t in enumerate(tasks):
        if t.repeat is not None:
            out[i] = t.repeat
            continue
        key = (round(float(angle[i]), 6), round(float(speed[i]), 6))
        out[i] = seen.get(key, 0)
        seen[key] = out[i] + 1
    return out


# ------------------------------------------------------------------ trends
def _line_fit(x, y):
    """Ordinary least squares y = a + b·x, with standard errors from the scatter
    (the per-record bootstrap spread covers white noise only; the scatter between records
    also holds what varies from impact to impact). Returns (a, b, sa, sb, rss, n)."""
    A = np.column_stack([np.ones_like(x), x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    rss = float(resid @ resid)
    dof = x.size - 2
    cov = np.linalg.pinv(A.T @ A) * (rss / dof if dof > 0 else np.nan)
    return float(coef[0]), float(coef[1]), *np.sqrt(np.diag(cov)).tolist(), rss, x.size


def trends(ds: xr.Dataset) -> dict:
    """The campaign's trends, fitted to the measured per-record values (``status == ok``).

    - friction: ``mu_a``, ``mu_b`` [s/m] of μ = a + b·v_t0 (Garland & Rogers' linear law)
      and ``mu_const``, fitted to ``mu_record`` by least squares, with standard errors from
      the scatter; AIC of both (Gaussian likelihood with the variance estimated);
    - restitution: ``e_const`` (e the same at every speed) and ``alpha`` [s/m] (the
      Hunt–Crossley material constant held fixed, c = α·v_n0, so e falls with speed:
      :func:`pipeline.contact.cor_hunt_crossley_alpha`), fitted to ``e_n`` against the
      approach speed v_n0; their residual sums and AIC side by side, and which the data
      prefer (lower AIC; equal parameter counts, so the lower residual).

    Returns a dict (strict JSON after :func:`pipeline._json.json_ready`); values are NaN
    where too few records allow the fit (two for a constant, three for a line).
    """
    from scipy import optimize

    ok = (ds["status"] == "ok").values
    out: dict = {"n_used": int(ok.sum())}
    v_t0 = ds["v_t0"].values[ok]
    mu = ds["mu_record"].values[ok]
    good = np.isfinite(v_t0) & np.isfinite(mu)
    x, y = v_t0[good], mu[good]
    nan = float("nan")
    if x.size >= 3 and np.ptp(x) > 0:
        a, b, sa, sb, rss, n = _line_fit(x, y)
        out["friction"] = {
            "law": "mu = mu_a + mu_b * v_t0",
            "mu_a": a,
            "mu_a_std": sa,
            "mu_b": b,
            "mu_b_std": sb,
            "aic_linear": _aic(rss, n, 2),
        }
    else:
        out["friction"] = {"law": "mu = mu_a + mu_b * v_t0", "mu_a": nan, "mu_b": nan}
    if y.size >= 2:
        out["friction"].update(
            mu_const=float(np.mean(y)),
            mu_const_std=float(np.std(y, ddof=1) / np.sqrt(y.size)),
            aic_constant=_aic(float(np.sum((y - y.mean()) ** 2)), y.size, 1),
        )
    speed = ds["speed"].values[ok]
    angle = ds["angle"].values[ok]
    v_n0 = speed * np.cos(np.radians(angle))
    e = ds["e_n"].values[ok]
    good = np.isfinite(v_n0) & np.isfinite(e) & (v_n0 > 0) & (e > 0)
    vn, en = v_n0[good], e[good]
    rest: dict = {"n_used": int(en.size)}
    if en.size >= 2:
        e0 = float(np.mean(en))
        rss_e = float(np.sum((en - e0) ** 2))

        def resid(log_alpha):
            return cor_hunt_crossley_alpha(np.exp(log_alpha), vn) - en

        # start from the α that gives the mean e at the mean approach speed

        start = math.log(float(alpha_hunt_crossley(min(e0, 0.999999), float(np.mean(vn)))))
        sol = optimize.least_squares(resid, [start], method="lm")
        alpha = float(np.exp(sol.x[0]))
        rss_a = float(np.sum(sol.fun**2))
        dof = en.size - 1
        J = sol.jac[:, 0] / alpha  # d e / d alpha (the fit ran in log alpha)
        s_alpha = math.sqrt(rss_a / dof / float(J @ J)) if dof > 0 and J @ J > 0 else nan
        rest.update(
            e_const=e0,
            e_const_std=float(np.std(en, ddof=1) / np.sqrt(en.size)),
            rss_constant_e=rss_e,
            aic_constant_e=_aic(rss_e, en.size, 1),
            alpha=alpha,
            alpha_std=s_alpha,
            rss_constant_alpha=rss_a,
            aic_constant_alpha=_aic(rss_a, en.size, 1),
            preferred="constant_alpha" if rss_a < rss_e else "constant_e",
        )
    out["restitution"] = rest
    return out


def _aic(rss: float, n: int, k: int) -> float:
    """AIC of a least-squares fit with Gaussian errors of unknown variance:
    n·ln(RSS/n) + 2(k + 1) (the variance counts as a parameter)."""
    if n <= 0 or not rss > 0:
        return float("nan")
    return float(n * math.log(rss / n) + 2 * (k + 1))


# ------------------------------------------------------------------ writing
def write_campaign(ds: xr.Dataset, out) -> dict:
    """Write a campaign's Dataset (``campaign.nc``), its table (``campaign.csv``) and
    figures into the folder ``out``, atomically and together
    (:func:`pipeline._atomic.atomic_files`). Returns ``{name: path}``.

    The netCDF file is made in memory (as large as the file: a few MB for 10,000 records)
    and written by :func:`pipeline._atomic.atomic_write_bytes`: HDF5 never writes to a
    disk that can fill under it (it spews errors and may crash the process when it does),
    and a full disk is one :class:`~pipeline.errors.OutputError`."""
    out = Path(out)
    written = {"campaign.nc": out / "campaign.nc", "campaign.csv": out / "campaign.csv"}
    with atomic_files(out):  # all of them, or none (the previous stay)
        atomic_write_bytes(written["campaign.nc"], ds.to_netcdf(engine="h5netcdf"))
        atomic_write_text(written["campaign.csv"], table_of(ds).to_csv(index=False))
        for name, fig in figures.campaign_figures(ds).items():
            written[name] = figures.save(fig, out / name)
    return written


def table_of(ds: xr.Dataset):
    """The per-record table of a campaign (pandas DataFrame): coordinates, status, regime,
    the measured outcomes with their std, the rigid prediction and the total score."""
    import pandas as pd

    cols = {
        "record": ds["record"].values,
        "status": ds["status"].values,
        "angle_deg": ds["angle"].values,
        "speed_m_s": ds["speed"].values,
        "v_t0_m_s": ds["v_t0"].values,
        "repeat": ds["repeat"].values,
        "regime": ds["regime"].values,
    }
    for k, units in OUTCOMES.items():
        u = "" if units == "1" else "_" + units.replace("/", "_").replace(" ", "")
        cols[f"{k}{u}"] = ds[k].values
        cols[f"{k}_std{u}"] = ds[f"{k}_std"].values
    for k in ("e_t_rigid", "omega_rigid", "rebound_deg_rigid", "mu_record"):
        cols[k] = ds[k].values
    for m in ("area", "max_distance", "Pt_drop"):
        cols[f"score_{m}"] = ds["score"].sel(phase="total", metric=m).values
    for k in ds.data_vars:
        if str(k).startswith("fit_"):
            cols[str(k)] = ds[k].values
    cols["reason"] = ds["reason"].values
    return pd.DataFrame(cols)


def with_trends(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with :func:`trends` added (``attrs["trends_json"]`` and ``trend_*`` scalars)."""
    tr = trends(ds)
    ds.attrs["trends_json"] = json.dumps(json_ready(tr), allow_nan=False, sort_keys=True)
    units = {"mu_b": "s/m", "mu_b_std": "s/m", "alpha": "s/m", "alpha_std": "s/m"}
    for group in ("friction", "restitution"):
        for k, v in tr.get(group, {}).items():
            if isinstance(v, float):
                ds[f"trend_{k}"] = ((), v, {"units": units.get(k, "1"), "group": group})
    return ds
