"""Exceptions and warnings raised by the pipeline.

Every failure caused by bad input raises :class:`InputError`, a :class:`ValueError`
whose message names the file (where there is one), the line and column where known,
and what the user can do about it.
"""

from __future__ import annotations

__all__ = ["InputError", "PipelineWarning", "PoorFitWarning", "PlaneImpactWarning"]


class InputError(ValueError):
    """Bad input: a malformed file, an impossible scene, an unreachable request.

    Parameters
    ----------
    message : str
        What is wrong and what to do about it.
    path : str or os.PathLike, optional
        The file at fault; prefixed to the message.
    line, column : int or str, optional
        Where in the file (1-based line numbers, column names or 1-based indices).
    """

    def __init__(self, message: str, *, path=None, line=None, column=None):
        where = []
        if path is not None:
            where.append(str(path))
        if line is not None:
            where.append(f"line {line}")
        if column is not None:
            where.append(f"column {column}")
        self.path = None if path is None else str(path)
        self.line = line
        self.column = column
        self.reason = message
        super().__init__(f"{', '.join(where)}: {message}" if where else message)


class PipelineWarning(UserWarning):
    """Base class of the pipeline's warnings."""


class PoorFitWarning(PipelineWarning):
    """A fit converged poorly or its residuals show structure the model misses."""


class PlaneImpactWarning(PipelineWarning):
    """The record casts doubt on the plane-impact assumption (large out-of-plane force)."""
