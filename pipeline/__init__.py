"""pipeline — impact-force histories to physics.

Stages, one module each, in the order data flows:
``io`` (read) → ``window`` → ``fit`` → ``percussion`` → ``rigid`` / ``contact`` →
``score`` → ``analysis`` → ``report``; ``simulate`` makes records with known truth.
"""

from .errors import InputError
from .scene import Scene

__version__ = "0.1.0"
__all__ = ["InputError", "Scene", "analyse", "__version__"]


def __getattr__(name):
    # analyse pulls in the whole chain; import it lazily so `import pipeline` stays light.
    if name == "analyse":
        from .analysis import analyse

        return analyse
    raise AttributeError(f"module 'pipeline' has no attribute {name!r}")
