"""Sparse matrices as the compiled kernels of both transients take them.

:class:`Csr` packs a matrix in compressed sparse row form (numba compiles a named tuple of
arrays as one argument); :func:`csr` builds it from any scipy/numpy matrix; :func:`row_dot`
(numba) is row i times a vector, the one sparse product the lateral and the torsional
transients build theirs from.

A compiled call counts a reference to every array it is passed (and releases it on return):
a small function called in a loop takes the arrays it reads, not their pack, or is inlined.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numba import njit
from numpy.typing import NDArray

from .jit import configure_cache

configure_cache()  # before the first @njit(cache=True): numba's cache outside the package

__all__ = ["Csr", "csr", "row_dot"]


class Csr(NamedTuple):
    """A sparse matrix by rows: row i holds ``data[p]`` at column ``indices[p]`` for p in
    ``indptr[i]:indptr[i + 1]`` (int64 indices, float64 values)."""

    indptr: NDArray
    indices: NDArray
    data: NDArray


def csr(A, *, drop_zeros: bool = False) -> Csr:
    """``A`` (dense or sparse) as a :class:`Csr`, column indices sorted in each row;
    ``drop_zeros``: stored zeros removed."""
    A = sp.csr_array(A)
    if drop_zeros:
        A.eliminate_zeros()
    A.sort_indices()
    return Csr(A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data.astype(float))


@njit(cache=True, inline="always")
def row_dot(indptr, indices, data, i, x):
    """Row i of the :class:`Csr` (indptr, indices, data) times x (summed in the row's stored
    order). Inlined where it is called: the caller's compile flags apply."""
    s = 0.0
    for p in range(indptr[i], indptr[i + 1]):
        s += data[p] * x[indices[p]]
    return s
