/* The exact peaks of a linear oscillator between samples, for the response-spectrum loops of
 * _spectra.c (included by it alone): the turning points of the closed-form response inside one
 * step of piecewise-linear ground acceleration (refine_step: relative displacement and absolute
 * acceleration) and of the free vibration after the record (free_vibration_peak). See spectra.py
 * for the method. */

#ifndef UPLIFT_TURNING_POINTS_H
#define UPLIFT_TURNING_POINTS_H

#include <math.h>


#define PI 3.141592653589793

/* max(a, b) of Python: a unless b is larger */
static inline double larger(double a, double b)
{
    return b > a ? b : a;
}

/* |f| at the root of f' in (lo, hi), f'(lo) = d_lo and f'(hi) = d_hi of opposite sign, for
 * f = l0 + l1 t + exp(-sigma t)(pa cos wd t + qa sin wd t), f' = l1 + exp(-sigma t)(pd cos + qd sin),
 * f'' = exp(-sigma t)(pdd cos + qdd sin): safeguarded Newton from the secant estimate. The value at
 * a turning point is stationary, so t to 1e-9 of the bracket is far below rounding. */
static double root_value(double l0, double l1, double pa, double qa, double pd, double qd, double pdd, double qdd,
                         double sigma, double wd, double lo, double hi, double d_lo, double d_hi)
{
    double width = hi - lo;
    double t = lo + width * d_lo / (d_lo - d_hi);
    for (int iteration = 0; iteration < 40; iteration++) {
        double ex = exp(-sigma * t);
        double co = cos(wd * t);
        double si = sin(wd * t);
        double d = l1 + ex * (pd * co + qd * si);
        if (d == 0.0) {
            break;
        }
        if ((d > 0.0) == (d_lo > 0.0)) {
            lo = t;
        } else {
            hi = t;
        }
        double dd = ex * (pdd * co + qdd * si);
        double t_new = dd != 0.0 ? t - d / dd : 0.5 * (lo + hi);
        if (!(lo < t_new && t_new < hi)) {
            t_new = 0.5 * (lo + hi);
        }
        int converged = fabs(t_new - t) <= 1e-9 * width;
        t = t_new;
        if (converged || hi - lo <= 1e-9 * width) {
            break;
        }
    }
    double ex = exp(-sigma * t);
    return fabs(l0 + l1 * t + ex * (pa * cos(wd * t) + qa * sin(wd * t)));
}

/* Largest |f| at the turning points of f = l0 + l1 t + exp(-sigma t)(pa cos wd t + qa sin wd t)
 * inside (0, h), f'(0) = d0, f'(h) = d1 (0 if there is none).
 *
 * With wd h < pi, f'' (a damped sinusoid) has at most one root t_e in (0, h), so f' has one root
 * when d0, d1 differ in sign, and otherwise none or two, two exactly when f'(t_e) has the other sign. */
static double interior_peak(double l0, double l1, double pa, double qa, double sigma, double wd, double h, double d0,
                            double d1)
{
    double pd = qa * wd - sigma * pa;
    double qd = -pa * wd - sigma * qa;
    double pdd = qd * wd - sigma * pd;
    double qdd = -pd * wd - sigma * qd;
    if (d0 * d1 < 0.0) {
        return root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, 0.0, h, d0, d1);
    }
    double theta = atan2(-pdd, qdd); /* pdd cos + qdd sin = 0 */
    if (theta < 0.0) {
        theta += PI;
    }
    double t_e = theta / wd;
    if (!(0.0 < t_e && t_e < h)) {
        return 0.0;
    }
    double d_e = l1 + exp(-sigma * t_e) * (pd * cos(wd * t_e) + qd * sin(wd * t_e));
    if (d_e * d0 >= 0.0) {
        return 0.0;
    }
    double first = root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, 0.0, t_e, d0, d_e);
    double second = root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, t_e, h, d_e, d1);
    return larger(first, second);
}

/* max |f| for t >= 0 of f = exp(-sigma t)(pa cos wd t + qa sin wd t): the first turning point. */
static double free_vibration_peak(double pa, double qa, double sigma, double wd)
{
    double pd = qa * wd - sigma * pa;
    double qd = -pa * wd - sigma * qa;
    double theta = atan2(-pd, qd); /* pd cos + qd sin = 0 */
    while (theta < 0.0) {
        theta += PI;
    }
    while (theta >= PI) {
        theta -= PI;
    }
    double t = theta / wd;
    double value = fabs(exp(-sigma * t) * (pa * cos(wd * t) + qa * sin(wd * t)));
    return larger(fabs(pa), value);
}

/* Exact peaks of u (which & 1) and of the absolute acceleration (which & 2) inside one step,
 * from the closed form of the step (raises *peak_u, *peak_at). */
static void refine_step(double u0, double v0, double dat0, double dat1, double v1, double a0, double a1, double w,
                        double sigma, double wd, double h, double *peak_u, double *peak_at, int which)
{
    double w2 = w * w;
    double slope = (a1 - a0) / h;
    double c1 = -slope / w2;
    double c0 = -(a0 + 2.0 * sigma * c1) / w2;
    double amp_a = u0 - c0;
    double amp_b = (v0 - c1 + sigma * amp_a) / wd;
    if (which & 1) {
        *peak_u = larger(*peak_u, interior_peak(c0, c1, amp_a, amp_b, sigma, wd, h, v0, v1));
    }
    if (!(which & 2)) {
        return;
    }
    /* absolute acceleration a_g + u'' = a0 + slope t + exp(-sigma t)(pa cos + qa sin) */
    double pa = -w2 * amp_a - 2.0 * sigma * (amp_b * wd - sigma * amp_a);
    double qa = -w2 * amp_b + 2.0 * sigma * (amp_a * wd + sigma * amp_b);
    *peak_at = larger(*peak_at, interior_peak(a0, slope, pa, qa, sigma, wd, h, dat0, dat1));
}

#endif
