"""Exception and warning types of hyperlattice.

Bad input raises the built-in :class:`ValueError` (with a plain sentence); the classes here
are for numerical trouble detected by the package itself.
"""


class HyperlatticeError(RuntimeError):
    """A computation could not deliver a trustworthy result."""


class ConvergenceError(HyperlatticeError):
    """An iterative method, root search or series did not reach its tolerance."""


class ConvergenceWarning(UserWarning):
    """A result was returned, but a convergence criterion was only nearly met."""


class RangeWarning(UserWarning):
    """A value overflows the float64 range and is returned as ``inf`` (its true size is finite)."""
