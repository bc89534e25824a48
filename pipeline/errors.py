"""Exceptions and warnings raised by the pipeline.

Every failure caused by bad input raises :class:`InputError`, a :class:`ValueError`
whose message names the file (where there is one), the line and column where known,
and what the user can do about it. A fault of the machine while an output is written (a
full disk, a folder turned read-only or gone) raises :class:`OutputError`, an
:class:`OSError` whose one-line message names the output and what its place still holds.
"""

from __future__ import annotations

import errno as _errno
import os
import sys

__all__ = [
    "InputError",
    "OutputError",
    "PipelineWarning",
    "PoorFitWarning",
    "PlaneImpactWarning",
    "NormalLawWarning",
    "SensorFilterWarning",
    "ImpulseMismatchWarning",
    "GeometryWarning",
    "ColouredNoiseWarning",
    "SensorDynamicsWarning",
    "caller_level",
]


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


class OutputError(OSError):
    """An output could not be written: the disk is full, its folder turned read-only, lost
    its permission or vanished, or the device failed.

    Outputs are written atomically (:mod:`pipeline._atomic`), so the output's place holds
    the previous output or the new one, whole; the message is one line that says so:
    ``the disk is full: cannot write build/c/campaign.nc (No space left on device);
    build/c holds the previous run, untouched``.

    Parameters
    ----------
    errno : int — the system's error number (``errno.ENOSPC``, ...)
    strerror : str — the system's words for it
    filename : str or os.PathLike — the output as the caller named it (never a temporary)
    kept : str — what the output's place still holds
    action : str — what could not be done, before the path [``"cannot write"``]

    Attributes
    ----------
    fault : str — ``"full"`` (no space or quota left), ``"device"`` (an input/output
        error: the disk or the network file system failed) or ``"unwritable"`` (read-only,
        no permission, the folder vanished, anything else)
    """

    def __init__(self, errno, strerror, filename, kept="", action="cannot write"):
        super().__init__(errno, strerror, None if filename is None else os.fspath(filename))
        self.kept = kept
        self.action = action

    @property
    def fault(self) -> str:
        if self.errno in _FULL:
            return "full"
        return "device" if self.errno == _errno.EIO else "unwritable"

    def __str__(self) -> str:
        what = _FAULT_WORDS.get(self.errno, "the output cannot be written")
        text = f"{what}: {self.action} {self.filename} ({self.strerror})"
        return f"{text}; {self.kept}" if self.kept else text


_FULL = {_errno.ENOSPC, _errno.EDQUOT, _errno.EFBIG}
_FAULT_WORDS = {
    _errno.ENOSPC: "the disk is full",
    _errno.EDQUOT: "the disk quota is used up",
    _errno.EFBIG: "the file is too large for its file system",
    _errno.EROFS: "the file system is read-only",
    _errno.EACCES: "no permission to write there",
    _errno.EPERM: "no permission to write there",
    _errno.ENOENT: "the output folder vanished",
    _errno.ENOTDIR: "the output folder vanished",
    _errno.ESTALE: "the output folder vanished",
    _errno.EIO: "the disk failed (input/output error)",
}


class PipelineWarning(UserWarning):
    """Base class of the pipeline's warnings."""


class PoorFitWarning(PipelineWarning):
    """A fit converged poorly or its residuals show structure the model misses."""


class PlaneImpactWarning(PipelineWarning):
    """The record casts doubt on the plane-impact assumption (large out-of-plane force)."""


# The causes a contact fit's verdict names (pipeline.fit.verdict): the model, the sensor or
# the scene does not describe the record, each in its own words. Coloured noise is no
# misfit (the fit models the noise it measures) but is said all the same.
class NormalLawWarning(PoorFitWarning):
    """Another normal force law describes the record decisively better."""


class SensorFilterWarning(PoorFitWarning):
    """The record's rise contradicts the sensor's stated filter (cut-off or order)."""


class ImpulseMismatchWarning(PoorFitWarning):
    """The model's percussion does not end where the measured integral of the force does."""


class GeometryWarning(PoorFitWarning):
    """The contact normal turns on a curved target by more than the model allows for."""


class ColouredNoiseWarning(PipelineWarning):
    """The record's noise is correlated (measured before the trigger); the fit whitens it."""


class SensorDynamicsWarning(PipelineWarning):
    """The record shows a transducer mode, a discharge or a zero shift the sensor's
    description does not state; the fit models it."""


