/* Compiled loops of the response spectra (C, built at install; spectra_kernels.py is their Python
 * face, spectra_numpy.py their numpy twin): the exact Nigam-Jennings step, the bound that finds the
 * steps where a peak can lie between samples, and the exact turning points there (turning_points.h;
 * see spectra.py for the method). Each loop runs over many oscillators at once. */

#include "buffers.h"
#include "turning_points.h"
#include <math.h>

/* rows of the per-oscillator constant table used by chunk_peaks (rows 0-7: step_coefficients) */
enum { A_UU, A_VU, A_UV, A_VV, B_U0, B_V0, B_U1, B_V1, W2, INV_W2, TWO_SIGMA, INV_WD, AT_GAIN2, HERMITE_ERROR2,
       CF_ROWS };
/* per-oscillator state of chunk_peaks besides the table: u, v, u_old, v_old, peak_u, peak_at, flag */
#define STATE_ROWS 7

/* The inner loop (advance) is HOT_LOOP (buffers.h): wider SIMD lanes, three-operand instructions and
 * (AVX-512) twice the registers make the spectrum about 1.8x faster than with the baseline SSE2. */

/* Exact state after one step h of piecewise-linear ground acceleration a0 -> a1. */
static inline void closed_form_step(double u0, double v0, double a0, double a1, double w, double sigma, double wd,
                                    double h, double e, double c, double s, double *u1, double *v1)
{
    double slope = (a1 - a0) / h;
    double c1 = -slope / (w * w);
    double c0 = -a0 / (w * w) - 2.0 * sigma * c1 / (w * w);
    double amp_a = u0 - c0;
    double amp_b = (v0 - c1 + sigma * amp_a) / wd;
    *u1 = c0 + c1 * h + e * (amp_a * c + amp_b * s);
    *v1 = c1 + e * ((amp_b * wd - sigma * amp_a) * c - (amp_a * wd + sigma * amp_b) * s);
}

/* Matrices of the recurrence [u1, v1] = A [u0, v0] + B [a0, a1] (Nigam-Jennings), into
 * coefficients[8] = A_uu, A_vu, A_uv, A_vv, B_u0, B_v0, B_u1, B_v1. */
static void step_coefficients(double w, double xi, double h, double *coefficients)
{
    static const double unit[4][4] = {{1.0, 0.0, 0.0, 0.0}, {0.0, 1.0, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0},
                                      {0.0, 0.0, 0.0, 1.0}};
    double sigma = xi * w;
    double wd = w * sqrt(1.0 - xi * xi);
    double e = exp(-sigma * h);
    double c = cos(wd * h);
    double s = sin(wd * h);
    for (int k = 0; k < 4; k++) {
        closed_form_step(unit[k][0], unit[k][1], unit[k][2], unit[k][3], w, sigma, wd, h, e, c, s,
                         &coefficients[2 * k], &coefficients[2 * k + 1]);
    }
}


/* One sub-step a0 -> a1 of the m oscillators of chunk_peaks (constant table cf[row * m + k]):
 * advance u, v (keeping u_old, v_old), keep the sampled peaks and set flag[k] (1: refine u, 2: a_t,
 * 3: both). No branch and no reduction (a count of the flags would need reassociation to
 * vectorise: chunk_peaks scans them instead), so the loop runs in SIMD lanes; the restrict
 * parameters tell the compiler that the rows do not overlap. */
