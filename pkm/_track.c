/* pkm's path tracker for the homotopy of pkm.homotopy, compiled by pkm.compiled into its kernel cache at first
   use and run by the kernel runner like an emitted kernel: a row is one path, tracked from s = 0 to s = 1 by the
   predictor-corrector of pkm.homotopy.track (its constants read from the settings row), every path with steps
   of its own.

   Inputs (rows of doubles): 0 the path's start point z (16: the real parts of e and g, then the imaginary
   parts); 1 its target instance (42: a (6 x 3), b (6 x 3), the squared radii (6), real); 2 the start instance
   (84: the same 42 entries, real parts, then imaginary parts), shared by the rows; 3 the patch c (16: real,
   then imaginary parts), shared; 4 the settings (8: MAX_STEPS, FIRST_STEP, the largest step, GROWTH,
   LEAST_STEP, CORRECTIONS, CONVERGED, END_STEPS), shared. Outputs: 0 the end point (16, as z), 1 whether
   the path arrived (1: 1 or 0). */
#include <math.h>

typedef struct { double re, im; } cx;

static inline cx c_add(cx a, cx b) { return (cx){a.re + b.re, a.im + b.im}; }
static inline cx c_sub(cx a, cx b) { return (cx){a.re - b.re, a.im - b.im}; }
static inline cx c_mul(cx a, cx b) { return (cx){a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
static inline cx c_scale(double t, cx a) { return (cx){t * a.re, t * a.im}; }
static inline double c_abs2(cx a) { return a.re * a.re + a.im * a.im; }

typedef struct { cx w, x, y, z; } quat;

/* Hamilton's product */
static inline quat q_mul(quat p, quat q)
{
  quat r;
  r.w = c_sub(c_sub(c_mul(p.w, q.w), c_mul(p.x, q.x)), c_add(c_mul(p.y, q.y), c_mul(p.z, q.z)));
  r.x = c_sub(c_add(c_add(c_mul(p.w, q.x), c_mul(p.x, q.w)), c_mul(p.y, q.z)), c_mul(p.z, q.y));
  r.y = c_add(c_add(c_sub(c_mul(p.w, q.y), c_mul(p.x, q.z)), c_mul(p.y, q.w)), c_mul(p.z, q.x));
  r.z = c_add(c_sub(c_add(c_mul(p.w, q.z), c_mul(p.x, q.y)), c_mul(p.y, q.x)), c_mul(p.z, q.w));
  return r;
}

static inline cx q_dot(quat p, quat q)
{
  return c_add(c_add(c_mul(p.w, q.w), c_mul(p.x, q.x)), c_add(c_mul(p.y, q.y), c_mul(p.z, q.z)));
}

static inline quat q_pure(const cx *v) { return (quat){{0, 0}, v[0], v[1], v[2]}; }
static inline quat q_of(const cx *v) { return (quat){v[0], v[1], v[2], v[3]}; }
static inline void q_put(cx *v, quat q) { v[0] = q.w; v[1] = q.x; v[2] = q.y; v[3] = q.z; }

typedef struct {
  cx start[42], change[42]; /* the instance along the path: start + s change (a, b, radii2) */
  cx c[8];                  /* the patch */
} path;

/* H (8), H_z (8 x 8, row major) and H_s (8) at z and s: pkm.homotopy._system */
static void system_at(const path *p, const cx *z, double s, cx *h, cx *hz, cx *hs)
{
  const quat e = q_of(z), g = q_of(z + 4);
  for (int i = 0; i < 6; ++i) {
    cx a[3], b[3], da[3], db[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = c_add(p->start[3 * i + k], c_scale(s, p->change[3 * i + k]));
      b[k] = c_add(p->start[18 + 3 * i + k], c_scale(s, p->change[18 + 3 * i + k]));
      da[k] = p->change[3 * i + k];
      db[k] = p->change[18 + 3 * i + k];
    }
    const cx r2 = c_add(p->start[36 + i], c_scale(s, p->change[36 + i]));
    const cx dr2 = p->change[36 + i];
    const quat pa = q_pure(a), pb = q_pure(b), qa = q_pure(da), qb = q_pure(db);
    const quat eb = q_mul(e, pb), ae = q_mul(pa, e);
    cx k = c_scale(-1, r2), dk = c_scale(-1, dr2);
    for (int m = 0; m < 3; ++m) {
      k = c_add(k, c_add(c_mul(a[m], a[m]), c_mul(b[m], b[m])));
      dk = c_add(dk, c_scale(2, c_add(c_mul(a[m], da[m]), c_mul(b[m], db[m]))));
    }
    const cx ee = q_dot(e, e);
    h[i] = c_sub(c_add(c_add(c_mul(k, ee), c_scale(4, q_dot(g, g))), c_scale(4, q_dot(eb, g))),
                 c_add(c_scale(2, q_dot(eb, ae)), c_scale(4, q_dot(g, ae))));
    const quat nb = {{0, 0}, c_scale(-1, b[0]), c_scale(-1, b[1]), c_scale(-1, b[2])};
    const quat gb = q_mul(g, nb), aeb = q_mul(ae, pb), ag = q_mul(pa, g);
    cx ebv[4], aev[4], gbv[4], aebv[4], agv[4], ev[4], gv[4];
    q_put(gbv, gb); q_put(aebv, aeb); q_put(agv, ag); q_put(ev, e); q_put(gv, g); q_put(ebv, eb); q_put(aev, ae);
    for (int m = 0; m < 4; ++m) {
      hz[8 * i + m] = c_add(c_scale(2, c_mul(k, ev[m])), c_scale(4, c_add(c_add(gbv[m], aebv[m]), agv[m])));
      hz[8 * i + 4 + m] = c_add(c_scale(8, gv[m]), c_scale(4, c_sub(ebv[m], aev[m])));
    }
    const quat edb = q_mul(e, qb), dae = q_mul(qa, e);
    hs[i] = c_sub(c_add(c_mul(dk, ee), c_scale(4, q_dot(edb, g))),
                  c_add(c_scale(2, c_add(q_dot(edb, ae), q_dot(eb, dae))), c_scale(4, q_dot(g, dae))));
  }
  h[6] = q_dot(e, g);
  cx one = {-1, 0};
  for (int m = 0; m < 8; ++m) one = c_add(one, c_mul(p->c[m], z[m]));
  h[7] = one;
  for (int m = 0; m < 4; ++m) {
    hz[48 + m] = z[4 + m];
    hz[48 + 4 + m] = z[m];
  }
  for (int m = 0; m < 8; ++m) hz[56 + m] = p->c[m];
  hs[6] = hs[7] = (cx){0, 0};
}

/* x = A^-1 y (8 x 8, row major) by Gaussian elimination with partial pivoting; 0 where A is singular */
static int solve8(cx *a, cx *y)
{
  for (int col = 0; col < 8; ++col) {
    int pivot = col;
    double best = c_abs2(a[8 * col + col]);
    for (int r = col + 1; r < 8; ++r) {
      const double size = c_abs2(a[8 * r + col]);
      if (size > best) best = size, pivot = r;
    }
    if (!(best > 0) || !isfinite(best)) return 0;
    if (pivot != col) {
      for (int m = 0; m < 8; ++m) {
        const cx t = a[8 * col + m];
        a[8 * col + m] = a[8 * pivot + m];
        a[8 * pivot + m] = t;
      }
      const cx t = y[col];
      y[col] = y[pivot];
      y[pivot] = t;
    }
    const cx d = a[8 * col + col];
    const cx inverse = {d.re / best, -d.im / best};
    for (int r = col + 1; r < 8; ++r) {
      const cx f = c_mul(a[8 * r + col], inverse);
      for (int m = col + 1; m < 8; ++m) a[8 * r + m] = c_sub(a[8 * r + m], c_mul(f, a[8 * col + m]));
      y[r] = c_sub(y[r], c_mul(f, y[col]));
    }
  }
  for (int r = 7; r >= 0; --r) {
    cx t = y[r];
    for (int m = r + 1; m < 8; ++m) t = c_sub(t, c_mul(a[8 * r + m], y[m]));
    const cx d = a[8 * r + r];
    const double size = c_abs2(d);
    y[r] = c_mul(t, (cx){d.re / size, -d.im / size});
  }
  return 1;
}

static int finite8(const cx *z)
{
  for (int m = 0; m < 8; ++m)
    if (!isfinite(z[m].re) || !isfinite(z[m].im)) return 0;
  return 1;
}

/* dz/ds = -H_z^-1 H_s; 0 where H_z is singular */
static int velocity(const path *p, const cx *z, double s, cx *v)
{
  cx h[8], hz[64];
  system_at(p, z, s, h, hz, v);
  for (int m = 0; m < 8; ++m) v[m] = c_scale(-1, v[m]);
  return solve8(hz, v);
}

/* up to `steps` Newton corrections at fixed s, stopping after one below `converged` (relative to |z|);
   whether the last one was */
static int corrected(const path *p, cx *z, double s, int steps, double converged)
{
  for (int k = 0; k < steps; ++k) {
    cx h[8], hz[64], hs[8];
    system_at(p, z, s, h, hz, hs);
    if (!solve8(hz, h)) return 0;
    double step = 0, size = 0;
    for (int m = 0; m < 8; ++m) {
      z[m] = c_sub(z[m], h[m]);
      step += c_abs2(h[m]);
      size += c_abs2(z[m]);
    }
    if (!finite8(z)) return 0;
    if (sqrt(step) <= converged * fmax(sqrt(size), 1.0)) return 1;
  }
  return 0;
}

static double track(const path *p, cx *z, const double *settings)
{
  const long max_steps = (long)settings[0];
  const double largest = settings[2], growth = settings[3], least = settings[4], converged = settings[6];
  const int corrections = (int)settings[5], end_steps = (int)settings[7];
  double s = 0, step = fmin(settings[1], largest);
  long taken = 0;
  for (; taken < max_steps && s < 1 && step >= least; ++taken) {
    const double h = fmin(step, 1 - s);
    cx k1[8], k2[8], k3[8], k4[8], w[8], guess[8];
    int ok = velocity(p, z, s, k1);
    for (int m = 0; m < 8; ++m) w[m] = c_add(z[m], c_scale(h / 2, k1[m]));
    ok = ok && velocity(p, w, s + h / 2, k2);
    for (int m = 0; m < 8; ++m) w[m] = c_add(z[m], c_scale(h / 2, k2[m]));
    ok = ok && velocity(p, w, s + h / 2, k3);
    for (int m = 0; m < 8; ++m) w[m] = c_add(z[m], c_scale(h, k3[m]));
    ok = ok && velocity(p, w, s + h, k4);
    for (int m = 0; m < 8; ++m)
      guess[m] = c_add(z[m], c_scale(h / 6, c_add(c_add(k1[m], c_scale(2, k2[m])), c_add(c_scale(2, k3[m]), k4[m]))));
    if (!ok || !finite8(guess))
      for (int m = 0; m < 8; ++m) guess[m] = z[m];
    if (corrected(p, guess, s + h, corrections, converged)) {
      for (int m = 0; m < 8; ++m) z[m] = guess[m];
      s += h;
      step = fmin(growth * step, largest);
    } else {
      step /= 2;
    }
  }
  const int closed = corrected(p, z, 1.0, end_steps, converged);
  return closed && s >= 1 && finite8(z);
}

void pkm_kernel(long n, long group, const double *const *in, const long *stride, double *const *out)
{
  (void)group;
  path p;
  const double *start = in[2], *patch = in[3], *settings = in[4];
  for (int m = 0; m < 8; ++m) p.c[m] = (cx){patch[m], patch[8 + m]};
  for (long r = 0; r < n; ++r) {
    const double *z0 = in[0] + r * stride[0], *target = in[1] + r * stride[1];
    cx z[8];
    for (int m = 0; m < 42; ++m) {
      p.start[m] = (cx){start[m], start[42 + m]};
      p.change[m] = (cx){target[m] - start[m], -start[42 + m]};
    }
    for (int m = 0; m < 8; ++m) z[m] = (cx){z0[m], z0[8 + m]};
    const double arrived = track(&p, z, settings);
    for (int m = 0; m < 8; ++m) {
      out[0][r * 16 + m] = z[m].re;
      out[0][r * 16 + 8 + m] = z[m].im;
    }
    out[1][r] = arrived;
  }
}
