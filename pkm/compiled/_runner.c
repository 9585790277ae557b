/* pkm's kernel runner, compiled by pkm.compiled into its cache at first use: load(path) opens a kernel's
   shared library and returns the address of its pkm_kernel; run(address, threads, strides, chunks) runs
   it over the chunks of a batch, reading and writing the numpy arrays it is given through the buffer
   protocol.

   pkm_kernel_run evaluates one kernel over several chunks of a batch at once: the calling thread takes
   chunks itself while threads kept from earlier calls take the others. A kept thread waits for the next
   call by polling for PKM_SPIN_NS before it sleeps, so that the calls of a solver, which follow each other
   within microseconds, do not wait for a sleeping thread to wake. A call made while another is running
   (from another Python thread) runs its chunks on its own thread. A forked child starts with no threads
   and makes its own. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

typedef void (*pkm_kernel_fn)(long n, long group, const double *const *in, const long *stride, double *const *out);

#define PKM_MAX_THREADS 64
#define PKM_SPIN_NS 1000000L

static pthread_mutex_t job_lock = PTHREAD_MUTEX_INITIALIZER;  /* one call at a time uses the threads */
static pthread_mutex_t wake_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t wake = PTHREAD_COND_INITIALIZER;
static long started;                                           /* threads running, under job_lock */

/* the call's generation << 32 | its number of chunks << 16 | the next chunk to take: a chunk is taken
   by a compare-and-swap on the whole word, so a thread late from an earlier call takes nothing of it */
static atomic_ullong ticket;

static struct {
  pkm_kernel_fn kernel;
  const long *n, *group, *stride;
  const double *const *const *in;
  double *const *const *out;
  atomic_long left;
} job;

static long now_ns(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1000000000L + t.tv_nsec;
}

/* the chunks of call gen, taken one by one until none is left, by the caller and the kept threads alike */
static void take_chunks(unsigned long long gen)
{
  unsigned long long t = atomic_load(&ticket);
  while (t >> 32 == gen && (t & 0xffff) < (t >> 16 & 0xffff)) {
    if (atomic_compare_exchange_weak(&ticket, &t, t + 1)) {
      long k = (long)(t & 0xffff);
      job.kernel(job.n[k], job.group[k], job.in[k], job.stride, job.out[k]);
      atomic_fetch_sub(&job.left, 1);
      t = atomic_load(&ticket);
    }
  }
}

static void *kept_thread(void *arg)
{
  unsigned long long seen = (unsigned long long)(uintptr_t)arg;
  for (;;) {
    long until = now_ns() + PKM_SPIN_NS;
    while (atomic_load(&ticket) >> 32 == seen && now_ns() < until)
      ;
    if (atomic_load(&ticket) >> 32 == seen) {
      pthread_mutex_lock(&wake_lock);
      while (atomic_load(&ticket) >> 32 == seen) pthread_cond_wait(&wake, &wake_lock);
      pthread_mutex_unlock(&wake_lock);
    }
    seen = atomic_load(&ticket) >> 32;
    take_chunks(seen);
  }
  return NULL;
}

static void forget_threads(void)
{
  pthread_mutex_init(&job_lock, NULL);
  pthread_mutex_init(&wake_lock, NULL);
  pthread_cond_init(&wake, NULL);
  started = 0;
}

/* kernel over chunks k = 0 .. chunks - 1 (at most 65535) of n[k] rows in groups of group[k], inputs
   in[k] with the row strides stride, outputs out[k]; on at most threads threads, the caller's included */
