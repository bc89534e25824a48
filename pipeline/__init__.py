"""pipeline — impact-force histories to physics.

Stages, one module each, in the order data flows:
``io`` (read) → ``window`` → ``smooth`` → ``percussion`` → ``rigid`` / ``contact`` →
``fit`` (contact parameters) → ``score`` → ``analysis`` → ``report``; ``simulate`` makes
records with known truth.
"""

from .errors import InputError
from .scene import Scene

__version__ = "0.1.0"
__all__ = [
    "InputError",
    "Scene",
    "advise",
    "analyse",
    "campaign",
    "fit_contact",
    "fit_campaign",
    "fit_outcomes",
    "select_model",
    "__version__",
]


_SUBMODULES = {
    "advice",
    "analysis",
    "campaigns",
    "contact",
    "errors",
    "export",
    "figures",
    "fit",
    "io",
    "notebook_report",
    "percussion",
    "record",
    "report",
    "rigid",
    "scene",
    "score",
    "sensor_model",
    "simulate",
    "smooth",
    "window",
}


def __getattr__(name):
    # The stages (and analyse, which pulls in the whole chain) load on first use, so
    # `import pipeline` stays light and `pipeline.io.load(...)` works after it.
    import importlib

    if name == "analyse":
        return importlib.import_module(".analysis", __name__).analyse
    if name == "advise":
        return importlib.import_module(".advice", __name__).advise
    if name == "fit_outcomes":
        return importlib.import_module(".fit.outcomes", __name__).fit_outcomes
    if name in ("fit_contact", "fit_campaign", "select_model"):
        return getattr(importlib.import_module(".fit", __name__), name)
    if name == "campaign":
        return importlib.import_module(".campaigns", __name__).campaign
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'pipeline' has no attribute {name!r}")
