"""The joint fit of a campaign: :func:`pipeline.fit_campaign` over the analysed records.

One fit of every record's Fn and Ft with the modulus shared, friction μ = a + b·v_t0 (or
constant) and both damping hypotheses (e constant; Hunt–Crossley α constant, e falling with
speed), compared by AIC (Garland & Rogers 2009, doi:10.1115/1.3086432; Hunt & Crossley
1975, doi:10.1115/1.3423596). :func:`with_joint_fit` stores the best hypothesis' values and
standard errors as ``joint_<name>`` scalars and every hypothesis' row of
:meth:`~pipeline.fit.CampaignFit.compare` in ``attrs["joint_fit_json"]``. Where the fitter is not
installed, or fewer than two records were analysed, the Dataset is returned unchanged.
The fit reads the records from their files one at a time and keeps them on disk
(:mod:`pipeline.fit.store`); on a cluster the workers read and prepare them and run the
fit's evaluations (the ``executor`` option of :func:`pipeline.fit_campaign`).
"""

from __future__ import annotations

import json
import logging
import math
import warnings

from .._json import json_ready
from ..errors import InputError, PipelineWarning
from ..fit import fit_campaign
from ..precision import reads_as
from ..scene import Scene
from ..sidecar import sensor_from_sidecar
from .tasks import FIT_PARAMETERS, read_task_record

__all__ = ["joint_fit", "with_joint_fit"]

log = logging.getLogger(__name__)

#: Units of the joint fit's parameters besides :data:`FIT_PARAMETERS` (``alpha`` is the
#: law's material constant: Thornton's reads as the yield speed v_y, ``reads_as``).
_UNITS = {**FIT_PARAMETERS, "alpha": "s/m", "v_y": "m/s", "mu_a": "1", "mu_b": "s/m"}


def joint_fit(tasks, ds, **options) -> dict | None:
    """The joint fit of the ``ok`` records (module notes), as a strict-JSON dict, or None.

    Parameters
    ----------
    tasks : list of RecordTask — the campaign's tasks, in the Dataset's order
    ds : xarray.Dataset — the campaign (its ``status`` picks the records)
    **options — passed to :func:`pipeline.fit_campaign` (``n_boot``, ``seed``, ...)
    """
    ok = [t for t, s in zip(tasks, ds["status"].values, strict=True) if s == "ok"]
    if len(ok) < 2:
        return None
    records = ok  # each read where the fit prepares it, once (read_task_record)
    scenes = [
        Scene.from_dict(json.loads(str(j)))
        for j, s in zip(ds["scene_json"].values, ds["status"].values, strict=True)
        if s == "ok"
    ]
    sensors = _stated_sensors(ok)
    if sensors is not None:
        options = {"sensor": sensors, **options}
    fit = fit_campaign(
        records, scenes, mu_law="linear_vt0", damping="constant_e", load=read_task_record,
        **options,
    )  # fmt: skip
    table = fit.compare()
    best = table.iloc[0]
    key = (str(best["mu_law"]), str(best["damping"]))
    chosen = fit.hypotheses.get(key, fit)
    return json_ready(
        {
            "records": [t.name for t in ok],
            "normal": chosen.model.normal,
            "hypothesis": {"mu_law": key[0], "damping": key[1]},
            "values": dict(chosen.values),
            "stderr": dict(chosen.stderr),
            "compare": table.to_dict("records"),
        }
    )


def _stated_sensors(tasks) -> list | None:
    """The sensor each task's sidecar states (as its own fit takes it,
    :func:`pipeline.sidecar.sensor_from_sidecar`), or None where none states one. Equal
    blocks are one object: a campaign of one rig keeps one, not one per record."""
    seen, out = {}, []
    for t in tasks:
        block = sensor_from_sidecar(t.path)
        key = json.dumps(block, sort_keys=True)
        out.append(seen.setdefault(key, block))
    return None if all(b is None for b in out) else out


def with_joint_fit(ds, tasks, **options):
    """``ds`` with the joint fit stored (module notes); a failed joint fit is logged and
    noted in ``attrs["joint_fit_error"]``, its warnings (a poor fit) in
    ``attrs["joint_fit_warnings"]``; the per-record results stay."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            jf = joint_fit(tasks, ds, **options)
        except Exception as exc:  # the per-record results stand without it
            log.warning("joint fit: %s", exc)
            reason = str(exc) if isinstance(exc, InputError) else f"{type(exc).__name__}: {exc}"
            ds.attrs["joint_fit_error"] = reason
            jf = None
    msgs = [
        f"{w.category.__name__}: {w.message}"
        for w in caught
        if issubclass(w.category, PipelineWarning)
    ]
    if msgs:
        ds.attrs["joint_fit_warnings"] = "\n".join(msgs)
    if jf is None:
        return ds
    ds.attrs["joint_fit_json"] = json.dumps(jf, allow_nan=False, sort_keys=True)
    for name, v in jf["values"].items():
        unit = _UNITS.get(reads_as(name, jf.get("normal")))
        if isinstance(v, (int, float)) and unit is not None:
            se = jf["stderr"].get(name)
            ds[f"joint_{name}"] = ((), float(v), {"units": unit})
            ds[f"joint_{name}_std"] = ((), math.nan if se is None else float(se), {"units": unit})
    return ds
