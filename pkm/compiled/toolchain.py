"""The system C compiler as the compiled path uses it: which compiler, the host's instruction set, the
flags, and the commands that build a kernel's shared library and the runner extension.

The compiler is ``$CC`` or the first of cc, gcc and clang on PATH. Kernels are compiled for this host
only (``-march=native``, whose expansion by the compiler names the instruction set and enters every
kernel's key), with IEEE semantics: no -ffast-math and no contraction into fused multiply-adds;
-fno-math-errno and -fno-trapping-math change no value (sqrt compiles to its instruction, selects to
blends), nor does GCC's -fno-thread-jumps, which keeps selects that share a condition in straight-line code
(threaded into branches, they stop the loop over a block from vectorising). GCC's register allocator is
told to treat a kernel as one region with the priority algorithm: a kernel's loop body is one long block
of thousands of values, on which the default regional allocator takes most of the compile (a 13,000
instruction integrand: 8.7 s -> 3.0 s) for kernels that run no faster. On x86-64 the vectoriser is told to
prefer the widest vectors the host has (AVX-512's 8 lanes where it has them; GCC 12 prefers 4 on such
hosts): the vector variants of the wrapper that keeps cos from merging with sin are made for the widest
only, and a loop of 4 lanes calls none of them, so kernels with a cosine ran one pose at a time (about 7x
slower). On x86-64 Linux the vector
functions come from glibc's libmvec.
"""

from __future__ import annotations

import hashlib
import os
import platform
import re
import shutil
import subprocess
import sys
import sysconfig
from dataclasses import dataclass
from functools import cached_property, lru_cache
from pathlib import Path

COMMON_FLAGS = ("-march=native", "-fPIC", "-shared", "-fno-math-errno",
                "-fno-trapping-math", "-ffp-contract=off")
GCC_FLAGS = ("-fno-tree-sink", "-fno-thread-jumps", "-fira-region=one", "-fira-algorithm=priority")
X86_FLAGS = ("-mprefer-vector-width=512",)
RUNNER_FLAGS = ("-O2", "-fPIC", "-shared")
SMALL = 200  # instructions below which a row kernel is compiled with -O3 instead of -O2
TIMEOUT = 600  # seconds one compile may take before it counts as failed


class CompileError(RuntimeError):
    """The compiler rejected a translation unit; the message is its first line of diagnostics."""


@dataclass(frozen=True)
class Toolchain:
    """A C compiler found on this host: its path, its identity (first line of ``--version``), the
    instruction set ``-march=native`` selects here, and whether it is GCC."""

    compiler: str
    identity: str
    target: str
    gcc: bool

    @property
    def flags(self) -> tuple[str, ...]:
        return COMMON_FLAGS + (GCC_FLAGS if self.gcc else ()) + (X86_FLAGS if platform.machine() == "x86_64" else ())

    @property
    def libraries(self) -> tuple[str, ...]:
        vector = sys.platform == "linux" and platform.machine() == "x86_64"
        return ("-lmvec", "-lm") if vector else ("-lm",)

    @cached_property
    def fingerprint(self) -> str:
        """What a kernel's binary depends on besides its source: compiler, flags, instruction set."""
        text = "\n".join([self.identity, self.target, *self.flags, *self.libraries])
        return hashlib.sha256(text.encode()).hexdigest()

    @property
    def instruction_set(self) -> str:
        """The CPU name ``-march=native`` resolves to (e.g. ``rocketlake``), or the whole expansion."""
        match = re.search(r"-march=(\S+)|-target-cpu (\S+)", self.target)
        return next(g for g in match.groups() if g) if match else self.target

    @staticmethod
    def optimisation(instructions: int, summed: bool = False) -> str:
        """-O1 for a summing kernel (a region's integrand): its loop adds each row into the sums and does not
        vectorise, and it runs within 4% as fast as at -O3 for 40% less compile; a row kernel vectorises at -O2
        and -O3 alike and runs as fast at either for 30% less compile at -O2 (bench/compile_levels.py), and
        the smallest (below SMALL instructions: the batch methods' inverse kinematics) keep -O3."""
        if summed:
            return "-O1"
        return "-O3" if instructions < SMALL else "-O2"

    def kernel_flags(self, instructions: int, summed: bool = False) -> tuple[str, ...]:
        """The flags a kernel of ``instructions`` instructions (summing over its rows or not) is compiled with."""
        return (self.optimisation(instructions, summed), *self.flags)

    def compile_kernel(self, source: Path, library: Path, instructions: int, summed: bool = False) -> None:
        """Compile a kernel's translation unit of ``instructions`` instructions into a shared library."""
        self._run([self.compiler, *self.kernel_flags(instructions, summed), str(source), "-o", str(library),
                   *self.libraries])

    def compile_runner(self, source: Path, library: Path) -> None:
        """Compile the runner (pkm/compiled/_runner.c) into a Python extension module."""
        include = sysconfig.get_paths()["include"]
        if not (Path(include) / "Python.h").is_file():
            raise CompileError(f"Python's C headers are not installed (no {include}/Python.h)")
        self._run([self.compiler, *RUNNER_FLAGS, f"-I{include}", str(source), "-o", str(library), "-lpthread",
                   "-ldl"])

    def _run(self, command: list[str]) -> None:
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT, check=False)
        except subprocess.TimeoutExpired as exc:
            raise CompileError(f"{self.compiler} took more than {TIMEOUT} s") from exc
        except OSError as exc:
            raise CompileError(f"{self.compiler} could not run: {exc}") from exc
        if done.returncode != 0:
            lines = [line for line in done.stderr.splitlines() if line.strip()]
            first = next((line for line in lines if "error" in line), lines[0] if lines else "no diagnostics")
            raise CompileError(f"{Path(self.compiler).name} exited with {done.returncode}: {first.strip()}")


@lru_cache(maxsize=1)
def find() -> Toolchain | str:
    """This host's toolchain, or why there is none."""
    named = os.environ.get("CC")
    candidates = [named] if named else ["cc", "gcc", "clang"]
    compiler = next((path for path in map(shutil.which, candidates) if path), None)
    if compiler is None:
        return f"no C compiler on PATH (looked for {', '.join(candidates)}; set CC to name one)"
    try:
        version = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=60, check=False)
        expanded = subprocess.run([compiler, "-march=native", "-###", "-x", "c", "-c", os.devnull],
                                  capture_output=True, text=True, timeout=60, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"the C compiler {compiler} does not run: {exc}"
    identity = next(iter(version.stdout.splitlines()), "").strip()
    if version.returncode != 0 or not identity:
        return f"the C compiler {compiler} does not answer --version"
    if expanded.returncode != 0:
        return f"the C compiler {compiler} does not take -march=native"
    # the compiler proper's command line (cc1 of GCC, clang -cc1) carries the expansion
    line = next((line for line in expanded.stderr.splitlines() if "cc1" in line), "").replace('"', "")
    options = re.findall(r"(?<!\S)(-march=\S+|-m[\w.=-]+|-target-cpu \S+|-target-feature \S+)", line)
    gcc = "clang" not in identity.lower() and ("gcc" in identity.lower() or "free software" in version.stdout.lower())
    return Toolchain(compiler, identity, " ".join(options), gcc)
