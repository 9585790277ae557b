"""The compiled path's kernels (generated/kernels.c and kernels_avx2.c, which include the
generated/<mechanism>_kernels.c) built into pkm._kernels at install: optional, so that pkm installs
without a C compiler and evaluates with CasADi's interpreter.

IEEE semantics are kept: no -ffast-math and no contraction into fused multiply-adds; -fno-math-errno and
-fno-trapping-math change no value (sqrt compiles to its instruction, selects to blends), nor does
-fno-thread-jumps, which keeps selects that share a condition in straight-line code (threaded into
branches, they stop the loop over a block from vectorising). Every kernel
is compiled for the generic x86-64 (kernels.c) and for AVX2 (kernels_avx2.c), and kernels.c picks one
when called, instead of -march=native; the vector functions come from glibc's libmvec.
"""

import platform
import sys

from setuptools import Extension, setup

VECTOR = sys.platform == "linux" and platform.machine() == "x86_64"

setup(
    ext_modules=[
        Extension(
            "pkm._kernels",
            sources=["pkm/_kernels.c", "generated/kernels.c", "generated/kernels_avx2.c"],
            depends=["generated/kernels_isa.c", "generated/*_kernels.c"],
            extra_compile_args=["-O3", "-fopenmp-simd", "-fno-math-errno", "-fno-trapping-math", "-fno-tree-sink",
                                "-fno-thread-jumps", "-ffp-contract=off"],
            libraries=["mvec", "m"] if VECTOR else ["m"],
            optional=True,
        )
    ]
)