# ------------------------------------------------------------ plausibility before physics
# Each check of a record a careful experimentalist would make has its own class, so a user
# can catch or filter exactly one kind. Errors where the record cannot give a right answer
# (a clipped peak, a pulse cut by the file's end, a unit off by 10³); warnings where the
# analysis goes on, on the part of the record it can trust (the first of two impacts, a
# record with one spike before the trigger). pipeline.window and pipeline.plausibility
# say which check raises which, with the number that tripped it.
__all__ += [
    "NoPulseError",
    "TruncatedPulseError",
    "SignFlipError",
    "ClippedSignalError",
    "UnitMismatchError",
    "PlausibilityWarning",
    "MultipleImpactWarning",
    "TriggerGlitchWarning",
    "SpikeWarning",
    "SampleRateWarning",
    "ContactTimeWarning",
    "PeakForceWarning",
    "ImpulseWarning",
    "ImpossibleOutcomeWarning",
    "NormalRestitutionWarning",
    "TangentialRestitutionWarning",
    "EnergyGainWarning",
    "FrictionBoundWarning",
    "FrictionDirectionWarning",
]


class NoPulseError(InputError):
    """No contact pulse stands above the record's noise."""


class TruncatedPulseError(InputError):
    """The contact pulse runs past the start or the end of the record (the file was cut
    mid-pulse)."""


class SignFlipError(InputError):
    """The normal force is a tensile (negative) pulse: the channel's sign is flipped."""


class ClippedSignalError(InputError):
    """A force channel sits at its maximum for several samples: the ADC saturated."""


class UnitMismatchError(InputError):
    """A quantity is off from what the scene or the file states by a unit factor
    (10³, 10⁶...): the unit written in the file, or passed, is not the unit of the values.

    Attributes
    ----------
    quantity : str — ``"time"`` or ``"force"``
    ratio : float — measured over expected [-]
    suggested : str or None — the unit the values fit, where one does
    """

    def __init__(self, message, *, quantity, ratio, suggested=None, **where):
        super().__init__(message, **where)
        self.quantity = quantity
        self.ratio = ratio
        self.suggested = suggested


class PlausibilityWarning(PipelineWarning):
    """Base class of the warnings of the plausibility checks."""


class MultipleImpactWarning(PlausibilityWarning):
    """A second pulse inside or after the contact window (a rebound strike); the analysis
    keeps to the first."""


class TriggerGlitchWarning(PlausibilityWarning):
    """A spike of one to three samples outside the contact pulse; it is ignored."""


class SpikeWarning(PlausibilityWarning):
    """Isolated samples no force history can make (electrical spikes): repaired by the
    window, left out of the fits."""


class SampleRateWarning(PlausibilityWarning):
    """The sample rate stated in the file disagrees with its time column."""


class ContactTimeWarning(PlausibilityWarning):
    """The contact lasts much longer or shorter than Hertz theory predicts for the scene."""


class PeakForceWarning(PlausibilityWarning):
    """The peak normal force is far from Hertz theory's for the scene."""


class ImpulseWarning(PlausibilityWarning):
    """The normal impulse is outside m*·v_n0·[1, 2], the range e ∈ [0, 1] allows."""


# After the physics: outcomes a passive impact cannot have (pipeline.plausibility,
# check_outcomes). Each names the bound it breaks and the likeliest cause.
class ImpossibleOutcomeWarning(PlausibilityWarning):
    """A measured outcome breaks an energy or momentum bound of a passive impact."""


class NormalRestitutionWarning(ImpossibleOutcomeWarning):
    """e_n > 1: the ball leaves the surface faster than it came."""


class TangentialRestitutionWarning(ImpossibleOutcomeWarning):
    """e_t > 1 with no spin and a still surface: friction sped the ball up along the slip."""


class EnergyGainWarning(ImpossibleOutcomeWarning):
    """The ball leaves with more kinetic energy (translation and spin) than it came with."""


class FrictionBoundWarning(ImpossibleOutcomeWarning):
    """The tangential percussion exceeds μ·Pn for the scene's (known) μ."""


class FrictionDirectionWarning(ImpossibleOutcomeWarning):
    """At the start of the contact the friction force pushes along the slip."""


def caller_level(where) -> int:
    """``stacklevel`` that points a warning at the first frame outside ``where`` (a folder,
    such as the readers' ``pipeline/io``, whose functions reach each other through one to
    three calls: load → read_sensor → ...; or one module's file). Call it from the function
    that warns."""
    where = str(where)
    inside = (
        (lambda f: f == where) if where.endswith(".py") else (lambda f: os.path.dirname(f) == where)
    )
    frame, level = sys._getframe(1), 1  # the frame that calls warnings.warn
    while frame is not None and inside(frame.f_code.co_filename):
        frame, level = frame.f_back, level + 1
    return level
