"""Errors a user sees as one line (the CLI prints them without a traceback)."""


class GsiInputError(ValueError):
    """Bad input: the message names the key path, the value, and what is allowed.

    Example: ``particles.radius = -0.001: must be > 0 (m)``.
    """


class GsiRunError(RuntimeError):
    """A run that cannot continue (blow-up, lost particles): the message is a diagnosis."""
