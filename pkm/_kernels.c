/* The Python module that carries the compiled path's kernels (generated/kernels.c): pkm.compiled loads
   this library with ctypes and calls pkm_kernel_count, pkm_kernel_key, pkm_kernel_isa and pkm_kernel_run,
   which runs pkm_kernel_call (the dispatch of generated/kernels.c) over the chunks of a batch.

   pkm_kernel_run evaluates one kernel over several chunks of a batch at once: the calling thread takes
   chunks itself while threads kept from earlier calls take the others. A kept thread waits for the next
   call by polling for PKM_SPIN_NS before it sleeps, so that the calls of a solver, which follow each other
   within microseconds, do not wait for a sleeping thread to wake. A call made while another is running
   (from another Python thread) runs its chunks on its own thread. A forked child starts with no threads
   and makes its own. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <time.h>

void pkm_kernel_call(long i, long n, long group, const double *const *in, const long *stride, double *const *out);

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
  long kernel;
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
      pkm_kernel_call(job.kernel, job.n[k], job.group[k], job.in[k], job.stride, job.out[k]);
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

/* kernel i over chunks k = 0 .. chunks - 1 (at most 65535) of n[k] rows in groups of group[k], inputs
   in[k] with the row strides stride, outputs out[k]; on at most threads threads, the caller's included */
void pkm_kernel_run(long i, long chunks, long threads, const long *n, const long *group,
                    const double *const *const *in, const long *stride, double *const *const *out)
{
  if (chunks < 2 || threads < 2 || chunks > 0xffff || pthread_mutex_trylock(&job_lock) != 0) {
    for (long k = 0; k < chunks; ++k) pkm_kernel_call(i, n[k], group[k], in[k], stride, out[k]);
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
  job.kernel = i;
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

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_kernels", "pkm's compiled kernels", -1, NULL};

PyMODINIT_FUNC PyInit__kernels(void)
{
  pthread_atfork(NULL, NULL, forget_threads);
  return PyModule_Create(&module);
}