static void pkm_kernel_run(pkm_kernel_fn kernel, long chunks, long threads, const long *n, const long *group,
                           const double *const *const *in, const long *stride, double *const *const *out)
{
  if (chunks < 2 || threads < 2 || chunks > 0xffff || pthread_mutex_trylock(&job_lock) != 0) {
    for (long k = 0; k < chunks; ++k) kernel(n[k], group[k], in[k], stride, out[k]);
    return;
  }
  long wanted = (threads < chunks ? threads : chunks) - 1;
  if (wanted > PKM_MAX_THREADS) wanted = PKM_MAX_THREADS;
  unsigned long long gen = (atomic_load(&ticket) >> 32) + 1;
  while (started < wanted) {
    pthread_t thread;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    int failed = pthread_create(&thread, &attr, kept_thread, (void *)(uintptr_t)(gen - 1));
    pthread_attr_destroy(&attr);
    if (failed) break;
    ++started;
  }
  job.kernel = kernel;
  job.n = n;
  job.group = group;
  job.in = in;
  job.stride = stride;
  job.out = out;
  atomic_store(&job.left, chunks);
  pthread_mutex_lock(&wake_lock);
  atomic_store(&ticket, gen << 32 | (unsigned long long)chunks << 16);
  pthread_cond_broadcast(&wake);
  pthread_mutex_unlock(&wake_lock);
  take_chunks(gen);
  while (atomic_load(&job.left) > 0)
    ;
  pthread_mutex_unlock(&job_lock);
}

/* the address of a C-contiguous array of doubles (writable for an output), its buffer held in view */
static double *buffer_of(PyObject *array, Py_buffer *view, int writable)
{
  if (PyObject_GetBuffer(array, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0)) != 0)
    return NULL;
  if (view->itemsize != sizeof(double) || view->format == NULL || strcmp(view->format, "d") != 0) {
    PyBuffer_Release(view);
    PyErr_SetString(PyExc_TypeError, "pkm's kernels take C-contiguous arrays of float64");
    return NULL;
  }
  return (double *)view->buf;
}

/* run(address, threads, strides, chunks): pkm_kernel_run of the kernel at address (from load) over
   chunks, a sequence of (inputs, outputs, n, group) with inputs and outputs lists of arrays, without
   the GIL */
