"""Exception hierarchy of rustfrac.

Every error rustfrac raises derives from :class:`RustfracError`. Bad input (a parameter out of
range, a wrong type, an unknown or missing key) is also a :class:`ValueError` (or
:class:`TypeError` for wrong types), so generic handlers keep working. The native module
``rustfrac._core`` raises these same classes.

Results that ran but may be inaccurate (e.g. volumetric locking of the Q4 elements in plane strain
near nu = 0.5) are reported with :class:`AccuracyWarning` (a ``UserWarning``), and listed in
``result.meta["warnings"]``.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "WARNING_CLASSES",
    "AccuracyWarning",
    "CheckpointIOError",
    "DiscretisationWarning",
    "IllConditionedWarning",
    "InternalError",
    "InvalidParameterError",
    "InvalidResultError",
    "InvalidTypeError",
    "LockingWarning",
    "MethodNotAvailableError",
    "MissingParameterError",
    "OutOfMemoryError",
    "OutputError",
    "ResultNotFoundError",
    "RustfracError",
    "SeparatedError",
    "SingularSystemError",
    "UnknownParameterError",
]


class RustfracError(Exception):
    """Base class of every rustfrac error."""


class InvalidParameterError(RustfracError, ValueError):
    """A parameter is outside its valid range; the message names it and the range.

    ``param`` holds the parameter name when known.
    """

    def __init__(self, message: str, param: str | None = None) -> None:
        super().__init__(message)
        self.param = param


class UnknownParameterError(InvalidParameterError):
    """A scene holds a key rustfrac does not know (a typo, most often)."""


class MissingParameterError(InvalidParameterError):
    """A scene lacks a key it must state (``method``; a circle hole's ``radius``: the keys the
    schema marks ``required``)."""


class InvalidTypeError(InvalidParameterError, TypeError):
    """A parameter has the wrong type (e.g. a string where a number is expected)."""


class SingularSystemError(RustfracError):
    """The system matrix is singular or not positive definite: a rigid-body mode is not removed."""


class SeparatedError(SingularSystemError):
    """The body separated into disconnected parts (e.g. the crack cut through the plate)."""


class InternalError(RustfracError, RuntimeError):
    """An internal failure of the numerical core (e.g. a caught Rust panic). Please report it."""


class OutOfMemoryError(RustfracError, MemoryError):
    """A run needs more memory than the machine's free memory or the process's address-space
    limit (``ulimit -v``) leaves: refused before the model is built, the message names the
    estimated size and what is available (or a large buffer's allocation failed)."""


class CheckpointIOError(RustfracError, OSError):
    """A checkpoint file could not be read or written (the message names the path)."""


class OutputError(RustfracError, OSError):
    """An output folder cannot be written: ``--out`` names a file, the folder is read-only, the
    disk is full, ... The message names the folder and the reason; ``path`` holds the folder and
    ``fallback`` the temporary folder the output was saved to instead (None if it was not)."""

    def __init__(self, message: str, path: Any = None, fallback: Any = None) -> None:
        super().__init__(message)
        self.path = path
        self.fallback = fallback

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class InvalidResultError(RustfracError, ValueError):
    """A saved result (or a fig7 / sweep output folder) cannot be read back: not a rustfrac
    result, an unsupported ``format_version``, a value out of its range, arrays that do not match
    ``result.json``, or files of two different saves. The message names the file and the field;
    ``path`` and ``field`` hold them."""

    def __init__(self, message: str, path: Any = None, field: str | None = None) -> None:
        super().__init__(message)
        self.path = path
        self.field = field


class ResultNotFoundError(InvalidResultError, FileNotFoundError):
    """The result folder, or a file of it, does not exist (also a ``FileNotFoundError``)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class IllConditionedWarning(RuntimeWarning):
    """A solve's condition estimate exceeded ``rustfrac._core.COND_WARN`` (1e12): round-off may
    reach ``condition * 2.2e-16`` relative in the solution. The result is still returned; its
    ``warnings`` and ``condition`` say which solve. Above ``rustfrac._core.COND_SINGULAR`` (1e14)
    the system counts as numerically singular: :class:`SingularSystemError` instead."""


class MethodNotAvailableError(RustfracError, NotImplementedError):
    """The scene is valid, but its method is not bound in this build yet."""


class AccuracyWarning(UserWarning):
    """The run completed, but a known discretisation limit makes its numbers less accurate than
    usual (the message says which and by how much it was measured to matter); e.g. plane-strain
    nu >= 0.49, where the fully integrated Q4 elements lock, a PD horizon factor m < 2 (too few
    bonds per node), or PD nodes detached (grounded) during the SLA. Issued with
    :func:`warnings.warn` and recorded in ``Result.meta["warnings"]``; the subclasses
    :class:`LockingWarning` and :class:`DiscretisationWarning` say which kind."""


class LockingWarning(AccuracyWarning):
    """Plane-strain nu >= 0.49: the fully integrated Q4 elements lock (native kind ``"locking"``)."""


class DiscretisationWarning(AccuracyWarning):
    """A PD discretisation limit: horizon factor m < 2, or nodes grounded after losing all
    stiffness along a direction (native kind ``"discretisation"``)."""


#: Python warning class of each native warning kind (``rustfrac._core.WARNING_KINDS``)
WARNING_CLASSES: dict[str, type[Warning]] = {
    "ill_conditioned": IllConditionedWarning,
    "locking": LockingWarning,
    "discretisation": DiscretisationWarning,
}


class PlotDataError(RustfracError, ValueError):
    """A plot, view or audit needs data the result does not carry (e.g. the damage map of an
    XFEM result, the load path of a single solve, the work-conjugate load of an energy audit);
    the message says what is missing and for which methods it exists."""


__all__ += ["PlotDataError"]
