"""The compiled path's kernels (generated/kernels.c, the table and the dispatch, and the translation units
of each part of a mechanism's kernels for each instruction set, generated/*_generic.c and *_avx2.c)
built into pkm._kernels at install:
optional, so that pkm installs without a C compiler and evaluates with CasADi's interpreter.

IEEE semantics are kept: no -ffast-math and no contraction into fused multiply-adds; -fno-math-errno and
-fno-trapping-math change no value (sqrt compiles to its instruction, selects to blends), nor does
-fno-thread-jumps, which keeps selects that share a condition in straight-line code (threaded into
branches, they stop the loop over a block from vectorising). Every kernel is compiled for the generic
x86-64 and for AVX2, and kernels.c picks one when called, instead of -march=native; the vector functions
come from glibc's libmvec. The translation units compile in parallel, one per core.
"""

import os
import platform
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

VECTOR = sys.platform == "linux" and platform.machine() == "x86_64"
UNITS = sorted(p.as_posix() for isa in ("generic", "avx2") for p in Path("generated").glob(f"*_{isa}.c"))


class ParallelBuild(build_ext):
    """build_ext compiling an extension's sources concurrently."""

    def build_extension(self, ext):
        compile_all = self.compiler.compile

        def compile_each(sources, **kwargs):
            with ThreadPoolExecutor(os.cpu_count() or 1) as pool:
                return [obj for objs in pool.map(lambda s: compile_all([s], **kwargs), sources) for obj in objs]

        self.compiler.compile = compile_each
        try:
            super().build_extension(ext)
        finally:
            self.compiler.compile = compile_all


setup(
    cmdclass={"build_ext": ParallelBuild},
    ext_modules=[
        Extension(
            "pkm._kernels",
            sources=["pkm/_kernels.c", "generated/kernels.c", *UNITS],
            depends=["generated/kernels_prelude.h", "generated/kernels_helpers.h"],
            extra_compile_args=["-O3", "-fopenmp-simd", "-fno-math-errno", "-fno-trapping-math", "-fno-tree-sink",
                                "-fno-thread-jumps", "-ffp-contract=off"],
            libraries=["mvec", "m"] if VECTOR else ["m"],
            optional=True,
        )
    ],
)
