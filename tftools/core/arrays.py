"""The numpy array types tftools passes around, named once."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

Int64Array = npt.NDArray[np.int64]  # stamps and record times (ns), arrival numbers
Int32Array = npt.NDArray[np.int32]  # frame and publisher ids
Int8Array = npt.NDArray[np.int8]
IntpArray = npt.NDArray[np.intp]  # row indices
UInt8Array = npt.NDArray[np.uint8]  # flags, bytes
BoolArray = npt.NDArray[np.bool_]
FloatArray = npt.NDArray[np.float64]  # translations, rotations, values (N, 7)
