"""The one exception family of impactsym.

Every error names the argument and the violated condition, so that the CLI can print it
as it is (exit status 2) and a Python caller can catch one base class.

>>> from impactsym.errors import ImpactInputError, ImpactError
>>> issubclass(ImpactInputError, ImpactError) and issubclass(ImpactInputError, ValueError)
True
"""

from __future__ import annotations

__all__ = ["ImpactError", "ImpactInputError", "DomainError", "NonTermination", "UndecidableSign",
           "VerificationError", "DerivationError", "TimeLimitExceeded"]


class ImpactError(Exception):
    """Base class of every error impactsym raises on purpose (CLI exit status 2)."""


class ImpactInputError(ImpactError, ValueError):
    """Malformed or inadmissible input: wrong shape, NaN, a mass matrix that is not SPD, ...

    Parameters
    ----------
    argument : str
        The name of the offending argument, as the user gave it (``"mass_matrix"``).
    condition : str
        The violated condition, in words.
    """

    def __init__(self, argument: str, condition: str):
        self.argument = argument
        self.condition = condition
        super().__init__(f"{argument}: {condition}")


class DomainError(ImpactError, ValueError):
    """A request the law cannot satisfy: a parameter outside the law's domain,
    a velocity that does not approach, no admissible outcome."""


class NonTermination(ImpactError, RuntimeError):
    """An iterative resolution hit its configured cap (the message names the cap)."""


class UndecidableSign(ImpactError, ArithmeticError):
    """An exact sign could not be certified (for instance a transcendental expression
    that is zero to every precision tried). Never guessed: raised instead."""


class VerificationError(AssertionError):
    """A certified or exact outcome failed the check its law runs before returning it
    (``H v⁺ ≥ 0`` on the closed contacts, the kinetic energy, the momentum balance, the count).

    This is a bug in impactsym, not bad input: it is deliberately *not* an :class:`ImpactError`
    (the CLI exits with status 1), and it is raised instead of returning the outcome.

    >>> issubclass(VerificationError, ImpactError)
    False
    """

    def __init__(self, law: str, condition: str):
        self.law = law
        self.condition = condition
        super().__init__(f"{law}: verification of the outcome failed: {condition} (a bug in impactsym; "
                         "the outcome was not returned)")


class DerivationError(AssertionError):
    """A step of a SymPy derivation that must hold (an identity, a branch equality, a proof
    obligation) does not: a bug in the derivation, raised explicitly so that ``python -O``
    cannot skip the check (``assert`` statements vanish under ``-O``).

    >>> issubclass(DerivationError, ImpactError)
    False
    """


class TimeLimitExceeded(ImpactError, TimeoutError):
    """A computation ran past the time limit its caller set (the CLI's ``--timeout``)."""
