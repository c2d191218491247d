/* The native reference of benches/python/bench_batch.py: eq. 1 by classic RK4 for N runs at
 * once, structure of arrays (one array per state component, runs innermost), written plainly
 * so that the compiler vectorises the loop over runs (gcc: -fopt-info-vec shows it does).
 * Coefficients differ per run. gcc contracts to FMA by default in GNU C: this is a speed
 * reference, not a bitwise one.
 * Build: cc -O3 -march=native -o rk4_soa rk4_soa.c
 * Run:   ./rk4_soa RUNS STEPS DT [REPEATS]
 *        -> prints the median wall seconds per run-step of REPEATS repeats (5 if not given),
 *           a check value, and the median CPU (process) seconds per run-step. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(clockid_t clock) {
    struct timespec ts;
    clock_gettime(clock, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *p, const void *q) {
    double x = *(const double *)p, y = *(const double *)q;
    return (x > y) - (x < y);
}

enum { C = 7 };

#define RHS(U, V, W, Q0, Q1, Q2, Q3, D)                                                  \
    D##0 = ai * V * W; D##1 = bi * U * W; D##2 = ci * U * V;                             \
    D##3 = -0.5 * (Q1 * U + Q2 * V + Q3 * W); D##4 = 0.5 * (Q0 * U + Q2 * W - Q3 * V);    \
    D##5 = 0.5 * (Q0 * V + Q3 * U - Q1 * W); D##6 = 0.5 * (Q0 * W + Q1 * V - Q2 * U);

/* One RK4 step of every run. */
static void step(long n, double h, const double *restrict a, const double *restrict b,
                 const double *restrict c, double *restrict u_, double *restrict v_,
                 double *restrict w_, double *restrict p0_, double *restrict p1_,
                 double *restrict p2_, double *restrict p3_) {
    for (long i = 0; i < n; i++) {
        double u = u_[i], v = v_[i], w = w_[i], q0 = p0_[i], q1 = p1_[i], q2 = p2_[i],
               q3 = p3_[i], ai = a[i], bi = b[i], ci = c[i];
        double k0, k1, k2, k3, k4, k5, k6, l0, l1, l2, l3, l4, l5, l6;
        double m0, m1, m2, m3, m4, m5, m6, o0, o1, o2, o3, o4, o5, o6;
        RHS(u, v, w, q0, q1, q2, q3, k)
        double f = 0.5 * h;
        RHS(u + f * k0, v + f * k1, w + f * k2, q0 + f * k3, q1 + f * k4, q2 + f * k5,
            q3 + f * k6, l)
        RHS(u + f * l0, v + f * l1, w + f * l2, q0 + f * l3, q1 + f * l4, q2 + f * l5,
            q3 + f * l6, m)
        RHS(u + h * m0, v + h * m1, w + h * m2, q0 + h * m3, q1 + h * m4, q2 + h * m5,
            q3 + h * m6, o)
        double g = h / 6;
        u_[i] = u + g * (k0 + 2 * (l0 + m0) + o0);
        v_[i] = v + g * (k1 + 2 * (l1 + m1) + o1);
        w_[i] = w + g * (k2 + 2 * (l2 + m2) + o2);
        p0_[i] = q0 + g * (k3 + 2 * (l3 + m3) + o3);
        p1_[i] = q1 + g * (k4 + 2 * (l4 + m4) + o4);
        p2_[i] = q2 + g * (k5 + 2 * (l5 + m5) + o5);
        p3_[i] = q3 + g * (k6 + 2 * (l6 + m6) + o6);
    }
}

int main(int argc, char **argv) {
    if (argc != 4 && argc != 5) {
        fprintf(stderr, "usage: rk4_soa RUNS STEPS DT [REPEATS]\n");
        return 2;
    }
    int repeats = argc == 5 ? atoi(argv[4]) : 5;
    if (repeats < 1 || repeats > 99) {
        fprintf(stderr, "REPEATS must be 1 to 99\n");
        return 2;
    }
    long n = atol(argv[1]), steps = atol(argv[2]);
    double h = atof(argv[3]), times[99], cpu[99], check = 0.0;
    double *x[C], *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)),
           *c = malloc(n * sizeof(double));
    for (int k = 0; k < C; k++) x[k] = malloc(n * sizeof(double));
    for (long i = 0; i < n; i++) { /* the paper's body and near ones */
        double ix = 52.0833, iy = 27.0833 + 1e-3 * (i % 7), iz = 41.6666;
        a[i] = (iy - iz) / ix; b[i] = (iz - ix) / iy; c[i] = (ix - iy) / iz;
    }
    for (int rep = 0; rep < repeats; rep++) {
        for (long i = 0; i < n; i++) {
            x[0][i] = 0.01 + 1e-5 * i; x[1][i] = 0.01; x[2][i] = 1.0;
            x[3][i] = 1.0; x[4][i] = 0.0; x[5][i] = 0.0; x[6][i] = 0.0;
        }
        double start = now(CLOCK_MONOTONIC), start_cpu = now(CLOCK_PROCESS_CPUTIME_ID);
        for (long s = 0; s < steps; s++)
            step(n, h, a, b, c, x[0], x[1], x[2], x[3], x[4], x[5], x[6]);
        times[rep] = (now(CLOCK_MONOTONIC) - start) / (double)(n * steps);
        cpu[rep] = (now(CLOCK_PROCESS_CPUTIME_ID) - start_cpu) / (double)(n * steps);
        check += x[3][n - 1];
    }
    qsort(times, repeats, sizeof(double), cmp);
    qsort(cpu, repeats, sizeof(double), cmp);
    printf("%.6e %.17g %.6e\n", times[repeats / 2], check / repeats, cpu[repeats / 2]);
    return 0;
}
