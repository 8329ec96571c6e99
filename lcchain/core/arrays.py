"""The numpy array types lcchain's annotations name, by what they hold.

Importing this module imports numpy: a module that keeps numpy out of its import (lcchain.core's checks, a
command that runs no theory) names these under ``TYPE_CHECKING`` only.
"""

from __future__ import annotations

from typing import TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["FloatArray"]

#: An array of float64: times, signals, frequencies, weights.
FloatArray: TypeAlias = npt.NDArray[np.float64]
