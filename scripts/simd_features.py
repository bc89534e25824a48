"""Print the SIMD features NumPy dispatches to on this CPU (space-separated).

``make test-narrow-simd`` disables them all with ``NPY_DISABLE_CPU_FEATURES``, so NumPy
falls back to its baseline kernels and sums in another order; a test that compares floats
more tightly than their rounding allows then fails here instead of on a user's machine.
"""

from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__  # NumPy ≥ 2

print(" ".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f)))