HOT_LOOP static void advance(int64_t m, const double *restrict cf, double *restrict u, double *restrict v,
                    double *restrict u_old, double *restrict v_old, double *restrict peak_u,
                    double *restrict peak_at, double *restrict flag, double a0, double a1, double inv_h,
                    double h_third)
{
    double slope_h = a1 - a0; /* ground-acceleration slope times h */
    double slope = slope_h * inv_h;
    for (int64_t k = 0; k < m; k++) {
        double u0 = u[k];
        double v0 = v[k];
        double u1 = cf[A_UU * m + k] * u0 + cf[A_UV * m + k] * v0 + cf[B_U0 * m + k] * a0 + cf[B_U1 * m + k] * a1;
        double v1 = cf[A_VU * m + k] * u0 + cf[A_VV * m + k] * v0 + cf[B_V0 * m + k] * a0 + cf[B_V1 * m + k] * a1;
        double w2 = cf[W2 * m + k];
        double two_sigma = cf[TWO_SIGMA * m + k];
        double at0 = -w2 * u0 - two_sigma * v0; /* absolute acceleration */
        double at1 = -w2 * u1 - two_sigma * v1;
        double dat0 = -w2 * v0 - two_sigma * (at0 - a0); /* its slope */
        double dat1 = -w2 * v1 - two_sigma * (at1 - a1);
        double p_u = larger(peak_u[k], fabs(u1));
        double p_at = larger(peak_at[k], fabs(at1));
        /* closed form over the step: u = c0 + c1 t + hom(t), |hom| <= sqrt(A^2 + B^2) */
        double c1h = -slope_h * cf[INV_W2 * m + k];
        double c0 = -(a0 + two_sigma * c1h * inv_h) * cf[INV_W2 * m + k];
        double amp_a = u0 - c0;
        double amp_b = (v0 - c1h * inv_h + 0.5 * two_sigma * amp_a) * cf[INV_WD * m + k];
        double r2 = amp_a * amp_a + amp_b * amp_b;
        /* max |f| over the step <= max |Bezier control points of the cubic Hermite interpolant|
         * + its error bound (w h)^4 / 384 * amplitude; the end points are in the peaks already */
        double room_u = p_u - larger(fabs(u0 + h_third * v0), fabs(u1 - h_third * v1));
        double room_at = p_at - larger(fabs(at0 + h_third * dat0), fabs(at1 - h_third * dat1));
        double error2 = cf[HERMITE_ERROR2 * m + k] * r2;
        /* an interior turning point needs a sign change of f' (one root) or of f'' (two roots) */
        double rel0 = at0 - a0; /* u'' */
        double rel1 = at1 - a1;
        double jerk0 = -w2 * rel0 + two_sigma * (slope + two_sigma * rel0 + w2 * v0); /* a_t'' */
        double jerk1 = -w2 * rel1 + two_sigma * (slope + two_sigma * rel1 + w2 * v1);
        int turn_u = (v0 * v1 < 0.0) | (rel0 * rel1 < 0.0);
        int turn_at = (dat0 * dat1 < 0.0) | (jerk0 * jerk1 < 0.0);
        int f_u = turn_u & ((room_u <= 0.0) | (error2 > room_u * room_u));
        int f_at = turn_at & ((room_at <= 0.0) | (error2 * cf[AT_GAIN2 * m + k] > room_at * room_at));
        flag[k] = (f_u ? 1.0 : 0.0) + (f_at ? 2.0 : 0.0); /* which quantities to refine */
        u_old[k] = u0;
        v_old[k] = v0;
        u[k] = u1;
        v[k] = v1;
        peak_u[k] = p_u;
        peak_at[k] = p_at;
    }
}

/* Peak |u| [m] and |absolute acceleration| [m/s^2] of the m oscillators (omegas, xis) sharing one
 * sub-step count nsub, into out_u, out_at; work: (CF_ROWS + STATE_ROWS) m doubles.
 *
 * Time loop outside, oscillators inside. The inner loop (advance) has no branch, so it runs in SIMD
 * lanes: it advances every oscillator, keeps the sampled peaks and flags the steps where a
 * turning point is possible and a rigorous bound of max |f| reaches the running peak (see
 * spectra.py); only flagged steps are refined (refine_step). */
