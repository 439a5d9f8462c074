"""The DOP853 tableau of the compiled kernel: :mod:`flapping.periodic._tableau`'s, re-exported.

The coefficients live in the periodic layer (the fixed-step periodic-orbit solver uses them too);
this module keeps the name :mod:`flapping.fast._compiled` imports, so the kernel's numba cache
(keyed on that file's content) is not invalidated by the move.
"""

from flapping.periodic._tableau import N_STAGES, A, B, C

__all__ = ["N_STAGES", "A", "B", "C"]
