/* The Python module that carries the compiled path's kernels (generated/kernels.c): pkm.compiled loads
   this library with ctypes and calls pkm_kernel_count, pkm_kernel_key and pkm_kernel_call. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_kernels", "pkm's compiled kernels", -1, NULL};

PyMODINIT_FUNC PyInit__kernels(void) { return PyModule_Create(&module); }