static void chunk_peaks(const double *acc, int64_t n, double dt, const double *omegas, const double *xis, int64_t m,
                        int64_t nsub, int free_vibration, double *out_u, double *out_at, double *work)
{
    double h = dt / (double)nsub;
    double *cf = work; /* cf[row * m + k] */
    double *u = work + CF_ROWS * m;
    double *v = u + m;
    double *u_old = v + m;
    double *v_old = u_old + m;
    double *peak_u = v_old + m;
    double *peak_at = peak_u + m;
    double *flag = peak_at + m;
    for (int64_t k = 0; k < m; k++) {
        double w = omegas[k];
        double sigma = xis[k] * w;
        double coefficients[8];
        step_coefficients(w, xis[k], h, coefficients);
        for (int row = 0; row < 8; row++) {
            cf[row * m + k] = coefficients[row];
        }
        cf[W2 * m + k] = w * w;
        cf[INV_W2 * m + k] = 1.0 / (w * w);
        cf[TWO_SIGMA * m + k] = 2.0 * sigma;
        cf[INV_WD * m + k] = 1.0 / (w * sqrt(1.0 - xis[k] * xis[k]));
        double gain = w * (w + 2.0 * sigma);
        cf[AT_GAIN2 * m + k] = gain * gain; /* amplitude of a_t's oscillation <= this^0.5 * u's */
        double wh = w * h, wh2 = wh * wh;
        double error = wh2 * wh2 / 384.0;
        cf[HERMITE_ERROR2 * m + k] = error * error; /* cubic Hermite error / amplitude, squared */
        u[k] = v[k] = u_old[k] = v_old[k] = peak_u[k] = peak_at[k] = 0.0;
        flag[k] = 0.0;
    }
    int64_t last = n - 1 + ((free_vibration && acc[n - 1] != 0.0) ? 1 : 0);
    double inv_h = 1.0 / h;
    double h_third = h / 3.0;
    for (int64_t i = 0; i < last; i++) {
        double g0 = acc[i];
        double g1 = i + 1 < n ? acc[i + 1] : 0.0;
        for (int64_t j = 0; j < nsub; j++) {
            double a0 = g0 + (g1 - g0) * ((double)j / (double)nsub);
            double a1 = g0 + (g1 - g0) * ((double)(j + 1) / (double)nsub);
            advance(m, cf, u, v, u_old, v_old, peak_u, peak_at, flag, a0, a1, inv_h, h_third);
            for (int64_t k = 0; k < m; k++) {
                if (flag[k] > 0.0) {
                    double sigma = 0.5 * cf[TWO_SIGMA * m + k];
                    double w2 = cf[W2 * m + k];
                    double at0 = -w2 * u_old[k] - 2.0 * sigma * v_old[k];
                    double at1 = -w2 * u[k] - 2.0 * sigma * v[k];
                    refine_step(u_old[k], v_old[k], -w2 * v_old[k] - 2.0 * sigma * (at0 - a0),
                                -w2 * v[k] - 2.0 * sigma * (at1 - a1), v[k], a0, a1, omegas[k], sigma,
                                1.0 / cf[INV_WD * m + k], h, &peak_u[k], &peak_at[k], (int)flag[k]);
                }
            }
        }
    }
    for (int64_t k = 0; k < m; k++) {
        if (free_vibration) {
            double sigma = 0.5 * cf[TWO_SIGMA * m + k];
            double wd = 1.0 / cf[INV_WD * m + k];
            double w2 = cf[W2 * m + k];
            double amp_a = u[k];
            double amp_b = (v[k] + sigma * u[k]) / wd;
            peak_u[k] = larger(peak_u[k], free_vibration_peak(amp_a, amp_b, sigma, wd));
            double pa = -w2 * amp_a - 2.0 * sigma * (amp_b * wd - sigma * amp_a);
            double qa = -w2 * amp_b + 2.0 * sigma * (amp_a * wd + sigma * amp_b);
            peak_at[k] = larger(peak_at[k], free_vibration_peak(pa, qa, sigma, wd));
        }
        out_u[k] = peak_u[k];
        out_at[k] = peak_at[k];
    }
}

/* spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, out_at): run the
 * chunks [chunk_starts[c], chunk_starts[c+1]) (equal sub-step count inside a chunk) one after the
 * other in this thread (the sweeps parallelise over processes). */