static PyObject *run(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
  (void)self;
  if (nargs != 4) {
    PyErr_SetString(PyExc_TypeError, "run(address, threads, strides, chunks) takes 4 arguments");
    return NULL;
  }
  pkm_kernel_fn kernel = (pkm_kernel_fn)PyLong_AsVoidPtr(args[0]);
  long threads = PyLong_AsLong(args[1]);
  PyObject *strides = PySequence_Fast(args[2], "strides must be a sequence");
  PyObject *chunks = strides ? PySequence_Fast(args[3], "chunks must be a sequence") : NULL;
  if (chunks == NULL || PyErr_Occurred()) {
    Py_XDECREF(strides);
    Py_XDECREF(chunks);
    return NULL;
  }
  Py_ssize_t count = PySequence_Fast_GET_SIZE(chunks), n_in = PySequence_Fast_GET_SIZE(strides), n_out = -1;
  Py_ssize_t held = 0;
  long *numbers = PyMem_Malloc(sizeof(long) * (size_t)(n_in + 2 * count + 1));
  const double **ins = PyMem_Malloc(sizeof(double *) * (size_t)(count * n_in + 1));
  const double *const **in_rows = PyMem_Malloc(sizeof(double **) * (size_t)(count + 1));
  double *const **out_rows = PyMem_Malloc(sizeof(double **) * (size_t)(count + 1));
  double **outs = NULL;
  Py_buffer *views = NULL;
  PyObject *result = NULL;
  if (!numbers || !ins || !in_rows || !out_rows) {
    PyErr_NoMemory();
    goto done;
  }
  long *stride = numbers, *n = numbers + n_in, *group = numbers + n_in + count;
  for (Py_ssize_t j = 0; j < n_in; ++j) stride[j] = PyLong_AsLong(PySequence_Fast_ITEMS(strides)[j]);
  for (Py_ssize_t k = 0; k < count; ++k) {
    PyObject *chunk = PySequence_Fast_ITEMS(chunks)[k];
    if (!PyTuple_Check(chunk) || PyTuple_GET_SIZE(chunk) != 4) {
      PyErr_SetString(PyExc_TypeError, "a chunk is a tuple (inputs, outputs, n, group)");
      goto done;
    }
    PyObject *in_list = PyTuple_GET_ITEM(chunk, 0), *out_list = PyTuple_GET_ITEM(chunk, 1);
    if (!PyList_Check(in_list) || !PyList_Check(out_list) || PyList_GET_SIZE(in_list) != n_in ||
        (n_out >= 0 && PyList_GET_SIZE(out_list) != n_out)) {
      PyErr_SetString(PyExc_TypeError, "a chunk's inputs (one per stride) and outputs are lists of one length");
      goto done;
    }
    if (n_out < 0) {
      n_out = PyList_GET_SIZE(out_list);
      outs = PyMem_Malloc(sizeof(double *) * (size_t)(count * n_out + 1));
      views = PyMem_Malloc(sizeof(Py_buffer) * (size_t)(count * (n_in + n_out) + 1));
      if (!outs || !views) {
        PyErr_NoMemory();
        goto done;
      }
    }
    n[k] = PyLong_AsLong(PyTuple_GET_ITEM(chunk, 2));
    group[k] = PyLong_AsLong(PyTuple_GET_ITEM(chunk, 3));
    for (Py_ssize_t j = 0; j < n_in; ++j) {
      if (!(ins[k * n_in + j] = buffer_of(PyList_GET_ITEM(in_list, j), &views[held], 0))) goto done;
      ++held;
    }
    for (Py_ssize_t j = 0; j < n_out; ++j) {
      if (!(outs[k * n_out + j] = buffer_of(PyList_GET_ITEM(out_list, j), &views[held], 1))) goto done;
      ++held;
    }
    in_rows[k] = ins + k * n_in;
    out_rows[k] = outs + k * n_out;
  }
  if (PyErr_Occurred()) goto done;
  Py_BEGIN_ALLOW_THREADS
  pkm_kernel_run(kernel, (long)count, threads, n, group, in_rows, stride, out_rows);
  Py_END_ALLOW_THREADS
  result = Py_NewRef(Py_None);
done:
  for (Py_ssize_t v = 0; v < held; ++v) PyBuffer_Release(&views[v]);
  PyMem_Free(views);
  PyMem_Free(outs);
  PyMem_Free(out_rows);
  PyMem_Free(in_rows);
  PyMem_Free(ins);
  PyMem_Free(numbers);
  Py_DECREF(strides);
  Py_DECREF(chunks);
  return result;
}

/* load(path): the address of pkm_kernel in the shared library at path, opened for the process's lifetime */
static PyObject *load(PyObject *self, PyObject *arg)
{
  (void)self;
  PyObject *bytes = NULL;
  if (!PyUnicode_FSConverter(arg, &bytes)) return NULL;
  void *library = dlopen(PyBytes_AS_STRING(bytes), RTLD_NOW | RTLD_LOCAL);
  Py_DECREF(bytes);
  if (library == NULL) {
    PyErr_SetString(PyExc_OSError, dlerror());
    return NULL;
  }
  void *symbol = dlsym(library, "pkm_kernel");
  if (symbol == NULL) {
    PyErr_SetString(PyExc_OSError, "the library has no pkm_kernel");
    dlclose(library);
    return NULL;
  }
  return PyLong_FromVoidPtr(symbol);
}

static PyMethodDef methods[] = {
  {"run", (PyCFunction)(void (*)(void))run, METH_FASTCALL, "run(address, threads, strides, chunks)"},
  {"load", load, METH_O, "load(path): the address of a kernel library's pkm_kernel"},
  {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_runner", "pkm's kernel runner", -1, methods};

PyMODINIT_FUNC PyInit__runner(void)
{
  pthread_atfork(NULL, NULL, forget_threads);
  return PyModule_Create(&module);
}
