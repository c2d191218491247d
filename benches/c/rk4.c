/* The C baseline of benches/python/bench_core.py: eq. 1 by classic RK4, written plainly with
 * scalar locals, parameters read at run time, frames stored as the package stores them.
 * Build: cc -O3 -march=native -o rk4 rk4.c
 * Run:   ./rk4 STEPS FRAMES IX IY IZ DT [REPEATS]
 *        -> prints the median wall seconds per step of REPEATS runs (5 if not given), a
 *           check value, and the median CPU (process) seconds per step. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define RHS(u, v, w, q0, q1, q2, q3, D)                \
    D##0 = a * v * w;                                   \
    D##1 = b * u * w;                                   \
    D##2 = c * u * v;                                   \
    D##3 = -0.5 * (q1 * u + q2 * v + q3 * w);           \
    D##4 = 0.5 * (q0 * u + q2 * w - q3 * v);            \
    D##5 = 0.5 * (q0 * v + q3 * u - q1 * w);            \
    D##6 = 0.5 * (q0 * w + q1 * v - q2 * u);

static double now(clockid_t clock) {
    struct timespec ts;
    clock_gettime(clock, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *p, const void *q) {
    double x = *(const double *)p, y = *(const double *)q;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (argc != 7 && argc != 8) {
        fprintf(stderr, "usage: rk4 STEPS FRAMES IX IY IZ DT [REPEATS]\n");
        return 2;
    }
    int repeats = argc == 8 ? atoi(argv[7]) : 5;
    if (repeats < 1 || repeats > 99) {
        fprintf(stderr, "REPEATS must be 1 to 99\n");
        return 2;
    }
    long steps = atol(argv[1]), frames = atol(argv[2]);
    double ix = atof(argv[3]), iy = atof(argv[4]), iz = atof(argv[5]), h = atof(argv[6]);
    double a = (iy - iz) / ix, b = (iz - ix) / iy, c = (ix - iy) / iz;
    long sub = steps / (frames - 1);
    double *out = malloc(sizeof(double) * 7 * frames), times[99], cpu[99], check = 0.0;
    for (int rep = 0; rep < repeats; rep++) {
        double u = 0.01, v = 0.01, w = 1.0, q0 = 1.0, q1 = 0.0, q2 = 0.0, q3 = 0.0;
        double start = now(CLOCK_MONOTONIC), start_cpu = now(CLOCK_PROCESS_CPUTIME_ID);
        for (long f = 1; f < frames; f++) {
            for (long s = 0; s < sub; s++) {
                double k0, k1, k2, k3, k4, k5, k6, l0, l1, l2, l3, l4, l5, l6;
                double m0, m1, m2, m3, m4, m5, m6, n0, n1, n2, n3, n4, n5, n6;
                RHS(u, v, w, q0, q1, q2, q3, k)
                double u2 = u + 0.5 * h * k0, v2 = v + 0.5 * h * k1, w2 = w + 0.5 * h * k2;
                double p0 = q0 + 0.5 * h * k3, p1 = q1 + 0.5 * h * k4, p2 = q2 + 0.5 * h * k5,
                       p3 = q3 + 0.5 * h * k6;
                RHS(u2, v2, w2, p0, p1, p2, p3, l)
                u2 = u + 0.5 * h * l0; v2 = v + 0.5 * h * l1; w2 = w + 0.5 * h * l2;
                p0 = q0 + 0.5 * h * l3; p1 = q1 + 0.5 * h * l4; p2 = q2 + 0.5 * h * l5;
                p3 = q3 + 0.5 * h * l6;
                RHS(u2, v2, w2, p0, p1, p2, p3, m)
                u2 = u + h * m0; v2 = v + h * m1; w2 = w + h * m2;
                p0 = q0 + h * m3; p1 = q1 + h * m4; p2 = q2 + h * m5; p3 = q3 + h * m6;
                RHS(u2, v2, w2, p0, p1, p2, p3, n)
                u += h / 6 * (k0 + 2 * (l0 + m0) + n0);
                v += h / 6 * (k1 + 2 * (l1 + m1) + n1);
                w += h / 6 * (k2 + 2 * (l2 + m2) + n2);
                q0 += h / 6 * (k3 + 2 * (l3 + m3) + n3);
                q1 += h / 6 * (k4 + 2 * (l4 + m4) + n4);
                q2 += h / 6 * (k5 + 2 * (l5 + m5) + n5);
                q3 += h / 6 * (k6 + 2 * (l6 + m6) + n6);
            }
            double *o = out + 7 * f;
            o[0] = u; o[1] = v; o[2] = w; o[3] = q0; o[4] = q1; o[5] = q2; o[6] = q3;
        }
        times[rep] = (now(CLOCK_MONOTONIC) - start) / (double)(sub * (frames - 1));
        cpu[rep] = (now(CLOCK_PROCESS_CPUTIME_ID) - start_cpu) / (double)(sub * (frames - 1));
        check += out[7 * (frames - 1) + 3];
    }
    qsort(times, repeats, sizeof(double), cmp);
    qsort(cpu, repeats, sizeof(double), cmp);
    printf("%.6e %.17g %.6e\n", times[repeats / 2], check / repeats, cpu[repeats / 2]);
    free(out);
    return 0;
}