static PyObject *py_spectrum_kernel(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 9, "spectrum_kernel")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 1, 0, "acc"}, {2, 'd', 1, 0, "omegas"}, {3, 'd', 1, 0, "xis"},
        {4, 'q', 1, 0, "nsubs"}, {5, 'q', 1, 0, "chunk_starts"}, {7, 'd', 1, 1, "out_u"}, {8, 'd', 1, 1, "out_at"}};
    Py_buffer *b[7];
    int taken = take_views(&v, args, arrays, 7, b);
    Py_buffer *acc = b[0], *omegas = b[1], *xis = b[2], *nsubs = b[3], *chunk_starts = b[4], *out_u = b[5],
              *out_at = b[6];
    if (!taken) {
        goto done;
    }
    double dt = PyFloat_AsDouble(args[1]);
    int free_vibration = PyObject_IsTrue(args[6]);
    if (PyErr_Occurred()) {
        goto done;
    }
    const int64_t n = acc->shape[0], m = omegas->shape[0], n_chunks = chunk_starts->shape[0] - 1;
    const int64_t *starts = INT64S(chunk_starts), *counts = INT64S(nsubs);
    if (n < 1 || xis->shape[0] != m || nsubs->shape[0] != m || out_u->shape[0] != m || out_at->shape[0] != m) {
        PyErr_SetString(PyExc_ValueError, "spectrum_kernel: inconsistent array shapes");
        goto done;
    }
    int64_t longest = 0;
    for (int64_t c = 0; c < n_chunks; c++) {
        int64_t lo = starts[c], hi = starts[c + 1];
        if (lo < 0 || hi < lo || hi > m || (hi > lo && counts[lo] < 1)) {
            PyErr_SetString(PyExc_ValueError,
                            "spectrum_kernel: chunk_starts must rise within [0, len(omegas)], nsubs be >= 1");
            goto done;
        }
        longest = hi - lo > longest ? hi - lo : longest;
    }
    double *work = PyMem_Malloc((size_t)((CF_ROWS + STATE_ROWS) * longest + 1) * sizeof(double));
    if (!work) {
        PyErr_NoMemory();
        goto done;
    }
    const double *a = DOUBLES(acc), *w = DOUBLES(omegas), *x = DOUBLES(xis);
    double *pu = DOUBLES(out_u), *pat = DOUBLES(out_at);
    Py_BEGIN_ALLOW_THREADS
    for (int64_t c = 0; c < n_chunks; c++) {
        int64_t lo = starts[c], hi = starts[c + 1];
        if (hi > lo) {
            chunk_peaks(a, n, dt, w + lo, x + lo, hi - lo, counts[lo], free_vibration, pu + lo, pat + lo, work);
        }
    }
    Py_END_ALLOW_THREADS
    PyMem_Free(work);
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}

/* history_kernel(acc, dt, w, xi, u_out, v_out): relative displacement and velocity at the samples,
 * zero initial conditions (the recurrence of step_coefficients with h = dt). */
static PyObject *py_history_kernel(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 6, "history_kernel")) {
        return NULL;
    }
    Views views = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 1, 0, "acc"}, {4, 'd', 1, 1, "u_out"}, {5, 'd', 1, 1, "v_out"}};
    Py_buffer *b[3];
    int taken = take_views(&views, args, arrays, 3, b);
    Py_buffer *acc = b[0], *u_out = b[1], *v_out = b[2];
    if (!taken) {
        goto done;
    }
    double dt = PyFloat_AsDouble(args[1]);
    double w = PyFloat_AsDouble(args[2]);
    double xi = PyFloat_AsDouble(args[3]);
    if (PyErr_Occurred()) {
        goto done;
    }
    const int64_t n = acc->shape[0];
    if (n < 1 || u_out->shape[0] != n || v_out->shape[0] != n) {
        PyErr_SetString(PyExc_ValueError, "history_kernel: inconsistent array shapes");
        goto done;
    }
    const double *a = DOUBLES(acc);
    double *uo = DOUBLES(u_out), *vo = DOUBLES(v_out);
    Py_BEGIN_ALLOW_THREADS
    double k[8];
    step_coefficients(w, xi, dt, k);
    double u = 0.0;
    double v = 0.0;
    uo[0] = 0.0;
    vo[0] = 0.0;
    for (int64_t i = 0; i < n - 1; i++) {
        double a0 = a[i];
        double a1 = a[i + 1];
        double u1 = k[0] * u + k[2] * v + k[4] * a0 + k[6] * a1;
        double v1 = k[1] * u + k[3] * v + k[5] * a0 + k[7] * a1;
        u = u1;
        v = v1;
        uo[i + 1] = u;
        vo[i + 1] = v;
    }
    Py_END_ALLOW_THREADS
    result = Py_NewRef(Py_None);
done:
    release_views(&views);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(spectrum_kernel, "spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, "
                              "out_at): peaks of the oscillators, chunk by chunk (spectra_kernels.py)."),
    FASTCALL(history_kernel, "history_kernel(acc, dt, w, xi, u_out, v_out): SDOF history at the samples "
                             "(spectra_kernels.py)."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_spectra, "Compiled loops of the response spectra.")
